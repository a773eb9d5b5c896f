#include "bench/io/results_reader.h"

#include <cmath>
#include <filesystem>
#include <set>

#include "bench/io/file_io.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool starts_with_at(const std::string& s, size_t i, const char* token) {
  return s.compare(i, std::char_traits<char>::length(token), token) == 0;
}

// Checks the document's shape; `where` is a JSON pointer for the message.
class Shape {
 public:
  explicit Shape(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& why) const {
    throw CompareError(file_ + ": " + (where.empty() ? "/" : where) + ": " + why);
  }
  const json& object(const json& j, const std::string& where) const {
    if (!j.is_object()) fail(where, "expected an object, found " + std::string(j.type_name()));
    return j;
  }
  const json& array(const json& j, const std::string& where) const {
    if (!j.is_array()) fail(where, "expected an array, found " + std::string(j.type_name()));
    return j;
  }
  // Optional members: absent is fine, any other type than the expected one is not. Null is a number here only
  // (Google Benchmark's NaN, read as null); elsewhere the readers' value() calls would throw on it.
  void optional(const json& parent, const std::string& where, const char* key, json::value_t type) const {
    auto it = parent.find(key);
    if (it == parent.end()) return;
    bool ok = type == json::value_t::number_float ? it->is_number() || it->is_null() : it->type() == type;
    if (!ok)
      fail(where + "/" + key,
           "expected " + std::string(json(type).type_name()) + ", found " + std::string(it->type_name()));
  }

 private:
  std::string file_;
};

void check_counters(const Shape& shape, const json& counters, const std::string& where) {
  shape.object(counters, where);
  for (const auto& [pass, c] : counters.items()) {
    std::string at = where + "/" + pass;
    shape.object(c, at);
    for (const auto& [field, v] : c.items())
      if (field == "valid" ? !v.is_boolean() : !v.is_number())
        shape.fail(at + "/" + field, field == "valid" ? "expected a boolean" : "expected a number");
  }
}

void check_case(const Shape& shape, const json& c, const std::string& where, std::set<std::string>& ids) {
  shape.object(c, where);
  auto id = c.find("id");
  if (id == c.end() || !id->is_string() || id->get_ref<const std::string&>().empty())
    shape.fail(where + "/id", "every case needs a non-empty string id");
  if (!ids.insert(id->get<std::string>()).second)
    shape.fail(where + "/id", "case " + id->dump() + " appears twice");
  shape.optional(c, where, "status", json::value_t::string);
  shape.optional(c, where, "reason", json::value_t::string);
  if (c.contains("counters")) check_counters(shape, c["counters"], where + "/counters");
  if (c.contains("images")) {
    const json& images = shape.object(c["images"], where + "/images");
    for (const auto& [role, path] : images.items()) {
      if (!path.is_string() || path.get_ref<const std::string&>().empty())
        shape.fail(where + "/images/" + role, "expected a non-empty relative path");
      if (fs::path(path.get<std::string>()).is_absolute())
        shape.fail(where + "/images/" + role, "image paths are relative to the run folder");
    }
  }
}

void check_benchmark(const Shape& shape, const json& b, const std::string& where) {
  shape.object(b, where);
  shape.optional(b, where, "name", json::value_t::string);
  shape.optional(b, where, "run_type", json::value_t::string);
  shape.optional(b, where, "error_occurred", json::value_t::boolean);
  shape.optional(b, where, "omnishadow_case", json::value_t::string);
  shape.optional(b, where, "real_time", json::value_t::number_float);
  shape.optional(b, where, "frame_cpu_ms", json::value_t::number_float);
  for (const char* key : {"gpu_timer_reliable", "shadow_gpu_ms", "lighting_gpu_ms"})
    shape.optional(b, where, key, json::value_t::number_float);
}

}  // namespace

json parse_gbench_json(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    char ch = text[i];
    if (in_string) {
      out += ch;
      if (ch == '\\' && i + 1 < text.size())
        out += text[++i];
      else if (ch == '"')
        in_string = false;
      continue;
    }
    if (ch == '"') {
      in_string = true;
      out += ch;
      continue;
    }
    size_t j = i + (ch == '-' ? 1 : 0);
    bool replaced = false;
    for (const char* token : {"NaN", "nan", "-nan", "Infinity", "inf"}) {
      if (!starts_with_at(text, j, token)) continue;
      size_t end = j + std::char_traits<char>::length(token);
      if (end < text.size() && std::isalnum(static_cast<unsigned char>(text[end]))) continue;
      out += "null";
      i = end - 1;
      replaced = true;
      break;
    }
    if (!replaced) out += ch;
  }
  return json::parse(out);
}

