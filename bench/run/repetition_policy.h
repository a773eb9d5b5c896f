#pragma once
// How many repetitions a case gets. Repetitions always run in rounds: one repetition of every case that still
// needs one per round, so a slow spell of a shared machine hits every case alike instead of the cases that
// happened to run during it. Three ways to end: a fixed count (--benchmark_repetitions), a precision target
// (--precision: until the median's confidence interval is narrow enough, within a cap), or a time budget
// (--sustain: the matrix looped for that long; the thermal/clock stability figure).

#include <cstddef>
#include <string>
#include <vector>

namespace omnishadow::bench {

struct RepetitionPolicy {
  int repetitions = 1;  // the fixed count; with --precision or --sustain the minimum
  // --no-timing: false, the run is its untimed part only (checks, the reference, read-backs, images), as a
  // check of a driver or the mutation suite wants it: no case is timed and Google Benchmark's output is
  // empty.
  bool timed = true;
  double precision_percent =
      0.0;                       // --precision: target half-width of the 95% interval, % of the median; 0 off
  int max_repetitions = 30;      // --max-repetitions: the cap under --precision
  double sustain_seconds = 0.0;  // --sustain: loop rounds until this much time has passed; 0 off
  // --precision-metric: what --precision judges per repetition: "wall" (frame wall time), "cpu" (process CPU
  // time per frame) or "gpu" (shadow + lighting timer-query time per frame, from repetitions whose GPU timer
  // passed its check: compare --metric gpu's samples).
  std::string metric = "wall";
  // The cases one comparison of this run holds (Holm's family in `omnishadow compare`): the timed cases, each
  // experiment-axis copy (/inj<N>, /rep<k>) counted once. Set by the harness before timing.
  size_t compared_cases = 1;
  // The least repetitions a precision target is judged on: the smallest sample whose extreme order statistics
  // bracket the median with >= 95% confidence (1 - 2 / 2^6 = 96.9%).
  static constexpr int kMinForInterval = 6;
  // Under --precision, the most of: the fixed count, kMinForInterval, and the fewest repetitions at which
  // `omnishadow compare` over compared_cases cases at its default alpha could flag a case at all (7 for 24
  // cases, 8 for 96: bench/io/statistics.h). A quiet case could otherwise stop precise and still be
  // undetectable.
  int minimum() const;
  int cap() const;  // the most repetitions a case can get (sustain: none, -1)
};

// The distribution-free confidence interval of a median from order statistics (the binomial sign-test
// interval): the widest symmetric pair of ranks (k, n + 1 - k) with P(Binomial(n, 1/2) < k) <= (1 -
// confidence) / 2. Samples are per-repetition frame times, treated as independent (frames within a repetition
// are not).
struct MedianInterval {
  bool defined = false;  // too few samples for the confidence asked
  double median = 0.0, low = 0.0, high = 0.0;
  double coverage = 0.0;            // the interval's exact coverage (>= the confidence asked)
  double half_width_percent = 0.0;  // max(median - low, high - median) / median, in %
};
MedianInterval median_interval(std::vector<double> samples, double confidence = 0.95);

// Whether a case with these per-repetition samples needs another repetition after `elapsed_seconds` of
// timing.
bool needs_repetition(const RepetitionPolicy& policy, const std::vector<double>& samples,
                      double elapsed_seconds);

// Best repetition against worst (shortest over longest per-repetition frame time), in %: the stability figure
// of sustained GPU benchmarks (3DMark's stress tests pass at >= 97%). 100 with fewer than two samples.
double stability_percent(const std::vector<double>& samples);
inline constexpr double kStabilityPassPercent = 97.0;

}  // namespace omnishadow::bench
