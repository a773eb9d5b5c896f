"""Injected work calibrated per device, in the metric the comparison will test (wall, CPU or GPU time).

`--inject-fragment-work N` adds N dependent multiply-adds to every lighting fragment. What N costs depends on the
device (an H100 runs 2 M fragments x 20 iterations in microseconds; llvmpipe needs milliseconds) and on the frame
size, and it is not linear in N (short loops are unrolled). So the count is found by doubling on the device itself,
in one run per batch so that every count meets the same machine state as the base: N = 1 .. 16 in the first run,
32 .. 512 in the next, and so on until some count slows the median case by at least the largest target. Each target's
count is then interpolated between the two measured counts around it.

Used by scripts/experiments/sensitivity.py (across runs) and sensitivity_same_run.py (within one run).
"""
import statistics
import sys

# Per benchmark entry (one repetition of one case), the per-frame figure each metric tests; gpu only where the
# repetition's GPU timer passed its check (compare --metric gpu reads the same).
def entry_value(entry, metric):
    if metric == "wall":
        return entry.get("real_time")
    if metric == "cpu":
        return entry.get("frame_cpu_ms")
    if not entry.get("gpu_timer_reliable") or "shadow_gpu_ms" not in entry:
        return None
    return entry["shadow_gpu_ms"] + entry.get("lighting_gpu_ms", 0.0)


def case_medians(doc, metric):
    """Per case id: the median per-repetition figure of `metric`; cases without any value left out."""
    samples = {}
    for b in doc["benchmarks"]:
        if b.get("run_type") != "iteration" or "omnishadow_case" not in b:
            continue
        v = entry_value(b, metric)
        if v is not None:
            samples.setdefault(b["omnishadow_case"], []).append(v)
    return {k: statistics.median(v) for k, v in samples.items()}


def slowdowns_in_run(doc, counts, metric):
    """Per injected count: the median over cases of (case with /inj<count>) / (the same case with /inj0) - 1."""
    m = case_medians(doc, metric)
    out = {}
    for n in counts:
        ratios = [m[k.replace("/inj0", f"/inj{n}")] / m[k] - 1 for k in m
                  if "/inj0" in k and k.replace("/inj0", f"/inj{n}") in m and m[k] > 0]
        if not ratios:
            sys.exit(f"calibration: no {metric} time for injected count {n} (for gpu: did the GPU timer pass its "
                     "check?)")
        out[n] = statistics.median(ratios)
    return out


def interpolate(measured, target):
    """The count slowing the median case by `target`: linear between the measured counts around it (0 costs 0)."""
    points = [(0, 0.0)] + sorted(measured.items())
    for (n0, s0), (n1, s1) in zip(points, points[1:]):
        if s1 >= target:
            if s1 <= s0:
                return max(1, n1)
            return max(1, round(n0 + (n1 - n0) * (target - s0) / (s1 - s0)))
    return None


def calibrate(run_with_counts, metric, targets, per_run=5, limit=1 << 16):
    """`run_with_counts(list_of_counts) -> results.json doc` runs the matrix once with every count in the list (0
    first) in the same rounds. Returns ({target: count}, {count: measured median slowdown})."""
    measured = {}
    n = 1
    while True:
        batch = [n << i for i in range(per_run)]
        measured.update(slowdowns_in_run(run_with_counts([0] + batch), batch, metric))
        if max(measured.values()) >= max(targets):
            break
        n = batch[-1] * 2
        if n > limit:
            sys.exit(f"calibration: {batch[-1]} injected iterations slowed the median case by only "
                     f"{100 * max(measured.values()):.2f}% ({metric} time); frames too small for fragment work to "
                     "show (a GPU-sized matrix: CI_MATRIX_SIZE=gpu)")
    return {t: interpolate(measured, t) for t in targets}, measured


def describe(measured, metric):
    return f"{metric} time, median case: " + ", ".join(f"{n}: {100 * s:+.2f}%" for n, s in sorted(measured.items()))
