#include "bench/report/export.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "bench/io/statistics.h"

namespace omnishadow::bench {

using nlohmann::json;

namespace {

struct Measure {
  std::string name, unit;
  double value = 0.0, lower = 0.0, upper = 0.0;
  bool has_range = false;
};

// A case's measures, named as Bencher slugs (at most 64 characters, lower case and dashes).
std::vector<Measure> measures_of(const RunData& run, const std::string& id, const json& c) {
  std::vector<Measure> out;
  auto series = [&](const std::map<std::string, std::vector<double>>& by_case, const char* name) {
    auto it = by_case.find(id);
    if (it == by_case.end() || it->second.empty()) return;
    const auto [lo, hi] = std::minmax_element(it->second.begin(), it->second.end());
    out.push_back({name, "ms", median(it->second), *lo, *hi, true});
  };
  series(run.samples, "frame-wall-ms");
  series(run.cpu_samples, "frame-cpu-ms");
  series(run.gpu_samples, "frame-gpu-ms");
  if (c.contains("accuracy") && c["accuracy"].is_object() &&
      c["accuracy"].contains("misclassified_percent") && c["accuracy"]["misclassified_percent"].is_number())
    out.push_back(
        {"misclassified-percent", "%", c["accuracy"]["misclassified_percent"].get<double>(), 0, 0, false});
  out.push_back({"status-ok", "1 = ok", c.value("status", "") == "ok" ? 1.0 : 0.0, 0, 0, false});
  return out;
}

}  // namespace

ExportFormat parse_export_format(const std::string& name) {
  if (name == "bencher") return ExportFormat::bencher;
  if (name == "github-action-benchmark") return ExportFormat::github_action_benchmark;
  throw std::invalid_argument("--format: '" + name + "' is not bencher or github-action-benchmark");
}

json export_run(const RunData& run, ExportFormat format) {
  json out = format == ExportFormat::bencher ? json::object() : json::array();
  for (const auto& [id, c] : run.cases) {
    for (const Measure& m : measures_of(run, id, *c)) {
      if (format == ExportFormat::bencher) {
        json metric = {{"value", m.value}};
        if (m.has_range) metric["lower_value"] = m.lower, metric["upper_value"] = m.upper;
        out[id][m.name] = metric;
        continue;
      }
      json entry = {{"name", id + " " + m.name}, {"unit", m.unit}, {"value", m.value}};
      if (m.has_range) {
        char range[64];
        std::snprintf(range, sizeof range, "%.4g..%.4g", m.lower, m.upper);
        entry["range"] = range;
      }
      entry["extra"] = "status " + c->value("status", "") + "; " + run.file;
      out.push_back(entry);
    }
  }
  return out;
}

}  // namespace omnishadow::bench
