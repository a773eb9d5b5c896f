#pragma once
// Google Benchmark's output for a run timed in rounds. Each round is one RunSpecifiedBenchmarks call with one
// repetition per case, so Google Benchmark neither numbers the repetitions nor aggregates them: RoundReporter
// collects every round's runs (numbering them per case) while printing them, and write_gbench_json writes the
// file Google Benchmark would have written for the same repetitions, aggregates (_mean, _median, _stddev,
// _cv) included, which tools/compare.py and `omnishadow compare` read.

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace omnishadow::bench {

// Google Benchmark's warning for a library built without NDEBUG, and what it means for omnishadow's figures.
inline constexpr const char* kDebugLibraryWarning = "Library was built as DEBUG";
inline constexpr const char* kDebugLibraryNote =
    "note: this libbenchmark was built with its assertions on (Debian's is); it only counts the iterations "
    "here, every figure is timed by omnishadow's own clocks and queries (manual_time), so none is affected\n";
// The context text with the debug-library warning line replaced by kDebugLibraryNote.
std::string explain_debug_library(const std::string& context_text);

class RoundReporter : public benchmark::ConsoleReporter {
 public:
  RoundReporter() : benchmark::ConsoleReporter(OO_Tabular) {}
  // Prints the context once (the first round), not once per round. Debian's libbenchmark is built without
  // NDEBUG and says "Library was built as DEBUG. Timings may be affected.": that line is replaced by what it
  // means here (kDebugLibraryNote).
  bool ReportContext(const Context& context) override;
  // Keeps the runs (repetition_index = this case's count so far), prints them with the headline counters
  // only.
  void ReportRuns(const std::vector<Run>& runs) override;
  // Every case's runs in the order they ran; with its aggregates when it has more than one repetition.
  std::vector<Run> all_runs() const;

 private:
  bool context_printed_ = false;
  std::vector<std::string> order_;                // case names in first-seen order
  std::map<std::string, std::vector<Run>> runs_;  // by benchmark name
};

// mean, median, stddev and cv over `runs` (iteration runs of one benchmark, without errors) of the real and
// CPU time per iteration and of every counter, as Google Benchmark computes them for --benchmark_repetitions.
std::vector<benchmark::BenchmarkReporter::Run> aggregate_runs(
    const std::vector<benchmark::BenchmarkReporter::Run>& runs);

// Writes Google Benchmark's JSON (context and benchmarks) of `runs` to `path`; throws std::runtime_error.
void write_gbench_json(const std::string& path, const std::vector<benchmark::BenchmarkReporter::Run>& runs);

}  // namespace omnishadow::bench
