#include "bench/io/statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace omnishadow::bench {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n1 = a.size(), n2 = b.size();
  if (n1 == 0 || n2 == 0) return 1.0;
  // Ranks of the pooled sample, ties sharing their mean rank.
  std::vector<std::pair<double, int>> pooled;
  for (double x : a) pooled.push_back({x, 0});
  for (double y : b) pooled.push_back({y, 1});
  std::sort(pooled.begin(), pooled.end());
  const size_t n = pooled.size();
  double rank_sum_a = 0.0, tie_term = 0.0;
  bool ties = false;
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j < n && pooled[j].first == pooled[i].first) ++j;
    double mean_rank = 0.5 * static_cast<double>(i + 1 + j);
    double t = static_cast<double>(j - i);
    if (t > 1) ties = true;
    tie_term += t * t * t - t;
    for (size_t k = i; k < j; ++k)
      if (pooled[k].second == 0) rank_sum_a += mean_rank;
    i = j;
  }
  const double u = rank_sum_a - static_cast<double>(n1 * (n1 + 1)) / 2.0;
  const double mean_u = static_cast<double>(n1 * n2) / 2.0;

  if (!ties && n1 <= 25 && n2 <= 25) {
    // counts[k][u]: ways to pick k of the first m ranks summing (in U terms) to u; built up over m.
    const size_t max_u = n1 * n2;
    std::vector<std::vector<double>> counts(n1 + 1, std::vector<double>(max_u + 1, 0.0));
    counts[0][0] = 1.0;
    for (size_t m = 1; m <= n; ++m)
      for (size_t k = std::min(m, n1); k >= 1; --k) {
        // Rank m as the k-th smallest element of a has (m - k) values of b below it: U grows by m - k.
        const size_t add = m - k;
        if (add > n2) continue;
        for (long s = static_cast<long>(max_u); s >= static_cast<long>(add); --s)
          counts[k][static_cast<size_t>(s)] += counts[k - 1][static_cast<size_t>(s) - add];
      }
    double total = std::accumulate(counts[n1].begin(), counts[n1].end(), 0.0);
    // Two-sided: the probability of a U at least as far from the mean as the one observed.
    double distance = std::fabs(u - mean_u), tail = 0.0;
    for (size_t s = 0; s <= max_u; ++s)
      if (std::fabs(static_cast<double>(s) - mean_u) >= distance - 1e-9) tail += counts[n1][s];
    return std::min(1.0, tail / total);
  }
  const double nn = static_cast<double>(n);
  const double variance = static_cast<double>(n1 * n2) / 12.0 * ((nn + 1.0) - tie_term / (nn * (nn - 1.0)));
  if (variance <= 0.0) return 1.0;  // every value equal
  const double z = (std::fabs(u - mean_u) - 0.5) / std::sqrt(variance);
  return std::min(1.0, std::erfc(std::max(z, 0.0) / std::sqrt(2.0)));
}

double smallest_p(size_t n1, size_t n2) {
  std::vector<double> low(n1), high(n2);
  std::iota(low.begin(), low.end(), 0.0);
  std::iota(high.begin(), high.end(), static_cast<double>(n1));
  return mann_whitney_p(low, high);
}

bool can_resolve(size_t n1, size_t n2, size_t cases, double alpha) {
  return smallest_p(n1, n2) * static_cast<double>(std::max<size_t>(cases, 1)) < alpha;
}

int fewest_resolving_repetitions(size_t cases, double alpha) {
  int n = 1;
  while (!can_resolve(n, n, cases, alpha) && n < 1000) ++n;  // 1000: alpha / cases below ~1e-600 never ends
  return n;
}

std::vector<double> holm_adjust(const std::vector<double>& p) {
  const size_t m = p.size();
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return p[a] < p[b]; });
  std::vector<double> adjusted(m);
  double running = 0.0;
  for (size_t i = 0; i < m; ++i) {
    running = std::max(running, std::min(1.0, static_cast<double>(m - i) * p[order[i]]));
    adjusted[order[i]] = running;
  }
  return adjusted;
}

}  // namespace omnishadow::bench
