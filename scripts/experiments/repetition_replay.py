#!/usr/bin/python3
"""Stopping rules replayed on recorded repetitions: how many repetitions a rule saves at equal false
alarms and detection, judged on the same samples, so that the comparison is paired instead of one noisy run against
another. A benchmark analysis, not a test.

Input: the folder of a `scripts/experiments/sensitivity_same_run.py` run. Its largest fixed design (`t*-fixed<R>`) recorded R
repetitions of every case in each of four arms (inj0/rep0, inj0/rep1, injN/rep0, injN/rep1), in the order the rounds
ran them. Any rule that stops at or before R can be replayed on those sequences: a fixed count n keeps each case's
first n repetitions; `--precision P` keeps them until the 95% interval of the median (the harness's order-statistic
interval, mirrored below) is within +-P%, from a minimum to the cap R. Each truncated arm goes through
`omnishadow compare` (U test, Holm over the cases) as the real designs do: A/A for false alarms, the two A/B pairs
for detections.

What a replay cannot show: in a real adaptive run the late rounds hold only the unfinished cases, so they run in a
different mix. The real precision designs in the same folder check that: the script replays each one's own rule on
its own samples (the stop count must equal what the harness did) and sets its measured detection beside the
replay's.

Usage: scripts/experiments/repetition_replay.py DIR [--precision 1.5,2,2.5,3,4] [--minimum 6,7,8] [--futility 0,2]
                                    [--metric wall|cpu|gpu] [--alpha 0.05]
Writes DIR/repetition_replay.json and DIR/repetition_replay_<metric>.md (docs/repetition-replay.md holds the
trials quoted in docs/guide.md).
"""
import argparse
import glob
import json
import math
import os
import random
import re
import statistics
import sys

import sensitivity
from sensitivity import compare, decide
from sensitivity_same_run import arm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def median_half_width(samples, confidence=0.95):
    """bench/run/repetition_policy.cpp median_interval(): the sign-test interval's half-width in % of the median, or
    None when the sample is too small for the confidence."""
    n = len(samples)
    s = sorted(samples)
    median = s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])
    tail, cdf, k = (1.0 - confidence) / 2.0, 0.0, 0
    for j in range(n):
        cdf += math.comb(n, j) / 2.0 ** n
        if cdf > tail:
            break
        k = j + 1
    if k == 0 or k > n + 1 - k or median <= 0:
        return None
    return 100.0 * max(median - s[k - 1], s[n - k] - median) / median


def stops(samples, precision, cap, futility=0.0):
    """Whether bench/run/repetition_policy.cpp needs_repetition() ends a case holding these samples (past its minimum).
    With `futility` F > 0 (not in the harness; explored here) a case also ends once even the cap could not bring
    its interval within F times the target (half-width * sqrt(n / cap) > F * P)."""
    n = len(samples)
    if n >= cap:
        return True
    hw = median_half_width(samples)
    if hw is not None and hw <= precision:
        return True
    return futility > 0 and hw is not None and hw * math.sqrt(n / cap) > futility * precision


def stop_count(samples, precision, minimum, cap, futility=0.0):
    """How many of these samples, in this order, a case under the rule would have run."""
    for n in range(minimum, min(cap, len(samples)) + 1):
        if stops(samples[:n], precision, cap, futility):
            return n
    return min(cap, len(samples))


# The per-repetition figures results.json holds per case, by metric (frame_gpu_ms: repetitions whose GPU timer
# passed its check only).
PER_REPETITION_KEY = {"wall": "frame_ms", "cpu": "frame_cpu_ms", "gpu": "frame_gpu_ms"}


def sequences(doc, key="frame_ms"):
    """Per full case id (with its /injN/repK suffix): the per-repetition frame times (`frame_ms` wall,
    `frame_cpu_ms` process CPU, `frame_gpu_ms` GPU timer), in the order they ran."""
    return {c["id"]: c["timing"]["per_repetition"][key] for c in doc["omnishadow"]["cases"]
            if c.get("timing", {}).get("per_repetition")}


def arms_of(doc):
    suffixes = sorted({re.search(r"inj\d+/rep\d+$", c["id"]).group(0) for c in doc["omnishadow"]["cases"]})
    base = [s for s in suffixes if s.startswith("inj0/")]
    heavy = [s for s in suffixes if not s.startswith("inj0/")]
    if len(base) != 2 or len(heavy) != 2:
        sys.exit(f"repetition_replay: expected arms inj0/rep0,1 and injN/rep0,1, found {suffixes}")
    return base, heavy


def judge(doc, counts, work):
    """Compare the arms truncated to `counts` (full case id -> repetitions kept): A/A and the two A/B outcomes, and
    the repetitions per copy of the matrix."""
    base, heavy = arms_of(doc)
    parts = {}
    for s in base + heavy:
        parts[s] = arm(doc, s, os.path.join(work, s.replace("/", "-")), keep=lambda case, s=s: counts[f"{case}/{s}"])
    return {"aa": compare(parts[base[0]], parts[base[1]], os.path.join(work, "cmp-aa")),
            "ab": [compare(parts[base[k]], parts[heavy[k]], os.path.join(work, f"cmp-ab{k}")) for k in (0, 1)],
            "spent": sum(counts.values()) / 4}


