#!/usr/bin/python3
"""Fixed against adaptive repetitions, measured where each design's own precision is what counts: in
one run. A benchmark, not a test.

scripts/experiments/sensitivity.py compares separate runs, as CI compares builds; on a shared machine the run-to-run drift (here
a run-wide factor of up to 2x, and 8% per case beyond it) swamps any within-run precision, so no design can show a
5% slowdown there. This script holds the designs against each other inside one run instead, the way a user
compares variants: every run of the CI matrix carries each case four times in the same rounds,
`--inject-fragment-work 0,N --replicas 2`, with N calibrated on this device in the metric tested
(scripts/experiments/calibration.py: doubling) to slow the median case by --target percent (default 5). Per trial
and design, `omnishadow compare` (U test, Holm over the 24 cases) judges the A/A pair (inj0/rep0 against inj0/rep1:
false alarms) and the two A/B pairs (inj0/repK against injN/repK: detections).

Designs (interleaved in every trial, order alternating): per fixed count R, `--benchmark_repetitions=R`; per
--precision P, `--precision P --max-repetitions <largest R>` from --min-repetitions. Reports, per gate (alpha, minimum effect), false alarms
and detections per design, the repetitions each spent per run, and at the smallest gate where every design has
<= 1% false alarms, the repetitions saved.

Usage: scripts/experiments/sensitivity_same_run.py [--trials 10] [--repetitions 24] [--precision 2] [--min-repetitions 7]
                                       [--frames 12] [--inject N | --target 5] [--metric wall|cpu|gpu] [--out DIR]
                                       [--judge] [--budget-s S] [--extra "run arguments"] [--docs]
--docs writes docs/sensitivity-same-run.md. --judge ends the report in a verdict line per design (as
sensitivity.py --judge: PASS when a gate with <= 1% false alarms flags >= 90% of the cases slowed by >= --target).
--budget-s S starts no trial that would end after S seconds (at least two run).
"""
import argparse
import json
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import time

import calibration
import sensitivity  # its compare() (raw adjusted p and change per case), decide() and verdict()
from sensitivity import compare, decide

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ALPHAS = [0.01, 0.05]
EFFECTS = [0.0, 0.005, 0.01, 0.015, 0.02, 0.03, 0.04, 0.05]


MATRIX = []  # --matrix: the axes of another matrix instead of the CI matrix's


def run_matrix(out, injected, extra, replicas=2):
    """The CI matrix (or --matrix's) with every case once per value in `injected` (and per replica), in the same
    rounds."""
    if MATRIX:
        head = [sensitivity.BINARY, "run", *MATRIX, "--frames", os.environ["CI_MATRIX_FRAMES"], "--warmup", "1",
                "--light-radius", "0", "--benchmark_enable_random_interleaving=true", "--out", out]
    else:
        head = ["bash", os.path.join(ROOT, "scripts", "ci", "ci_matrix.sh"), out]
    cmd = [*head, "--no-images", "--no-accuracy", "--inject-fragment-work=" + ",".join(str(n) for n in injected),
           "--replicas", str(replicas), *sensitivity.EXTRA, *extra]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"sensitivity_same_run: {' '.join(cmd)} failed:\n{done.stderr[-2000:]}")
    with open(os.path.join(out, "results.json")) as f:
        return json.load(f)


def arm(doc, suffix, out, keep=None):
    """The cases whose ids end in /<suffix>, renamed without it: a run folder `omnishadow compare` reads. With
    `keep` (case id without the suffix -> count), only each case's first `count` repetitions, in the order they
    ran: what a run that had stopped there would hold (scripts/experiments/repetition_replay.py)."""
    tail = "/" + suffix
    part = json.loads(json.dumps(doc))
    part["benchmarks"] = []
    taken = {}
    for b in doc["benchmarks"]:
        case = b.get("omnishadow_case", "")
        if b.get("run_type") == "iteration" and case.endswith(tail):
            base = case[: -len(tail)]
            taken[base] = taken.get(base, 0) + 1
            if keep is not None and taken[base] > keep(base):
                continue
            b = dict(b)
            for key in ("omnishadow_case", "name", "run_name"):
                if isinstance(b.get(key), str):
                    b[key] = b[key].replace(tail, "")
            part["benchmarks"].append(b)
    part["omnishadow"]["cases"] = []
    for c in doc["omnishadow"]["cases"]:
        if c["id"].endswith(tail):
            c = dict(c)
            c["id"] = c["id"][: -len(tail)]
            part["omnishadow"]["cases"].append(c)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(part, f)
    return out


