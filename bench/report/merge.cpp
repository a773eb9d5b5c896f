#include "bench/report/merge.h"

#include <filesystem>
#include <set>

#include "bench/io/file_io.h"
#include "bench/report/compare.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;
using nlohmann::json;

std::string MergeResult::describe() const {
  std::string out;
  for (int shard : missing_shards)
    out += (out.empty() ? "" : "; ") + std::string("shard ") + std::to_string(shard) + " missing";
  for (const std::string& file : incomplete_inputs)
    out += (out.empty() ? "" : "; ") + file + " is an incomplete run (stopped before it ended)";
  return out;
}

MergeResult merge_runs(const std::string& out_dir, const std::vector<std::string>& runs) {
  MergeResult result;
  if (runs.empty()) throw CompareError("merge: no runs given");
  create_writable_folder(out_dir, "merge OUT");
  if (fs::exists(fs::path(out_dir) / "results.json"))
    throw CompareError("merge: " + out_dir + " already holds a run (results.json); choose a new folder");
  json merged;
  std::set<std::string> ids;
  std::map<std::string, std::string> keys;
  bool complete = true;
  std::set<int> shards;
  int shard_count = 0;  // 0: no run said (results written before shards were recorded)
  for (const std::string& path : runs) {
    RunData run = load_run(path);
    if (const json& o = run.doc["omnishadow"]; o.contains("shard") && o["shard"].is_object()) {
      const int index = o["shard"].value("index", 0), count = o["shard"].value("count", 1);
      if (shard_count && count != shard_count)
        throw CompareError("merge: " + run.file + " is a shard of " + std::to_string(count) +
                           ", the others of " + std::to_string(shard_count));
      shard_count = count;
      if (!shards.insert(index).second)
        throw CompareError("merge: shard " + std::to_string(index) + " is given twice (" + run.file + ")");
    }
    for (const auto& [backend, key] : device_keys(run)) {
      auto [it, inserted] = keys.emplace(backend, key);
      if (!inserted && it->second != key)
        throw CompareError("merge: backend " + backend + " ran on different devices: " + it->second +
                           " and " + key);
    }
    // Image paths were relative to the shard's folder; make them relative to the merged one.
    std::string prefix = fs::relative(fs::absolute(run.dir), fs::absolute(out_dir)).string();
    json cases = run.doc["omnishadow"]["cases"];
    for (json& c : cases) {
      std::string id = c["id"];
      if (!ids.insert(id).second) throw CompareError("merge: case " + id + " is in more than one run");
      if (c.contains("images"))
        for (auto& [role, rel] : c["images"].items())
          rel = (fs::path(prefix) / rel.get<std::string>()).string();
    }
    if (!run.doc["omnishadow"].value("complete", false)) {
      complete = false;
      result.incomplete_inputs.push_back(run.file);
    }
    if (merged.is_null()) {
      merged = run.doc;
      merged["omnishadow"]["cases"] = cases;
      merged["omnishadow"]["merged_from"] = json::array();
      if (!merged.contains("benchmarks")) merged["benchmarks"] = json::array();
    } else {
      for (json& c : cases) merged["omnishadow"]["cases"].push_back(c);
      for (const json& b : run.doc.value("benchmarks", json::array())) merged["benchmarks"].push_back(b);
      for (const auto& [backend, d] : run.doc["omnishadow"]["devices"].items())
        merged["omnishadow"]["devices"][backend] = d;
    }
    merged["omnishadow"]["merged_from"].push_back(run.file);
  }
  // A missing shard's cases are simply absent: the merged run is incomplete, and says which shards it lacks,
  // so that compare fails on the cases the baseline has and this run does not.
  json missing = json::array();
  for (int i = 0; i < shard_count; ++i)
    if (!shards.count(i)) {
      missing.push_back(i);
      result.missing_shards.push_back(i);
    }
  if (!missing.empty()) complete = false;
  merged["omnishadow"]["missing_shards"] = missing;
  merged["omnishadow"]["shard"] = {{"index", 0}, {"count", 1}};
  merged["omnishadow"]["complete"] = complete;
  write_file_atomic((fs::path(out_dir) / "results.json").string(), merged.dump(2) + "\n");
  result.complete = complete;
  return result;
}

}  // namespace omnishadow::bench
