#include "bench/summary_table.h"

#include <cstdio>
#include <map>
#include <sstream>

#include "bench/timing_stats.h"

namespace omnishadow::bench {
namespace {

double median_of(const std::vector<FrameTiming>& frames, double (*get)(const FrameTiming&)) {
  std::vector<double> v;
  for (const FrameTiming& f : frames) v.push_back(get(f));
  return summarize(v).median;
}

double shadow_wall(const FrameTiming& f) { return f.shadow.cpu_wall_ms; }
double lighting_wall(const FrameTiming& f) { return f.lighting.cpu_wall_ms; }

std::string cell(double value, double base) {
  char buf[48];
  if (value <= 0 || base <= 0) return "-";
  std::snprintf(buf, sizeof buf, "%.2f ms (%.2fx)", value, value / base);
  return buf;
}

// One row per group of cases that differ only in `axis`; one column per value of the axis, each the median
// of `metric` over the timed frames and its ratio to the `base` value's.
template <typename E>
void ratio_table(std::ostringstream& md, const std::vector<CaseResult>& results, const std::string& title,
                 E CaseConfig::*axis, E base, double (*metric)(const FrameTiming&)) {
  const std::vector<E> values = all_values<E>();
  md << "\n## " << title << "\n\n| case group |";
  for (E v : values) md << " " << to_string(v) << " |";
  md << "\n|---|";
  for (size_t i = 0; i < values.size(); ++i) md << "---|";
  md << "\n";
  std::map<std::string, std::map<E, double>> by_group;
  std::vector<std::string> group_order;
  const std::string base_part = "/" + std::string(to_string(base));
  for (const CaseResult& r : results) {
    if (r.frames.empty()) continue;
    CaseConfig g = r.config;
    g.*axis = base;
    std::string key = g.id();
    key.erase(key.find(base_part), base_part.size());
    if (!by_group.count(key)) group_order.push_back(key);
    by_group[key][r.config.*axis] = median_of(r.frames, metric);
  }
  for (const std::string& key : group_order) {
    auto& row = by_group[key];
    double base_value = row.count(base) ? row[base] : 0.0;
    md << "| `" << key << "` |";
    for (E v : values) md << " " << (row.count(v) ? cell(row[v], base_value) : "-") << " |";
    md << "\n";
  }
}

}  // namespace

std::string summary_markdown(const std::vector<CaseResult>& results) {
  std::ostringstream md;
  std::map<std::string, int> status_counts;
  for (const CaseResult& r : results) ++status_counts[std::string(to_string(r.status))];
  md << "## Cases\n\n";
  for (const auto& [status, count] : status_counts) md << "- " << status << ": " << count << "\n";
  for (const CaseResult& r : results)
    if (r.status != Status::ok) md << "  - `" << r.config.id() << "` " << to_string(r.status) << ": " << r.reason << "\n";

  ratio_table<Technique>(md, results, "Shadow pass: median wall time per technique (ratio to six_pass)",
                         &CaseConfig::technique, Technique::six_pass, shadow_wall);
  ratio_table<Filter>(md, results, "Lighting pass: median wall time per filter (ratio to hard)", &CaseConfig::filter,
                      Filter::hard, lighting_wall);
  return md.str();
}

}  // namespace omnishadow::bench
