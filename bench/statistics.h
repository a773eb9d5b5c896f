#pragma once
// Rank statistics for comparing timing samples that are not normal (bursty noise, long tails).

#include <vector>

namespace omnishadow::bench {

// Two-sided Mann-Whitney U test of "a and b come from the same distribution". Exact null distribution when
// there are no ties and both samples have at most 25 values; otherwise the normal approximation with tie and
// continuity corrections. Returns 1.0 when either sample is empty.
double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b);

// Holm-Bonferroni: adjusted p-values (same order as given) controlling the family-wise error rate.
std::vector<double> holm_adjust(const std::vector<double>& p);

double median(std::vector<double> values);

}  // namespace omnishadow::bench
