#!/usr/bin/python3
"""How sensitive, and how trustworthy, is `omnishadow compare` on this machine? A benchmark, not a test.

Runs the CI matrix (scripts/ci/ci_matrix.sh) once in each arm per trial, in a shuffled order: a base run, the
same build again, and the same build with injected fragment work (--inject-fragment-work) calibrated on this device,
in the metric tested (scripts/experiments/calibration.py: doubling), to slow the median case by each of --slowdowns
(default 5% and 10%). Every arm is compared with its trial's base run by `omnishadow compare`; the decisions are
then re-derived for a grid of (alpha, minimum effect) gates from the Holm-adjusted p-values and changes it reports.
Writes sensitivity.json and sensitivity.md: false-alarm rate (same build against itself), detection rates per
slowdown, per gate; and the smallest gate meeting <= 1% false alarms.

With --judge P the report ends in a verdict line per design, `Verdict (...): PASS` or `FAIL`: PASS when some gate
keeps false alarms at or under 1% of cases and flags at least 90% of the cases that the P% arm slowed by at least P%
(each case's slowdown: its median change over all trials). With --metric gpu and CI_MATRIX_SIZE=gpu this is issue
23's target on a GPU: a 2% slowdown found at <= 1% false alarms (scripts/gpu_acceptance.sh precision).
--budget-s S starts no trial that would end after S seconds (at least two trials run).

With --alternate R each arm's sample is pooled from R separate runs of 9/R repetitions, alternated with the
base's runs (base, arm, base, arm, ...), so that machine-wide slow spells hit both sides alike: the design to
use when comparing two builds on a shared machine.

With --precision P the trials also run a second design, interleaved with the fixed one in the same trials:
adaptive repetitions (`run --precision P`, at least --min-repetitions, at most --max-repetitions per case), and
the report sets the two side by side: repetitions spent per run, false alarms and detections at the same gate.

With --metric cpu the test runs on the process's CPU time per frame (all threads; on llvmpipe the rendering work
itself) instead of frame wall time.

Usage: scripts/experiments/sensitivity.py [--trials 20] [--alternate R] [--repetitions N] [--metric wall|cpu|gpu] [--out DIR]
                              [--write-gate] [--precision P [--min-repetitions M] [--max-repetitions C]]
                              [--slowdowns 5,10] [--judge P] [--budget-s S] [--extra "run arguments"]
--write-gate stores the recommended gate in results/baselines/<device key>/gate.json for scripts/ci/ci_compare.sh.
"""
import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
import shlex
import time

import calibration

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BINARY = os.environ.get("OMNISHADOW_BIN") or os.path.join(ROOT, "build", "release", "omnishadow")
ALPHAS = [0.01, 0.05]
EFFECTS = [0.0, 0.005, 0.01, 0.015, 0.02, 0.03, 0.05, 0.075, 0.10, 0.15, 0.25, 0.5]


EXTRA = []  # --extra: more `run` arguments for every run (e.g. --warmup-ms)


def run_matrix(out, injected, repetitions=9, extra=()):
    cmd = ["bash", os.path.join(ROOT, "scripts", "ci", "ci_matrix.sh"), out, "--no-images", "--no-accuracy",
           f"--inject-fragment-work={injected}", f"--benchmark_repetitions={repetitions}", *EXTRA, *extra]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"sensitivity: {' '.join(cmd)} failed:\n{done.stderr[-2000:]}")


METRIC = "wall"


def compare(base, new, out):
    # alpha 0.5, effect 0: the raw material (adjusted p, change) for re-deciding under every gate below.
    cmd = [BINARY, "compare", base, new, "--alpha", "0.5", "--min-effect", "0", "--metric", METRIC, "--out", out]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode not in (0, 1):
        sys.exit(f"sensitivity: compare failed: {done.stderr}")
    with open(os.path.join(out, "comparison.json")) as f:
        return json.load(f)["cases"]


def pool(runs, out):
    """One results.json whose benchmark entries are all the runs' repetitions: compare pools them per case."""
    with open(os.path.join(runs[0], "results.json")) as f:
        doc = json.load(f)
    for run in runs[1:]:
        with open(os.path.join(run, "results.json")) as f:
            doc["benchmarks"].extend(json.load(f)["benchmarks"])
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(doc, f)
    return out


def calibrate(work_dir, targets):
    """Injected iterations per target slowdown of the median case, found by doubling in this metric."""
    def run_with_counts(counts):
        path = os.path.join(work_dir, "cal-" + "-".join(str(n) for n in counts[1:]))
        run_matrix(path, ",".join(str(n) for n in counts))
        with open(os.path.join(path, "results.json")) as f:
            return json.load(f)
    return calibration.calibrate(run_with_counts, METRIC, targets)