def trial_counts(outcome, alpha):
    """One trial's (repetitions per matrix, false alarms, A/A cases, detections, A/B cases) under the gate."""
    aa, ab = outcome["aa"], [c for pair in outcome["ab"] for c in pair]
    return (outcome["spent"], sum(decide(c, alpha, 0.0) for c in aa), len(aa),
            sum(decide(c, alpha, 0.0) and c["change"] > 0 for c in ab), len(ab))


def tally(counts):
    """Pooled over trials (a list of trial_counts)."""
    return {"spent": statistics.mean(c[0] for c in counts),
            "false_alarms": sum(c[1] for c in counts) / sum(c[2] for c in counts),
            "detect": sum(c[3] for c in counts) / sum(c[4] for c in counts)}


def fixed_cost(fixed, detect):
    """Repetitions per matrix a fixed count needs for this detection: linear between the fixed counts around it
    (their detection made monotone by a running maximum); None outside the replayed range."""
    pts, best = [], -1.0
    for spent, d in sorted(fixed):
        best = max(best, d)
        pts.append((spent, best))
    for (s0, d0), (s1, d1) in zip(pts, pts[1:]):
        if d0 <= detect <= d1:
            return s0 if d1 == d0 else s0 + (detect - d0) * (s1 - s0) / (d1 - d0)
    return None


def make_rules(args, cap):
    """Rule name -> ("fixed", n) or ("precision", P, minimum, futility)."""
    rules = {f"fixed{n}": ("fixed", n) for n in range(min(int(m) for m in args.minimum.split(",")), cap + 1)}
    for p in args.precision.split(","):
        for m in args.minimum.split(","):
            for f in args.futility.split(","):
                name = f"precision{p}/min{m}" + (f"/futility{f}" if float(f) > 0 else "")
                rules[name] = ("precision", float(p), int(m), float(f))
    return rules


def replay(fixed_docs, rules, cap, key, work):
    """Per rule, one judge() outcome per fixed run, its arms cut where the rule would have stopped."""
    outcomes = {name: [] for name in rules}
    for t, doc in enumerate(fixed_docs):
        seqs = sequences(doc, key)
        for name, rule in rules.items():
            if rule[0] == "fixed":
                counts = {case: min(rule[1], len(s)) for case, s in seqs.items()}
            else:
                counts = {case: stop_count(s, rule[1], rule[2], cap, rule[3]) for case, s in seqs.items()}
            outcomes[name].append(judge(doc, counts, os.path.join(work, f"t{t:02d}", name.replace("/", "-"))))
        print(f"replayed run {t + 1}/{len(fixed_docs)} ({len(rules)} rules)", flush=True)
    return outcomes


def real_designs(paths, work):
    """The real adaptive runs: whether this mirror stops each case arm where the harness did, and their outcomes."""
    real = {}
    for path in sorted(paths):
        p = float(re.search(r"precision([\d.]+)", path).group(1))
        with open(path) as f:
            doc = json.load(f)
        policy = doc["omnishadow"]["repetition_policy"]
        minimum, cap = policy.get("minimum", max(6, policy["repetitions"])), policy["max_repetitions"]
        judged = PER_REPETITION_KEY[policy.get("precision_metric", "wall")]
        entry = real.setdefault(p, {"agree": 0, "total": 0, "outcomes": [], "minimum": minimum, "cap": cap,
                                    "metric": policy.get("precision_metric", "wall")})
        for s in sequences(doc, judged).values():
            entry["total"] += 1
            entry["agree"] += stops(s, p, cap) and not any(stops(s[:n], p, cap) for n in range(minimum, len(s)))
        counts = {case: len(s) for case, s in sequences(doc).items()}
        entry["outcomes"].append(judge(doc, counts, os.path.join(work, os.path.basename(os.path.dirname(path)))))
    return real


def savings(rules, per_trial, resamples):
    """Rows per rule: the pooled figures, what a fixed count needs for the same detection, the saving and (for the
    adaptive rules) its 90% interval over `resamples` resamplings of the runs."""
    rows = {name: tally(c) for name, c in per_trial.items()}
    fixed_names = [n for n in rules if rules[n][0] == "fixed"]
    fixed = [(rows[n]["spent"], rows[n]["detect"]) for n in fixed_names]
    for name in rules:
        need = fixed_cost(fixed, rows[name]["detect"])
        rows[name]["fixed_cost"] = need
        rows[name]["saved"] = None if need is None else 1.0 - rows[name]["spent"] / need
    draws = {name: [] for name in rules if rules[name][0] != "fixed"}
    runs = len(next(iter(per_trial.values())))
    rng = random.Random(1)
    for _ in range(resamples):  # runs resampled with replacement, every rule on the same draw
        pick = [rng.randrange(runs) for _ in range(runs)]
        fx = [(b["spent"], b["detect"]) for b in (tally([per_trial[n][i] for i in pick]) for n in fixed_names)]
        for name in draws:
            b = tally([per_trial[name][i] for i in pick])
            need = fixed_cost(fx, b["detect"])
            if need:
                draws[name].append(1.0 - b["spent"] / need)
    for name, saved in draws.items():
        if len(saved) >= 0.9 * resamples:  # else the interval would hide draws outside the fixed range
            saved.sort()
            rows[name]["saved_90"] = (saved[int(0.05 * len(saved))], saved[int(0.95 * len(saved)) - 1])
    return rows