def calibrate(work, target):
    """Iterations of injected work that slow the median case by `target` in the metric tested: doubling, several
    counts per run (scripts/experiments/calibration.py)."""
    def run_with_counts(counts):
        return run_matrix(os.path.join(work, "cal-" + "-".join(str(n) for n in counts[1:])), counts,
                          ["--benchmark_repetitions=9"], replicas=1)
    counts, measured = calibration.calibrate(run_with_counts, sensitivity.METRIC, [target])
    return counts[target], measured


def repetitions_spent(doc):
    return sum(c.get("timing", {}).get("repetitions", 0) for c in doc["omnishadow"]["cases"])


def rates(trials, alpha, effect):
    aa = [c for t in trials for c in t["aa"]]
    ab = [c for t in trials for pair in t["ab"] for c in pair]
    return {"alpha": alpha, "min_effect": effect,
            "false_alarms": sum(decide(c, alpha, effect) for c in aa) / len(aa),
            "detect": sum(decide(c, alpha, effect) and c["change"] > 0 for c in ab) / len(ab)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=10)
    parser.add_argument("--repetitions", default="24",
                        help="comma list of fixed counts (one fixed design each); the largest is the adaptive cap")
    parser.add_argument("--precision", default="2", help="comma list of adaptive targets P (percent)")
    parser.add_argument("--min-repetitions", type=int, default=7)
    parser.add_argument("--frames", type=int, default=12, help="timed frames per repetition")
    parser.add_argument("--inject", type=int, default=0,
                        help="iterations of injected work for the A/B arms (default: calibrated to --target first)")
    parser.add_argument("--target", type=float, default=5, help="percent slowdown the calibration aims at")
    parser.add_argument("--metric", choices=["wall", "cpu", "gpu"], default="wall",
                        help="what --precision judges (--precision-metric) and compare tests (--metric): frame wall "
                             "time, process CPU time or GPU (timer query) time per frame")
    parser.add_argument("--judge", action="store_true", help="end in a PASS/FAIL verdict per design")
    parser.add_argument("--budget-s", type=float, default=0, help="start no trial that would end after this")
    parser.add_argument("--extra", default="", help="more `run` arguments for every run")
    parser.add_argument("--matrix", default="",
                        help="the matrix's axes instead of the CI matrix's, e.g. \"--backend gl --scene room --cube "
                             "128,512 --frame 160x120,640x480\" (cases unlike in noise)")
    parser.add_argument("--out", default="/tmp/omnishadow-sensitivity-same-run")
    parser.add_argument("--docs", action="store_true")
    args = parser.parse_args()
    if not os.path.exists(sensitivity.BINARY):
        sys.exit(f"sensitivity_same_run: {sensitivity.BINARY} missing; run scripts/build.sh first")
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    # A copy: a rebuild must not change what is measured; sensitivity.compare() runs it too.
    sensitivity.BINARY = shutil.copy2(sensitivity.BINARY, os.path.join(args.out, "omnishadow"))
    os.environ["OMNISHADOW_BIN"] = sensitivity.BINARY
    os.environ["CI_MATRIX_FRAMES"] = str(args.frames)
    MATRIX[:] = shlex.split(args.matrix)
    sensitivity.METRIC = args.metric
    sensitivity.EXTRA[:] = shlex.split(args.extra)
    started = time.time()
    if args.inject:
        n5, slow = args.inject, {}
    else:
        n5, slow = calibrate(args.out, args.target / 100)
        print(f"calibration ({calibration.describe(slow, args.metric)}); taking {n5}", flush=True)
    counts = sorted(int(r) for r in args.repetitions.split(","))
    designs = {f"fixed{r}": [f"--benchmark_repetitions={r}"] for r in counts}
    for p in args.precision.split(","):
        designs[f"precision{p}"] = [f"--benchmark_repetitions={args.min_repetitions}", "--precision", p,
                                    "--precision-metric", args.metric,
                                    "--max-repetitions", str(counts[-1])]
    outcomes = {d: [] for d in designs}
    spent = {d: [] for d in designs}
    trials_started = time.time()
    for trial in range(args.trials):
        per_trial = (time.time() - trials_started) / trial if trial else 0
        if args.budget_s and trial >= 2 and time.time() - started + per_trial > args.budget_s:
            print(f"budget: {trial} trials fit in {args.budget_s:g} s", flush=True)
            break
        order = list(designs) if trial % 2 == 0 else list(designs)[::-1]
        for d in order:
            run = os.path.join(args.out, f"t{trial:02d}-{d}")
            doc = run_matrix(run, [0, n5], designs[d])
            spent[d].append(repetitions_spent(doc) / 4)  # per copy of the matrix: what one run of it costs
            parts = {s: arm(doc, s, os.path.join(run, s.replace("/", "-")))
                     for s in ("inj0/rep0", "inj0/rep1", f"inj{n5}/rep0", f"inj{n5}/rep1")}
            outcomes[d].append({
                "aa": compare(parts["inj0/rep0"], parts["inj0/rep1"], os.path.join(run, "cmp-aa")),
                "ab": [compare(parts[f"inj0/rep{k}"], parts[f"inj{n5}/rep{k}"], os.path.join(run, f"cmp-ab{k}"))
                       for k in (0, 1)]})
        print(f"trial {trial + 1}/{args.trials} done ({time.time() - started:.0f} s)", flush=True)

    grids = {d: [rates(outcomes[d], a, e) for a in ALPHAS for e in EFFECTS] for d in designs}
    first = next(iter(designs))
    common = [g for g in grids[first]
              if all(next(r for r in grids[d] if r["alpha"] == g["alpha"] and r["min_effect"] == g["min_effect"])
                     ["false_alarms"] <= 0.01 for d in designs)]
    gate = min(common, key=lambda r: (r["min_effect"], -r["alpha"])) if common else None
    realized_change = statistics.median(c["change"] for t in outcomes[first] for pair in t["ab"] for c in pair)
    cases = len(outcomes[first][0]["aa"])
    md = ["# Fixed against adaptive repetitions, in one run\n",
          f"`scripts/experiments/sensitivity_same_run.py --trials {len(outcomes[first])} --repetitions {args.repetitions} --precision "
          f"{args.precision} --min-repetitions {args.min_repetitions} --frames {args.frames} --metric {args.metric}"
          + (f" --target {args.target:g}" if args.target != 5 else "")
          + (f" --matrix \"{args.matrix}\"" if args.matrix else "") + f"`: the {'' if args.matrix else 'CI '}matrix "
          f"({cases} cases) four times in the same rounds (`--inject-fragment-work 0,{n5} --replicas 2`; {n5} iterations "
          f"slowed the median case by {100 * realized_change:.1f}% in the {first} design's runs). Per trial and design "
          f"one A/A comparison (false alarms) and two A/B comparisons (detections) of {cases} cases each; "
          f"{time.time() - started:.0f} s.\n",
          f"| design | repetitions per matrix (mean) | gate | false alarms (cases) | detect {args.target:g}% (cases) |",
          "|---|---|---|---|---|"]
    rows = []
    for d in designs:
        if gate is None:
            break
        r = next(x for x in grids[d] if x["alpha"] == gate["alpha"] and x["min_effect"] == gate["min_effect"])
        rows.append((d, statistics.mean(spent[d]), r))
        md.append(f"| {d} | {statistics.mean(spent[d]):.0f} | alpha {gate['alpha']}, {100 * gate['min_effect']:.0f}% | "
                  f"{100 * r['false_alarms']:.1f}% | {100 * r['detect']:.1f}% |")
    md.append(f"\nEvery gate (false alarms / detect {args.target:g}%, per case):\n")
    md.append("| alpha | min effect | " + " | ".join(designs) + " |")
    md.append("|---|---|" + "---|" * len(designs))
    for i, g in enumerate(grids[first]):
        md.append(f"| {g['alpha']} | {100 * g['min_effect']:.0f}% | " + " | ".join(
            f"{100 * grids[d][i]['false_alarms']:.1f}% / {100 * grids[d][i]['detect']:.1f}%" for d in designs) + " |")
    verdicts = {}
    if args.judge:
        md.append("")
        slow_arm = f"slow{args.target:g}"
        for d in designs:
            # sensitivity.verdict's shapes: the A/B comparisons as the arm's trials, the A/A rate as "same".
            passed, why = sensitivity.verdict(
                {slow_arm: [pair for t in outcomes[d] for pair in t["ab"]]},
                [{"alpha": g["alpha"], "min_effect": g["min_effect"], "same": {"case_rate": g["false_alarms"]}}
                 for g in grids[d]], args.target)
            verdicts[d] = {"passed": passed, "why": why}
            md.append(f"Verdict ({d}, {args.target:g}% slowdown, {args.metric} time, one run): "
                      f"{'PASS' if passed else 'FAIL'}: {why}")
    text = "\n".join(md) + "\n"
    print(text)
    with open(os.path.join(args.out, "sensitivity_same_run.json"), "w") as f:
        json.dump({"n5": n5, "calibration": slow, "designs": designs, "spent": spent, "grids": grids, "gate": gate,
                   "realized_change": realized_change, "verdicts": verdicts, "trials": len(outcomes[first])},
                  f, indent=2)
    with open(os.path.join(args.out, "sensitivity_same_run.md"), "w") as f:
        f.write(text)
    if args.docs:
        with open(os.path.join(ROOT, "docs", "sensitivity-same-run.md"), "w") as f:
            f.write(text)
    print(f"every stopping rule on the {counts[-1]}-repetition runs' own samples: "
          f"scripts/experiments/repetition_replay.py {args.out}")


if __name__ == "__main__":
    main()