def repetitions_spent(run):
    with open(os.path.join(run, "results.json")) as f:
        doc = json.load(f)
    return sum(c.get("timing", {}).get("repetitions", 0) for c in doc["omnishadow"]["cases"])


def choose_gate(grid, max_false_alarms=0.01):
    """The gate CI may trust: of the grid's (alpha, minimum effect) rows whose false-alarm rate per case is at most
    `max_false_alarms`, the one with the smallest minimum effect (then the largest alpha); None when no row is."""
    ok = [r for r in grid if r["same"]["case_rate"] <= max_false_alarms]
    return min(ok, key=lambda r: (r["min_effect"], -r["alpha"])) if ok else None


def write_gate_file(path, metric, gate, trials):
    """results/baselines/<key>/gate.json, as `omnishadow compare --gate` reads it (metric, alpha, min_effect)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    doc = {"metric": metric, "alpha": gate["alpha"], "min_effect": gate["min_effect"],
           "false_alarm_case_rate": gate["same"]["case_rate"], "trials": trials}
    for arm in slow_arms(gate):
        doc[f"detect_{arm[4:]}_case_rate"] = gate[arm]["case_rate"]
    with open(path + ".tmp", "w") as f:
        json.dump(doc, f, indent=2)
    os.replace(path + ".tmp", path)


def slow_arms(row):
    """The arms with injected work in a grid row or arm map, in their order: slow2, slow5, ..."""
    return [k for k in row if k.startswith("slow")]


def case_slowdowns(trials):
    """Per case id: its median change over the trials' comparisons (the best estimate of what the arm did to it)."""
    changes = {}
    for trial in trials:
        for c in trial:
            changes.setdefault(c["id"], []).append(c["change"])
    return {k: statistics.median(v) for k, v in changes.items()}


def verdict(outcomes, grid, percent, max_false_alarms=0.01, min_detection=0.90):
    """PASS when a gate with <= max_false_alarms per case flags >= min_detection of the cases the P% arm slowed by
    at least P%. Returns (passed, one line saying why)."""
    arm = f"slow{percent:g}"
    slowed = {k for k, v in case_slowdowns(outcomes[arm]).items() if v >= percent / 100}
    if not slowed:
        return False, f"no case slowed by {percent:g}% or more in the {arm} arm: calibration missed"
    best = None
    for row in grid:
        if row["same"]["case_rate"] > max_false_alarms:
            continue
        hits = [decide(c, row["alpha"], row["min_effect"]) and c["change"] > 0
                for trial in outcomes[arm] for c in trial if c["id"] in slowed]
        rate = sum(hits) / len(hits)
        if best is None or rate > best[0]:
            best = (rate, row)
    if best is None:
        return False, f"no gate keeps false alarms at or under {100 * max_false_alarms:g}% of cases"
    rate, row = best
    return rate >= min_detection, (
        f"at alpha {row['alpha']}, minimum effect {100 * row['min_effect']:.1f}%: false alarms "
        f"{100 * row['same']['case_rate']:.1f}% of cases, {100 * rate:.0f}% of the {len(slowed)} cases slowed by >= "
        f"{percent:g}% flagged (target: >= {100 * min_detection:.0f}% at <= {100 * max_false_alarms:g}% false alarms)")



def decide(case, alpha, effect):
    return case["p_adjusted"] < alpha and abs(case["change"]) > effect


def rates(outcomes, arms, alpha, effect):
    row = {"alpha": alpha, "min_effect": effect}
    for arm in arms:
        cases = [c for trial in outcomes[arm] for c in trial]
        flagged = [c for c in cases if decide(c, alpha, effect) and (arm == "same" or c["change"] > 0)]
        runs_flagged = sum(any(decide(c, alpha, effect) for c in trial) for trial in outcomes[arm])
        row[arm] = {"case_rate": len(flagged) / len(cases), "run_rate": runs_flagged / len(outcomes[arm])}
    return row


