#pragma once
// Rank statistics for comparing timing samples that are not normal (bursty noise, long tails).

#include <cstddef>
#include <vector>

namespace omnishadow::bench {

// Two-sided Mann-Whitney U test of "a and b come from the same distribution". Exact null distribution when
// there are no ties and both samples have at most 25 values; otherwise the normal approximation with tie and
// continuity corrections. Returns 1.0 when either sample is empty.
double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b);

// The family-wise alpha `omnishadow compare` uses unless told otherwise (--alpha, a baseline's gate.json).
inline constexpr double kDefaultAlpha = 0.05;

// The smallest p the U test above can give for samples of these sizes: every value of one below every value
// of the other. With ranks only, nothing less is possible, however large the change.
double smallest_p(size_t n1, size_t n2);

// Whether Holm over `cases` comparisons at `alpha` could flag a case with these sample sizes at all: its
// first step needs p < alpha / cases. (6 against 6 repetitions give at best p = 0.00216: over 24 cases,
// never.)
bool can_resolve(size_t n1, size_t n2, size_t cases, double alpha = kDefaultAlpha);

// The fewest repetitions per side at which a comparison of `cases` cases at `alpha` can flag one.
int fewest_resolving_repetitions(size_t cases, double alpha = kDefaultAlpha);

// Holm-Bonferroni: adjusted p-values (same order as given) controlling the family-wise error rate.
std::vector<double> holm_adjust(const std::vector<double>& p);

double median(std::vector<double> values);

}  // namespace omnishadow::bench
