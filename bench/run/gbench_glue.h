#pragma once
// Google Benchmark drives the timed part: one benchmark per case, manual time = the frame's wall time,
// counters = per-pass figures. Repetitions run in rounds (bench/run/repetition_policy.h): each round is one
// Google Benchmark run with one repetition of every case that still needs one. Its flags (--benchmark_filter,
// --benchmark_enable_random_interleaving: the case order within each round shuffled, ...) apply as usual;
// --benchmark_repetitions is the policy's fixed count and is not passed on.

#include <functional>
#include <string>
#include <vector>

#include "bench/run/case_runner.h"
#include "bench/run/repetition_policy.h"

namespace omnishadow::bench {

// The cases one comparison of this run would hold (RepetitionPolicy::compared_cases): the cases that will be
// timed, the copies of an experiment axis (/inj<N>, /rep<k>) counted once.
size_t compared_cases(const std::vector<CaseResult>& results);

// Cases whose checks ran (passed or not) are timed; cases that could not be prepared are not.
bool is_timed(Status s);

// Times every case whose checks ran, with console output on stdout, and writes Google Benchmark's JSON of all
// rounds to `gbench_json_path`. Timings are appended to each result; `after_case` runs after every timed
// repetition (the caller saves partial results there). When `stop_requested` turns true (SIGINT/SIGTERM) the
// repetition in hand finishes and nothing more is timed: cases never timed are marked "interrupted", the
// others keep the repetitions they have.
void run_timed(Harness& harness, std::vector<CaseResult>& results, const RepetitionPolicy& policy,
               const std::string& gbench_json_path, const std::function<void()>& after_case,
               const std::function<bool()>& stop_requested);

}  // namespace omnishadow::bench
