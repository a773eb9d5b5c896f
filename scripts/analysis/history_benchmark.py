#!/usr/bin/python3
"""How well does `scripts/analysis/history.py` find steps? A benchmark on synthetic histories shaped like real ones.

Noise: the relative run-to-run scatter of the same build's per-case median frame times in repeated runs of this
repository (RUN folders; e.g. the base and same-build runs of scripts/experiments/sensitivity.py), standardised and rescaled
to the level asked (default 2%), so that its shape (tails, skew) is the machine's. Each trial is a history of
--commits commits analysed after every commit, as CI would:
  detection:     a +5% step at a random commit of the middle third; found if the history places an alert within
                 3 commits of it; also, analysing after every commit, how many commits after the step it alerted;
  false alerts:  no step; alerts in the whole history, and distinct alerts raised by the analyses after every
                 commit (per 100 commits);
  after accept:  the step accepted at the commit its first alert named; the next 20 commits' analyses must
                 raise no alert.
Writes OUT/history-benchmark.json and, with --docs, docs/history-benchmark.md.

Usage: scripts/analysis/history_benchmark.py RUN... [--trials 200] [--noise 0.02] [--step 0.05] [--docs]
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
import changepoints  # noqa: E402
import history  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def residuals(runs):
    """log(value / the case's median over runs), pooled over cases: the machine's run-to-run noise."""
    per_case = {}
    for run in runs:
        for case_id, value in history.case_times(history.load(run)).items():
            per_case.setdefault(case_id, []).append(value)
    out = []
    for values in per_case.values():
        if len(values) >= 3:
            logs = np.log(values)
            out += list(logs - np.median(logs))
    if len(out) < 20:
        sys.exit(f"history_benchmark: {len(out)} residuals from {len(runs)} runs; give more repeated runs")
    return np.array(out)


def series(rng, noise, n, step_at=None, step=0.0):
    """Values of one case over n commits: 1 ms, times exp(resampled standardised noise), stepped at step_at."""
    v = np.exp(rng.choice(noise, n))
    if step_at is not None:
        v[step_at:] *= 1.0 + step
    return v


GATE = history.TIMING_GATE


def alerts(values, accepted_at=(), slower_only=False):
    """Alert indices in values, as history.py raises them (accepted steps silence alerts near them)."""
    return [s["index"] for s in history.persistent(values, list(accepted_at), history.timing_find)
            if not slower_only or s["step"] > 0]


def trial_detection(rng, noise, n, step, window=3):
    """A step at a random commit in the middle third. Returns (found in the full history within +-window,
    commits after the step until an analysis first placed an alert within +-window of it (None: never))."""
    at = int(rng.integers(n // 3, 2 * n // 3))
    v = series(rng, noise, n, at, step)
    found = any(abs(a - at) <= window for a in alerts(v))
    latency = next((end - at for end in range(at + 1, n + 1) if any(abs(a - at) <= window for a in alerts(v[:end]))),
                   None)
    return found, latency


def trial_false_alerts(rng, noise, n):
    """(alerts in the full history, distinct alerts raised by analyses after every commit)."""
    v = series(rng, noise, n)
    seen = []
    for end in range(8, n + 1):
        for a in alerts(v[:end]):
            if all(abs(a - s) > 1 for s in seen):
                seen.append(a)
    return len(alerts(v)), len(seen)


def trial_after_accept(rng, noise, n, step, quiet=20, window=3):
    """The (slower) step accepted where its first alert placed it, then `quiet` more commits analysed: (a repeat:
    an alert of a slowdown again, any alert at all). None when the step was never found."""
    at = int(rng.integers(n // 3, 2 * n // 3))
    v = series(rng, noise, n + quiet, at, step)
    for end in range(at + 1, n + 1):
        near = [a for a in alerts(v[:end]) if abs(a - at) <= window]
        if near:
            later = range(end + 1, end + quiet + 1)
            return (int(any(alerts(v[:e], [near[0]], slower_only=True) for e in later)),
                    int(any(alerts(v[:e], [near[0]]) for e in later)))
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--trials", type=int, default=200)
    parser.add_argument("--commits", type=int, default=100)
    parser.add_argument("--noise", type=float, default=0.02)
    parser.add_argument("--step", type=float, default=0.05)
    parser.add_argument("--out", default=os.path.join(ROOT, "results", time.strftime("history-benchmark-%Y%m%d-%H%M%S")))
    parser.add_argument("--docs", action="store_true")
    parser.add_argument("--source", default="repeated runs of the CI matrix on llvmpipe",
                        help="what the RUN folders are, for the report")
    args = parser.parse_args()
    raw = residuals(args.runs)
    measured = float(np.std(raw))
    noise = (raw - np.mean(raw)) / measured * args.noise  # the machine's shape, the level asked
    rng = np.random.default_rng(20261122)
    started = time.time()
    detections = [trial_detection(rng, noise, args.commits, args.step) for _ in range(args.trials)]
    latencies = [lat for _, lat in detections if lat is not None]
    false_alerts = [trial_false_alerts(rng, noise, args.commits) for _ in range(args.trials)]
    repeats = [r for r in (trial_after_accept(rng, noise, args.commits, args.step) for _ in range(args.trials))
               if r is not None]
    per_100 = 100 / args.commits
    result = {
        "runs": len(args.runs), "residuals": len(raw), "measured_noise": measured, "noise": args.noise,
        "step": args.step, "commits": args.commits, "trials": args.trials, "gate": history.TIMING_GATE,
        "accept_window": history.ACCEPT_WINDOW,
        "detected_within_3": sum(found for found, _ in detections) / args.trials,
        "alerted_within_3_commits_after": sum(lat is not None and lat <= 3 for _, lat in detections) / args.trials,
        "median_commits_until_alert": float(np.median(latencies)) if latencies else None,
        "false_alerts_per_100_commits": float(np.mean([f for f, _ in false_alerts])) * per_100,
        "false_alerts_per_100_commits_online": float(np.mean([o for _, o in false_alerts])) * per_100,
        "series_with_more_than_one_false_alert": sum(f > 1 for f, _ in false_alerts) / args.trials,
        "repeat_alerts_after_accept": float(np.mean([r for r, _ in repeats])) if repeats else None,
        "any_alert_after_accept": float(np.mean([a for _, a in repeats])) if repeats else None,
        "accepted_trials": len(repeats), "seconds": time.time() - started}
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "history-benchmark.json"), "w") as f:
        json.dump(result, f, indent=2)
    ok = (result["detected_within_3"] >= 0.9 and result["false_alerts_per_100_commits"] <= 1.0
          and (result["repeat_alerts_after_accept"] or 0.0) == 0.0)
    r = result
    md = [f"# History: change-point detection on synthetic histories\n",
          f"Generated by `scripts/analysis/history_benchmark.py RUN... --docs` ({args.trials} trials per row, {args.commits} "
          f"commits per history, analysed after every commit). Noise: the run-to-run scatter of {len(raw)} per-case "
          f"median frame times from {len(args.runs)} {args.source} (measured "
          f"{100 * measured:.1f}%), rescaled to {100 * args.noise:.0f}%. Gate: PELT penalty "
          f"{history.TIMING_GATE['penalty']} log n, Mann-Whitney alpha {history.TIMING_GATE['alpha']}, minimum "
          f"step {100 * history.TIMING_GATE['min_effect']:.0f}% (scripts/analysis/history.py).\n",
          "| figure | target | measured |", "|---|---|---|",
          f"| +{100 * args.step:.0f}% step placed within 3 commits of where it is | >= 90% of trials | "
          f"{100 * r['detected_within_3']:.1f}% |",
          f"| false alerts per history of 100 commits | <= 1 | {r['false_alerts_per_100_commits']:.2f} "
          f"(histories with more than one: {100 * r['series_with_more_than_one_false_alert']:.1f}%) |",
          f"| accepted step alerting again (a slowdown) in the next 20 commits | 0 | "
          + (f"{100 * r['repeat_alerts_after_accept']:.1f}% of {len(repeats)} trials (any alert, an improvement "
             f"included: {100 * r['any_alert_after_accept']:.1f}%) |" if repeats else "- |"),
          f"\nAnalysed after every commit, as CI would: the step alerted (within 3 commits of it) at most 3 commits "
          f"after it landed in {100 * r['alerted_within_3_commits_after']:.1f}% of trials, after a median of "
          f"{r['median_commits_until_alert']} commits; distinct false alerts over a history's 100 analyses: "
          f"{r['false_alerts_per_100_commits_online']:.2f} per 100 commits.",
          f"\nTargets {'met' if ok else 'NOT met'}."]
    text = "\n".join(md) + "\n"
    with open(os.path.join(args.out, "history-benchmark.md"), "w") as f:
        f.write(text)
    if args.docs:
        with open(os.path.join(ROOT, "docs", "history-benchmark.md"), "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