def run_trial(args, trial, arms, designs, rng, spent):
    """One trial: per design, a base run and one run per arm (alternated or shuffled); returns compared cases."""
    out = {}
    for design, (repetitions, extra) in designs.items():
        tag = f"t{trial:02d}" + ("" if design == "fixed" else f"-{design}")
        runs = {}
        if args.alternate <= 1:
            order = ["base"] + list(arms)
            rng.shuffle(order)  # no arm always runs first or last: drift must not look like an effect
            for arm in order:
                runs[arm] = os.path.join(args.out, f"{tag}-{arm}")
                run_matrix(runs[arm], 0 if arm == "base" else arms[arm], repetitions, extra)
                spent[design].append(repetitions_spent(runs[arm]))
            bases = {arm: runs["base"] for arm in arms}
        else:
            bases = {}
            reps = max(1, repetitions // args.alternate)
            for arm in arms:
                pair = {"base": [], arm: []}
                for r in range(args.alternate):
                    for side in (["base", arm] if r % 2 == 0 else [arm, "base"]):
                        path = os.path.join(args.out, f"{tag}-{arm}-{side}-{r}")
                        run_matrix(path, 0 if side == "base" else arms[arm], reps, extra)
                        pair[side].append(path)
                bases[arm] = pool(pair["base"], os.path.join(args.out, f"{tag}-{arm}-base"))
                runs[arm] = pool(pair[arm], os.path.join(args.out, f"{tag}-{arm}-pooled"))
                spent[design].append(repetitions_spent(runs[arm]))
        out[design] = {arm: compare(bases[arm], runs[arm], os.path.join(runs[arm], "compare")) for arm in arms}
    return out


def design_table(designs, grids, spent, gate):
    """The designs side by side at the fixed design's recommended gate and at each one's own."""
    slow = slow_arms(grids[next(iter(designs))][0])
    md = ["\n## Designs compared (same trials, interleaved)\n",
          "| design | repetitions per run (mean) | gate | false alarms (cases) | "
          + " | ".join(f"detect {a[4:]}% (cases)" for a in slow) + " |", "|---|---|---|---|" + "---|" * len(slow)]
    for design in designs:
        own = [r for r in grids[design] if r["same"]["case_rate"] <= 0.01]
        own_gate = min(own, key=lambda r: (r["min_effect"], -r["alpha"])) if own else None
        for label, g in (("fixed design's", gate), ("its own", own_gate)):
            if g is None:
                continue
            row = next(r for r in grids[design] if r["alpha"] == g["alpha"] and r["min_effect"] == g["min_effect"])
            md.append(f"| {design} | {statistics.mean(spent[design]):.0f} | {label}: alpha {g['alpha']}, "
                      f"{100 * g['min_effect']:.1f}% | {100 * row['same']['case_rate']:.1f}% | "
                      + " | ".join(f"{100 * row[a]['case_rate']:.1f}%" for a in slow) + " |")
    return md


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--out", default=os.path.join(ROOT, "results", time.strftime("sensitivity-%Y%m%d-%H%M%S")))
    parser.add_argument("--write-gate", action="store_true")
    parser.add_argument("--alternate", type=int, default=1, help="runs per arm, alternated with the base's")
    parser.add_argument("--repetitions", type=int, default=9, help="repetitions per side (split over the runs)")
    parser.add_argument("--metric", choices=["wall", "cpu", "gpu"], default="wall",
                        help="time the U-test runs on (gpu: timer queries, CI_MATRIX_SIZE=gpu on a GPU)")
    parser.add_argument("--slowdowns", default="5,10", help="percent slowdowns of the injected arms")
    parser.add_argument("--judge", type=float, help="end in a PASS/FAIL verdict for this slowdown (one of --slowdowns)")
    parser.add_argument("--budget-s", type=float, default=0, help="start no trial that would end after this")
    parser.add_argument("--extra", default="", help="more `run` arguments for every run")
    parser.add_argument("--frames", type=int, default=3, help="timed frames per repetition (CI matrix: 3)")
    parser.add_argument("--precision", type=float, help="also run the adaptive design: run --precision P")
    parser.add_argument("--min-repetitions", type=int, default=7, help="adaptive design: fewest per case")
    parser.add_argument("--max-repetitions", type=int, default=15, help="adaptive design: the cap per case")
    args = parser.parse_args()
    global METRIC, BINARY
    METRIC = args.metric
    EXTRA[:] = shlex.split(args.extra)
    percents = [float(p) for p in args.slowdowns.split(",")]
    if args.judge is not None and args.judge not in percents:
        sys.exit(f"sensitivity: --judge {args.judge:g} is not one of --slowdowns {args.slowdowns}")
    os.environ["CI_MATRIX_FRAMES"] = str(args.frames)
    if not os.path.exists(BINARY):
        sys.exit(f"sensitivity: {BINARY} missing; run scripts/build.sh first")
    os.makedirs(args.out, exist_ok=True)
    # A copy of the binary: a rebuild while the trials run must not change (or break) what they measure.
    BINARY = shutil.copy2(BINARY, os.path.join(args.out, "omnishadow"))
    os.environ["OMNISHADOW_BIN"] = BINARY
    started = time.time()

    counts, measured = calibrate(args.out, [p / 100 for p in percents])
    print("calibration (" + calibration.describe(measured, METRIC) + "): "
          + ", ".join(f"+{p:g}% = {counts[p / 100]}" for p in percents) + " iterations", flush=True)
    arms = {"same": 0, **{f"slow{p:g}": counts[p / 100] for p in percents}}
    designs = {"fixed": (args.repetitions, ())}
    if args.precision:
        designs[f"precision{args.precision:g}"] = (
            args.min_repetitions, ("--precision", str(args.precision), "--max-repetitions", str(args.max_repetitions),
                                   "--precision-metric", args.metric))
    outcomes = {d: {arm: [] for arm in arms} for d in designs}  # per design, arm, trial: compared cases
    spent = {d: [] for d in designs}  # repetitions per run (all cases)
    rng = random.Random(12345)
    trials_started = time.time()
    for trial in range(args.trials):
        per_trial = (time.time() - trials_started) / trial if trial else 0
        if args.budget_s and trial >= 2 and time.time() - started + per_trial > args.budget_s:
            print(f"budget: {trial} trials fit in {args.budget_s:g} s", flush=True)
            break
        for design, per_arm in run_trial(args, trial, arms, designs, rng, spent).items():
            for arm, cases in per_arm.items():
                outcomes[design][arm].append(cases)
        print(f"trial {trial + 1}/{args.trials} done ({time.time() - started:.0f}s)", flush=True)
    trials_done = len(outcomes["fixed"]["same"])

    grids = {d: [rates(outcomes[d], arms, a, e) for a in ALPHAS for e in EFFECTS] for d in designs}
    grid = grids["fixed"]
    realized = {arm: statistics.median(c["change"] for trial in outcomes["fixed"][arm] for c in trial) for arm in arms}
    gate = choose_gate(grid)
    result = {"metric": METRIC, "trials": trials_done, "calibration": {str(n): v for n, v in measured.items()}, "alternate": args.alternate, "repetitions": args.repetitions,
              "cases_per_run": len(outcomes["fixed"]["same"][0]), "injected_iterations": arms,
              "realized_median_change": realized, "grid": grid,
              "recommended_gate": gate, "seconds": time.time() - started,
              "designs": {d: {"repetitions_per_run": spent[d], "grid": grids[d], "options": list(designs[d][1]),
                              "min_repetitions": designs[d][0]} for d in designs}}
    with open(os.path.join(args.out, "sensitivity.json"), "w") as f:
        json.dump(result, f, indent=2)

    design = (f"{args.repetitions} interleaved repetitions in one run per side" if args.alternate <= 1 else
              f"{args.alternate} alternating runs of {max(1, args.repetitions // args.alternate)} repetitions per "
              "side, pooled")
    md = [f"# Regression-detection sensitivity\n\n{trials_done} trials x {result['cases_per_run']} cases (CI matrix, {args.frames} frames per repetition, "
          f"{design}; metric: {'process CPU time' if METRIC == 'cpu' else 'wall time'} per frame); every run a "
          "separate process. Realized median change: "
          + ", ".join(f"{a} {100 * v:+.1f}%" for a, v in realized.items()) + ".\n",
          f"Injected iterations: {', '.join(f'{a} {n}' for a, n in arms.items() if n)} (calibration, "
          f"{calibration.describe(measured, METRIC)}).\n",
          "| alpha | min effect | false alarms (cases) | false alarms (runs) | "
          + " | ".join(f"detect {a[4:]}% (cases) | detect {a[4:]}% (runs)" for a in arms if a != "same") + " |",
          "|---|---|---|---|" + "---|---|" * (len(arms) - 1)]
    for r in grid:
        md.append(f"| {r['alpha']} | {100 * r['min_effect']:.1f}% | {100 * r['same']['case_rate']:.1f}% | "
                  f"{100 * r['same']['run_rate']:.0f}% | "
                  + " | ".join(f"{100 * r[a]['case_rate']:.1f}% | {100 * r[a]['run_rate']:.0f}%"
                               for a in arms if a != "same") + " |")
    md.append("\nRecommended gate (smallest minimum effect with <= 1% false alarms per case): "
              + (f"alpha {gate['alpha']}, minimum effect {100 * gate['min_effect']:.1f}%" if gate else "none"))
    if len(designs) > 1:
        md += design_table(designs, grids, spent, gate)
    if args.judge is not None:
        md.append("")
        for d in designs:
            passed, why = verdict(outcomes[d], grids[d], args.judge)
            result["designs"][d]["verdict"] = {"passed": passed, "why": why}
            md.append(f"Verdict ({d}, {args.judge:g}% slowdown, {METRIC} time): {'PASS' if passed else 'FAIL'}: {why}")
        with open(os.path.join(args.out, "sensitivity.json"), "w") as f:
            json.dump(result, f, indent=2)
    with open(os.path.join(args.out, "sensitivity.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))

    if args.write_gate and gate:
        key = subprocess.run([BINARY, "device-key", os.path.join(args.out, "cal-1-2-4-8")], capture_output=True,
                             text=True).stdout.split()[0]
        path = os.path.join(ROOT, "results", "baselines", key, "gate.json")
        write_gate_file(path, METRIC, gate, trials_done)
        print(f"gate written to {path}")


if __name__ == "__main__":
    main()
