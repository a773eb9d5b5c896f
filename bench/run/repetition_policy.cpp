#include "bench/run/repetition_policy.h"

#include <algorithm>
#include <cmath>

#include "bench/io/statistics.h"

namespace omnishadow::bench {

int RepetitionPolicy::minimum() const {
  int n = std::max(1, repetitions);
  if (precision_percent <= 0.0) return n;
  return std::max({n, kMinForInterval, fewest_resolving_repetitions(compared_cases)});
}

int RepetitionPolicy::cap() const {
  if (sustain_seconds > 0.0) return -1;
  return precision_percent > 0.0 ? std::max(minimum(), max_repetitions) : minimum();
}

MedianInterval median_interval(std::vector<double> samples, double confidence) {
  MedianInterval out;
  const int n = static_cast<int>(samples.size());
  if (n == 0) return out;
  std::sort(samples.begin(), samples.end());
  out.median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
  // P(B <= j) for B ~ Binomial(n, 1/2), accumulated in log space so that large n does not overflow.
  const double tail = (1.0 - confidence) / 2.0;
  double cdf = 0.0;
  int k = 0;  // ranks (k, n + 1 - k), 1-based; 0 = none qualifies
  for (int j = 0; j < n; ++j) {
    double log_pmf =
        std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) - n * std::log(2.0);
    cdf += std::exp(log_pmf);
    if (cdf > tail) break;
    k = j + 1;
    out.coverage = 1.0 - 2.0 * cdf;
  }
  if (k == 0 || k > n + 1 - k) return out;
  out.defined = true;
  out.low = samples[k - 1];
  out.high = samples[n - k];
  if (out.median > 0.0)
    out.half_width_percent = 100.0 * std::max(out.median - out.low, out.high - out.median) / out.median;
  return out;
}

bool needs_repetition(const RepetitionPolicy& policy, const std::vector<double>& samples,
                      double elapsed_seconds) {
  const int n = static_cast<int>(samples.size());
  if (n < policy.minimum()) return true;
  if (policy.sustain_seconds > 0.0) return elapsed_seconds < policy.sustain_seconds;
  if (n >= policy.cap()) return false;
  if (policy.precision_percent <= 0.0) return false;
  MedianInterval ci = median_interval(samples);
  return !ci.defined || ci.half_width_percent > policy.precision_percent;
}

double stability_percent(const std::vector<double>& samples) {
  if (samples.size() < 2) return 100.0;
  auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
  return *hi > 0.0 ? 100.0 * *lo / *hi : 100.0;
}

}  // namespace omnishadow::bench
