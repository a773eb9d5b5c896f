#include "bench/results/merge.h"

#include <filesystem>
#include <set>

#include "bench/results/compare.h"
#include "bench/results/file_io.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;
using nlohmann::json;

void merge_runs(const std::string& out_dir, const std::vector<std::string>& runs) {
  if (runs.empty()) throw CompareError("merge: no runs given");
  fs::create_directories(out_dir);
  if (fs::exists(fs::path(out_dir) / "results.json"))
    throw CompareError("merge: " + out_dir + " already holds a run (results.json); choose a new folder");
  json merged;
  std::set<std::string> ids;
  std::map<std::string, std::string> keys;
  bool complete = true;
  for (const std::string& path : runs) {
    RunData run = load_run(path);
    for (const auto& [backend, key] : device_keys(run)) {
      auto [it, inserted] = keys.emplace(backend, key);
      if (!inserted && it->second != key)
        throw CompareError("merge: backend " + backend + " ran on different devices: " + it->second + " and " + key);
    }
    // Image paths were relative to the shard's folder; make them relative to the merged one.
    std::string prefix = fs::relative(fs::absolute(run.dir), fs::absolute(out_dir)).string();
    json cases = run.doc["omnishadow"]["cases"];
    for (json& c : cases) {
      std::string id = c["id"];
      if (!ids.insert(id).second) throw CompareError("merge: case " + id + " is in more than one run");
      if (c.contains("images"))
        for (auto& [role, rel] : c["images"].items()) rel = (fs::path(prefix) / rel.get<std::string>()).string();
    }
    complete = complete && run.doc["omnishadow"].value("complete", false);
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
  merged["omnishadow"]["complete"] = complete;
  write_file_atomic((fs::path(out_dir) / "results.json").string(), merged.dump(2) + "\n");
}

}  // namespace omnishadow::bench
