#pragma once
// Summaries of per-frame timings, and the sanity check that decides whether a backend's GPU timer figures
// can be trusted for a case.

#include <string>
#include <vector>

#include "backends/backend.h"

namespace omnishadow::bench {

// Of every timed frame (not of Google Benchmark's per-repetition means): a technique that is faster on median
// but stutters shows it in p99 and max. Percentiles interpolate linearly between order statistics (numpy's
// default).
struct Summary {
  int count = 0;
  double mean = 0, median = 0, min = 0, max = 0, stddev = 0;
  double p90 = 0, p99 = 0;
};
Summary summarize(std::vector<double> values);
// The q-quantile (0..1) of sorted values, linear between order statistics; 0 for none.
double quantile_sorted(const std::vector<double>& sorted, double q);

// GPU timer figures are trusted only if every frame's figure is positive and no larger than the wall time
// of the same pass (which brackets it: the pass is finished before the wall clock stops), with 5% + 0.1 ms of
// slack for clock granularity. Warm-up frames are checked too: a timer that is wrong on the first query after
// a context is created (llvmpipe returns ~5e5 ms there) is wrong.
struct GpuTimerCheck {
  bool available = false;  // the backend reported GPU figures at all
  bool reliable = false;
  int frames_checked = 0;
  int frames_failing = 0;
  std::string note;  // first failure, e.g. "shadow pass: gpu 516371.5 ms > wall 92.6 ms (frame 0)"
};
GpuTimerCheck check_gpu_timer(const std::vector<FrameTiming>& frames);

}  // namespace omnishadow::bench