def markdown(args, rules, rows, real, runs, cap):
    md = [f"# Stopping rules replayed on recorded repetitions ({args.metric} time)\n",
          f"`scripts/experiments/repetition_replay.py {args.dir} --precision {args.precision} --minimum {args.minimum} "
          f"--futility {args.futility} --metric {args.metric}`: {runs} runs with {cap} repetitions of every case in "
          "four arms (A/A: false alarms; two A/B with injected work: detections), each rule replayed on the same "
          f"samples; `omnishadow compare`, alpha {args.alpha}, Holm over the cases. \"fixed would need\": the "
          "repetitions a fixed count spends for the same detection (linear between fixed counts); \"saved\": 1 - "
          "spent / that, with a 90% interval from resampling the runs.\n",
          "| rule | repetitions per matrix | false alarms | detected | fixed would need | saved (90% interval) |",
          "|---|---|---|---|---|---|"]
    for name in rules:
        r, adaptive = rows[name], rules[name][0] != "fixed"
        saved = "" if r["saved"] is None or not adaptive else f"{100 * r['saved']:+.1f}%"
        if "saved_90" in r:
            saved += f" ({100 * r['saved_90'][0]:+.1f}% .. {100 * r['saved_90'][1]:+.1f}%)"
        need = "" if r["fixed_cost"] is None or not adaptive else f"{r['fixed_cost']:.0f}"
        md.append(f"| {name} | {r['spent']:.0f} | {100 * r['false_alarms']:.1f}% | {100 * r['detect']:.1f}% | "
                  f"{need} | {saved} |")
    if real:
        md += ["\nThe real adaptive designs of the same trials (their own rounds), and whether this mirror of the "
               "harness's rule stops where the harness stopped:\n",
               "| design | runs | repetitions per matrix | false alarms | detected | replay = harness (case arms) |",
               "|---|---|---|---|---|---|"]
        for p, e in sorted(real.items()):
            r = tally([trial_counts(o, args.alpha) for o in e["outcomes"]])
            md.append(f"| precision{p:g} (min {e['minimum']}, cap {e['cap']}, judging {e['metric']}) | "
                      f"{len(e['outcomes'])} | {r['spent']:.0f} | {100 * r['false_alarms']:.1f}% | "
                      f"{100 * r['detect']:.1f}% | {e['agree']}/{e['total']} |")
    return "\n".join(md) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dir")
    parser.add_argument("--precision", default="1.5,2,2.5,3,4")
    parser.add_argument("--minimum", default="6,7,8")
    parser.add_argument("--futility", default="0")
    parser.add_argument("--alpha", type=float, default=0.05)
    parser.add_argument("--metric", choices=sorted(PER_REPETITION_KEY), default="wall",
                        help="what the rules judge and compare tests: frame wall time, process CPU time or GPU "
                             "(timer query) time per frame")
    parser.add_argument("--bootstrap", type=int, default=2000, help="resamples of the runs for the saving's interval")
    args = parser.parse_args()
    sensitivity.BINARY = os.path.join(args.dir, "omnishadow")
    sensitivity.METRIC = args.metric
    fixed_runs = {}
    for path in glob.glob(os.path.join(args.dir, "t*-fixed*", "results.json")):
        fixed_runs.setdefault(int(re.search(r"fixed(\d+)", path).group(1)), []).append(path)
    if not fixed_runs:
        sys.exit(f"repetition_replay: no t*-fixed*/results.json in {args.dir}")
    cap = max(fixed_runs)
    fixed_docs = []
    for path in sorted(fixed_runs[cap]):
        with open(path) as f:
            fixed_docs.append(json.load(f))
    rules = make_rules(args, cap)
    key = PER_REPETITION_KEY[args.metric]
    outcomes = replay(fixed_docs, rules, cap, key, os.path.join(args.dir, "replay"))
    real = real_designs(glob.glob(os.path.join(args.dir, "t*-precision*", "results.json")),
                        os.path.join(args.dir, "replay", "real"))
    per_trial = {name: [trial_counts(o, args.alpha) for o in outs] for name, outs in outcomes.items()}
    rows = savings(rules, per_trial, args.bootstrap)
    text = markdown(args, rules, rows, real, len(fixed_docs), cap)
    print(text)
    with open(os.path.join(args.dir, "repetition_replay.json"), "w") as f:
        json.dump({"rules": {n: list(r) for n, r in rules.items()}, "rows": rows,
                   "real": {f"{p:g}": {k: v for k, v in e.items() if k != "outcomes"} for p, e in real.items()}},
                  f, indent=2)
    with open(os.path.join(args.dir, f"repetition_replay_{args.metric}.md"), "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