RunData parse_run(const std::string& text, const std::string& file, const std::string& dir) {
  RunData run;
  run.file = file;
  run.dir = dir.empty() ? "." : dir;
  Shape shape(file);
  try {
    run.doc = parse_gbench_json(text);
  } catch (const json::parse_error& e) {
    throw CompareError(file + ": not valid JSON (truncated or corrupt) at byte " + std::to_string(e.byte));
  } catch (const json::exception& e) {  // out_of_range 406: a number beyond double ("1e400")
    throw CompareError(
        file + ": not valid JSON: " + std::string(e.what()).substr(std::string(e.what()).find(']') + 2));
  }
  const json& doc = run.doc;
  auto section = doc.is_object() ? doc.find("omnishadow") : doc.end();
  if (doc.is_object() && section != doc.end() && section->is_object() && section->contains("format") &&
      (*section)["format"] != "omnishadow-results/1")
    throw CompareError(
        file + ": /omnishadow/format is " + (*section)["format"].dump() +
        ", not omnishadow-results/1, the format this binary reads (a run of another omnishadow "
        "version)");
  if (!doc.is_object() || section == doc.end() || !section->is_object() || !section->contains("format"))
    throw CompareError(file +
                       ": not an omnishadow results file (no \"omnishadow\" section of format "
                       "omnishadow-results/1)");
  const json& o = *section;
  shape.optional(o, "/omnishadow", "complete", json::value_t::boolean);
  if (o.contains("system")) {
    shape.object(o["system"], "/omnishadow/system");
    shape.optional(o["system"], "/omnishadow/system", "LP_NUM_THREADS", json::value_t::string);
  }
  if (o.contains("devices"))
    for (const auto& [backend, d] : shape.object(o["devices"], "/omnishadow/devices").items()) {
      std::string at = "/omnishadow/devices/" + backend;
      shape.object(d, at);
      for (const char* key : {"api", "vendor", "renderer", "version", "platform"})
        shape.optional(d, at, key, json::value_t::string);
    }
  if (!o.contains("cases")) shape.fail("/omnishadow/cases", "missing");
  const json& cases = shape.array(o["cases"], "/omnishadow/cases");
  std::set<std::string> ids;
  for (size_t i = 0; i < cases.size(); ++i) {
    check_case(shape, cases[i], "/omnishadow/cases/" + std::to_string(i), ids);
    run.cases[cases[i]["id"].get<std::string>()] = &cases[i];
  }
  if (doc.contains("benchmarks")) {
    const json& benchmarks = shape.array(doc["benchmarks"], "/benchmarks");
    for (size_t i = 0; i < benchmarks.size(); ++i) {
      const json& b = benchmarks[i];
      check_benchmark(shape, b, "/benchmarks/" + std::to_string(i));
      if (b.value("run_type", "") != "iteration" || b.value("error_occurred", false)) continue;
      std::string id = b.value("omnishadow_case", "");
      if (id.empty() || !b.contains("real_time") || !b["real_time"].is_number()) continue;
      double ms = b["real_time"].get<double>();
      if (!std::isfinite(ms) || ms < 0)
        shape.fail("/benchmarks/" + std::to_string(i) + "/real_time", "not a finite, non-negative time");
      run.samples[id].push_back(ms);
      if (b.contains("frame_cpu_ms") && b["frame_cpu_ms"].is_number()) {
        double cpu = b["frame_cpu_ms"].get<double>();
        if (!std::isfinite(cpu) || cpu < 0)
          shape.fail("/benchmarks/" + std::to_string(i) + "/frame_cpu_ms", "not a finite, non-negative time");
        run.cpu_samples[id].push_back(cpu);
      }
      if (b.value("gpu_timer_reliable", 0.0) == 1.0 && b.contains("shadow_gpu_ms") &&
          b.contains("lighting_gpu_ms")) {
        double gpu = b["shadow_gpu_ms"].get<double>() + b["lighting_gpu_ms"].get<double>();
        if (!std::isfinite(gpu) || gpu < 0)
          shape.fail("/benchmarks/" + std::to_string(i) + "/shadow_gpu_ms",
                     "not a finite, non-negative time");
        run.gpu_samples[id].push_back(gpu);
      }
    }
  }
  return run;
}

RunData load_run(const std::string& path) {
  std::error_code ec;
  std::string file = fs::is_directory(path, ec) ? (fs::path(path) / "results.json").string() : path;
  std::string text;
  try {
    text = read_file(file);
  } catch (const std::exception&) {
    throw CompareError(file + ": cannot read (give a run folder or its results.json)");
  }
  return parse_run(text, file, fs::path(file).parent_path().string());
}

}  // namespace omnishadow::bench
