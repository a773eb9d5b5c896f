#include "bench/run/timing_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace omnishadow::bench {

double quantile_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(at));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (at - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

Summary summarize(std::vector<double> values) {
  Summary s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  size_t n = values.size();
  s.median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  s.p90 = quantile_sorted(values, 0.90);
  s.p99 = quantile_sorted(values, 0.99);
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(n);
  double sq = 0;
  for (double v : values) sq += (v - s.mean) * (v - s.mean);
  s.stddev = n > 1 ? std::sqrt(sq / static_cast<double>(n - 1)) : 0.0;
  return s;
}

GpuTimerCheck check_gpu_timer(const std::vector<FrameTiming>& frames) {
  GpuTimerCheck c;
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameTiming& f = frames[i];
    const std::pair<const char*, const PassTiming*> passes[] = {{"shadow", &f.shadow},
                                                                {"lighting", &f.lighting}};
    bool frame_ok = true;
    for (const auto& [name, p] : passes) {
      if (p->gpu_ms < 0) continue;  // the backend has no GPU figure for this pass
      c.available = true;
      bool ok = std::isfinite(p->gpu_ms) && p->gpu_ms > 0 && p->gpu_ms <= p->cpu_wall_ms * 1.05 + 0.1;
      if (!ok && frame_ok && c.note.empty()) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s pass: gpu %.3f ms vs wall %.3f ms (frame %zu of the case)", name,
                      p->gpu_ms, p->cpu_wall_ms, i);
        c.note = buf;
      }
      frame_ok = frame_ok && ok;
    }
    ++c.frames_checked;
    if (!frame_ok) ++c.frames_failing;
  }
  c.reliable = c.available && c.frames_failing == 0;
  if (!c.available) c.note = "the backend reports no GPU timer figures";
  return c;
}

}  // namespace omnishadow::bench
