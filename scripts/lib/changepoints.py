"""Change points in a performance history: PELT on the log of the values, each candidate step then confirmed with a
Mann-Whitney U test between its neighbouring segments and a minimum relative effect.

PELT: R. Killick, P. Fearnhead, I. A. Eckley, "Optimal detection of changepoints with a linear computational
cost", Journal of the American Statistical Association 107(500):1590-1598, 2012. The cost of a segment is the
Gaussian mean-change cost (sum of squared deviations from the segment mean, in units of the noise variance), the
penalty per change point is `penalty` x log(n) (BIC-like), and the pruning rule drops every candidate start whose
cost already exceeds the best by the penalty. The noise scale comes from the first differences (median absolute
deviation and interquartile range, noise_scale), so that a step does not inflate it, and the U test's p-value is multiplied by the
number of positions PELT could have chosen (Bonferroni), since the split was selected on the same data; values are winsorised at 5 noise scales from the
median of their neighbourhood first, so that one outlying run does not become a segment of its own.

Work counters and image hashes are exact: any change of value is a step (exact_steps).
"""
import math

import numpy as np
from scipy.stats import mannwhitneyu


def noise_scale(x):
    """Robust standard deviation of the noise from the first differences: the larger of MAD / 0.6745 and
    IQR / 1.349 (they agree on Gaussian noise; the MAD alone is 0 where most differences are equal), over sqrt 2;
    0 for constant input."""
    x = np.asarray(x, dtype=float)
    if len(x) < 3:
        return 0.0
    d = np.diff(x)
    mad = np.median(np.abs(d - np.median(d))) / 0.6745
    q75, q25 = np.percentile(d, [75, 25])
    return float(max(mad, (q75 - q25) / 1.349) / math.sqrt(2.0))


def winsorise(x, sigma, k=5.0, window=5):
    """Clips each value to within k sigma of the median of its +-window neighbourhood."""
    x = np.asarray(x, dtype=float)
    if sigma <= 0:
        return x.copy()
    out = x.copy()
    for i in range(len(x)):
        m = np.median(x[max(0, i - window):i + window + 1])
        out[i] = min(max(x[i], m - k * sigma), m + k * sigma)
    return out


def pelt(x, penalty, min_size=2):
    """Indices where a new segment starts (sorted, excluding 0) minimising the sum of segment costs + penalty each.
    x is already in noise units (cost = sum of squared deviations from the segment mean)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    if n < 2 * min_size:
        return []
    s1 = np.concatenate([[0.0], np.cumsum(x)])
    s2 = np.concatenate([[0.0], np.cumsum(x * x)])

    def cost(starts, end):  # vectorised over segment starts, segment [start, end)
        length = end - starts
        total = s1[end] - s1[starts]
        return (s2[end] - s2[starts]) - total * total / length

    best = np.full(n + 1, np.inf)
    best[0] = -penalty
    last = np.zeros(n + 1, dtype=int)
    candidates = np.array([0])
    for end in range(min_size, n + 1):
        usable = candidates[end - candidates >= min_size]
        if len(usable):
            totals = best[usable] + cost(usable, end) + penalty
            i = int(np.argmin(totals))
            best[end], last[end] = totals[i], usable[i]
            # Pruning: a start whose cost to here already exceeds the optimum can never be the best later.
            keep = totals <= best[end] + penalty
            candidates = np.concatenate([usable[keep], candidates[end - candidates < min_size]])
        if end + 1 - min_size >= min_size:
            candidates = np.append(candidates, end + 1 - min_size)
        candidates = np.unique(candidates)
    points, end = [], n
    while end > 0:
        end = last[end]
        if end > 0:
            points.append(int(end))
    return sorted(points)


def timing_steps(values, penalty=3.0, alpha=0.01, min_effect=0.02, min_size=2, history=None):
    """Confirmed steps of a timing series (positive values, one per commit in commit order): dicts with `index`
    (first value after the step), `before` and `after` (segment medians), `step` (after / before - 1), `p` (two-sided
    Mann-Whitney U between the two segments) and `confidence` (1 - p). The noise scale comes from `history` (the
    case's whole series, of which `values` is the part analysed) when given: a short part estimates it badly."""
    v = np.asarray(values, dtype=float)
    if len(v) < 2 * min_size or np.any(v <= 0):
        return []
    logs = np.log(v)
    whole = np.asarray(history if history is not None else values, dtype=float)
    sigma = noise_scale(np.log(whole[whole > 0]))
    if sigma <= 0:
        sigma = max(1e-9, 1e-6 * abs(float(np.median(logs))))
    z = winsorise(logs, sigma) / sigma
    # The penalty grows with the whole history, not with the part analysed: a short part after an accepted step is
    # held to the same evidence as the history it belongs to.
    points = pelt(z, penalty * math.log(max(len(v), len(whole))), min_size)
    bounds = [0] + points + [len(v)]
    steps = []
    for k, index in enumerate(points):
        before, after = v[bounds[k]:index], v[index:bounds[k + 2]]
        m0, m1 = float(np.median(before)), float(np.median(after))
        # PELT chose this split among every admissible one: the test's p-value is Bonferroni-corrected for that
        # choice (positions a segment of min_size could start at), or chance splits of short series pass it.
        positions = max(1, len(v) - 2 * min_size + 1)
        p = min(1.0, positions * float(mannwhitneyu(before, after, alternative="two-sided").pvalue))
        change = m1 / m0 - 1.0
        if p < alpha and abs(change) > min_effect:
            steps.append({"index": index, "before": m0, "after": m1, "step": change, "p": p, "confidence": 1.0 - p})
    return steps


def exact_steps(values, history=None):
    """Every index whose value differs from the one before (work counters, image hashes): no statistics."""
    return [{"index": i, "before": values[i - 1], "after": values[i]} for i in range(1, len(values))
            if values[i] != values[i - 1]]
