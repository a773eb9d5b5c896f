#pragma once
// `omnishadow compare BASE NEW`: per case, a timing verdict (Mann-Whitney U over the repetitions,
// Holm-corrected across cases, and a minimum effect), an exact comparison of the work counters, and an image
// comparison (checksum first, then metrics and a diff PNG); and each case's status: a case ok in the base
// that failed, became unsupported, or is missing or interrupted in the new run is a regression (listed
// first). Exit codes: 0 no regression, 1 regression (status, timing, work or image change, or no case in
// common), 2 usage or input error.

#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/io/results_reader.h"
#include "bench/io/statistics.h"

namespace omnishadow::bench {

struct CompareOptions {
  double alpha = kDefaultAlpha;  // family-wise, over all compared cases (Holm)
  double min_effect = 0.05;      // a significant change smaller than this (relative) is "no change"
  bool timing = true;            // false: counters and images only
  bool timing_fails = true;      // false: timing verdicts are reported but only work and image changes fail
  bool allow_device_mismatch = false;
  // Which time is tested: "wall" (frame wall time, Google Benchmark's real_time), "cpu" (the process's CPU
  // time per frame, all threads: on CPU drivers the rendering work itself, and much less disturbed by other
  // load) or "gpu" (shadow + lighting pass GPU time per frame, from repetitions whose timer passed its sanity
  // check: on a GPU the work itself, without the CPU's submission and scheduling noise).
  std::string metric = "wall";
  std::string out_dir;  // summary.md, comparison.json and diffs/; empty = NEW's folder/compare
};

// "gl-llvmpipe-llvm-15.0.6-256-bits-4.5-core-profile-mesa-22.3.6-lp-unset": what must match for timings to be
// comparable (API, device, driver version, raster threads). One per backend in the run.
std::map<std::string, std::string> device_keys(const RunData& run);

struct CaseComparison {
  std::string id;
  std::string verdict;                         // regression, improvement, no change, not timed
  double base_ms = 0, new_ms = 0, change = 0;  // medians over repetitions; change = new / base - 1
  double p = 1.0, p_adjusted = 1.0;
  size_t base_n = 0, new_n = 0;
  std::vector<std::string> work_changes;   // "shadow gs_primitives 432 -> 72"
  std::vector<std::string> image_changes;  // "lit: 1.2% of values differ (max 64), diff: ..."
  // Whether base_n against new_n repetitions could reach significance at all over this comparison's cases
  // (bench/io/statistics.h can_resolve): false means "no change" says nothing about the change.
  bool resolvable = true;
  bool regressed(bool timing_counts = true) const {
    return (timing_counts && verdict == "regression") || !work_changes.empty() || !image_changes.empty();
  }
};

struct Comparison {
  // "gl/room/...: ok -> failed_check (cube_texels: ...)", "...: ok -> missing": cases ok in the base and not
  // in new.
  std::vector<std::string> status_regressions;
  std::vector<CaseComparison> cases;      // in both runs
  std::vector<std::string> only_in_base;  // listed; a status regression where the base had it ok
  std::vector<std::string> only_in_new;
  std::map<std::string, std::string> base_devices, new_devices;
  // Median clock over every device-state sample of each run (bench/run/device_state.h); -1 where a run has
  // none. Two runs of one device at different clocks are different measurements: the output says so.
  double base_clock_mhz = -1, new_clock_mhz = -1;
  std::string clock_note() const;  // "clocks: base 1980 MHz, new 1755 MHz (-11.4%)"; empty without both
  // A device's settings that differ between the runs, where both record them (results.json
  // devices.<backend>.extra: the SPIR-V level, the GL profile, API checks...): "vulkan spirv_optimization:
  // performance (glslc -O) -> none (glslc -O0)". The same device made to run a different program or path.
  std::vector<std::string> setup_changes;
  // "3 of 24 timed cases cannot be flagged at alpha 0.05 whatever their change: ..."; empty when all can.
  std::string resolution_note(const CompareOptions& options) const;
  // Whether the comparison fails: a status regression, a regressed case, or nothing in common to compare.
  bool failed(const CompareOptions& options) const;
};

Comparison compare_runs(const RunData& base, const RunData& fresh, const CompareOptions& options);
std::string comparison_table(const Comparison& c, const CompareOptions& options);     // for stdout
std::string comparison_markdown(const Comparison& c, const CompareOptions& options);  // for a CI job page
nlohmann::json comparison_json(const Comparison& c, const CompareOptions& options);   // for scripts

// The CLI entry point: prints the table, writes summary.md, returns the exit code.
int compare_command(const std::string& base, const std::string& fresh, const CompareOptions& options);
// Sets metric, alpha and min_effect from a gate file (results/baselines/<key>/gate.json, written by
// scripts/experiments/sensitivity.py --write-gate): the one reader of that file. Throws CompareError naming
// the file and field.
void apply_gate_file(const std::string& path, CompareOptions& options);

}  // namespace omnishadow::bench
