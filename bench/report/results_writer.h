#pragma once
// results.json: Google Benchmark's JSON (so tools/compare.py reads it) with an "omnishadow" section holding
// every case's axes, status, checks, work counters, timing summaries and images, plus device and machine.
// Written atomically after every case, so a run killed at any point leaves a valid file with what finished.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/report/summary_table.h"
#include "bench/run/case_result.h"
#include "bench/run/run_options.h"

namespace omnishadow::bench {

struct RunInfo {
  std::string command_line;
  std::map<std::string, DeviceInfo> devices;  // by backend name
  RunOptions options;
  std::string stopped_by;                // "SIGINT" / "SIGTERM" when the run was interrupted
  int shard_index = 0, shard_count = 1;  // --shard i/N: merge checks that every shard of N is there
  RunPhases phases;
  RepetitionPolicy repetitions;
};

nlohmann::json case_to_json(const CaseResult& r);
nlohmann::json axes_to_json(const CaseConfig& c);  // a case's "axes" object
nlohmann::json device_to_json(const DeviceInfo& d);

// `gbench` is Google Benchmark's own JSON for the run, or null while timing has not finished; `complete`
// says whether every case of the matrix is in.
void write_results(const std::string& path, const RunInfo& run, const std::vector<CaseResult>& results,
                   const nlohmann::json& gbench, bool complete);

}  // namespace omnishadow::bench
