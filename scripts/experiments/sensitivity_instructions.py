#!/usr/bin/python3
"""How well the deterministic work gate separates noise from real slowdowns. A benchmark, not a test.

Runs scripts/ci/instruction_counts.sh K times for the same build (false alarms: every pair of those runs compared
case by case) and once with --inject-fragment-work calibrated to +5% and once to +10% of the median case's
instructions (detection: each compared with the first same-build run). A case is flagged when its instructions
per frame changed by more than the threshold (scripts/ci/instruction_counts.py, default 0.2%). Writes
sensitivity-instructions.json and .md to --out.

Usage: scripts/experiments/sensitivity_instructions.py [--runs 3] [--threshold 0.002] [--out DIR]
"""
import argparse
import itertools
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def counts(out, injected):
    cmd = ["bash", os.path.join(ROOT, "scripts", "ci", "instruction_counts.sh"), out, f"--inject-fragment-work={injected}"]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"sensitivity_instructions: {' '.join(cmd)} failed:\n{done.stderr[-2000:]}")
    with open(os.path.join(out, "instructions.json")) as f:
        return json.load(f)["instructions_per_frame"]


def changes(a, b):
    return [b[k] / a[k] - 1 for k in a if k in b and a[k]]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threshold", type=float, default=0.002)
    parser.add_argument("--out", default=os.path.join(ROOT, "results",
                                                      time.strftime("sensitivity-instructions-%Y%m%d-%H%M%S")))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    same = [counts(os.path.join(args.out, f"same-{i}"), 0) for i in range(max(2, args.runs))]
    probe = counts(os.path.join(args.out, "probe-40"), 40)
    per_iteration = statistics.median(changes(same[0], probe)) / 40
    n5, n10 = max(1, round(0.05 / per_iteration)), max(1, round(0.10 / per_iteration))
    slow = {"slow5": counts(os.path.join(args.out, f"slow-{n5}"), n5),
            "slow10": counts(os.path.join(args.out, f"slow-{n10}"), n10)}
    noise = [c for a, b in itertools.combinations(same, 2) for c in changes(a, b)]
    result = {
        "threshold": args.threshold, "same_build_runs": len(same), "cases": len(same[0]),
        "injected_iterations": {"slow5": n5, "slow10": n10}, "per_iteration_fraction": per_iteration,
        "false_alarm_rate": sum(abs(c) > args.threshold for c in noise) / len(noise),
        "same_build_max_abs_change": max(abs(c) for c in noise), "comparisons": len(noise),
        "seconds": time.time() - started,
    }
    for arm, data in slow.items():
        ch = changes(same[0], data)
        result[arm] = {"median_change": statistics.median(ch), "min_change": min(ch),
                       "detection_rate": sum(c > args.threshold for c in ch) / len(ch)}
    with open(os.path.join(args.out, "sensitivity-instructions.json"), "w") as f:
        json.dump(result, f, indent=2)
    md = (f"# Work-gate sensitivity (instructions per frame, callgrind)\n\n"
          f"{result['cases']} cases (CI matrix), threshold {100 * args.threshold:.2f}%.\n\n"
          f"- Same build, {len(same)} runs ({len(noise)} case comparisons): false alarms "
          f"{100 * result['false_alarm_rate']:.1f}%, largest change {100 * result['same_build_max_abs_change']:.3f}%.\n"
          f"- Injected +5% ({n5} iterations; median {100 * result['slow5']['median_change']:.2f}%, smallest "
          f"{100 * result['slow5']['min_change']:.2f}%): detected in {100 * result['slow5']['detection_rate']:.0f}% of cases.\n"
          f"- Injected +10% ({n10} iterations; median {100 * result['slow10']['median_change']:.2f}%, smallest "
          f"{100 * result['slow10']['min_change']:.2f}%): detected in {100 * result['slow10']['detection_rate']:.0f}% of cases.\n")
    with open(os.path.join(args.out, "sensitivity-instructions.md"), "w") as f:
        f.write(md)
    print(md)


if __name__ == "__main__":
    main()
