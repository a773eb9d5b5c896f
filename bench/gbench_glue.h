#pragma once
// Google Benchmark drives the timed part: one benchmark per case, manual time = the frame's wall time,
// counters = per-pass figures. Its flags (--benchmark_filter, --benchmark_repetitions,
// --benchmark_enable_random_interleaving, ...) apply as usual.

#include <functional>
#include <vector>

#include "bench/case_runner.h"

namespace omnishadow::bench {

// Registers every case (unsupported and failed ones report their status through SkipWithError, so that
// they still appear in the JSON), runs them with console output on stdout and Google Benchmark's JSON to
// the file named by --benchmark_out. Timings are appended to each result; `after_case` runs after every
// timed repetition (the caller saves partial results there). `repetitions` only feeds the progress line.
// When `stop_requested` turns true (SIGINT/SIGTERM), the cases not yet timed are skipped as "interrupted".
void run_timed(Harness& harness, std::vector<CaseResult>& results, int repetitions,
               const std::function<void()>& after_case, const std::function<bool()>& stop_requested);

}  // namespace omnishadow::bench
