#!/usr/bin/python3
"""What changed over the last N commits, and when: change points in the history of many runs of one device.

Reads run folders (or folders holding run folders), keeps one device key (the most common, or --device-key),
orders the runs by commit date (results.json's commit_date; else `git log` in --repo; else the run's date), takes
the median per commit where a commit ran more than once, and for every case and metric finds the steps:
  timings (frame time, per-pass wall and GPU time):  scripts/lib/changepoints.py (PELT + Mann-Whitney U + minimum step),
                                                     kept when the history without its newest commit has it too
  statuses, work counters, misclassified %, cube-texel errors and images (SHA-256 of the lit frame, cube faces and
  shadow factor PNGs the run wrote): exact; any change of value is a step
Steps recorded in the accepted files (--accepted, repeatable; results/accepted_steps.json by default; the results
store's with `omnishadow history --db`: case and metric patterns, commit, reason) stop alerting: a series is
analysed from its latest accepted step on, and an alert placed within ACCEPT_WINDOW commits of an accepted step is
silent, so only a new step raises a new alert. Thresholds (--thresholds; the store's with --db) replace the timing
gate's alpha and minimum effect for the metrics and devices they match, or set a fixed percentage below which a
change of any metric is no step.
Writes OUT/history.json and OUT/history.md (regressions first), or with --alerts OUT/alerts.json and OUT/alerts.md
(only the alerts, each with its commit range); exit 1 when there is an alert, 2 on bad input.

Usage: scripts/analysis/history.py RUN_OR_FOLDER... [--out DIR] [--accepted FILE]... [--thresholds FILE] [--alerts]
                                   [--repo DIR] [--device-key KEY]
"""
import argparse
import functools
import hashlib
import json
import os
import re
import subprocess
import sys
from collections import Counter

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
import changepoints  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# The timing gate; scripts/analysis/history_benchmark.py measures what it finds and what it raises falsely.
TIMING_GATE = {"penalty": 3.0, "alpha": 0.01, "min_effect": 0.02, "min_size": 3}


def fail(message):
    """Bad input: one line in the CLI's words (omnishadow history runs this script), exit 2 (1 is an alert)."""
    print(f"omnishadow: error: history: {message}", file=sys.stderr)
    sys.exit(2)


def load(path):
    file = os.path.join(path, "results.json") if os.path.isdir(path) else path
    try:
        with open(file) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"cannot read {file}: {e}")
    if not isinstance(doc, dict) or not isinstance(doc.get("omnishadow"), dict):
        fail(f"{file} is not an omnishadow results file")
    doc["_path"] = path
    return doc


def find_runs(paths):
    runs = []
    for p in paths:
        if os.path.isfile(os.path.join(p, "results.json")) or os.path.isfile(p):
            runs.append(p)
        elif os.path.isdir(p):
            runs += sorted(os.path.join(p, d) for d in os.listdir(p)
                           if os.path.isfile(os.path.join(p, d, "results.json")))
        else:
            fail(f"{p}: no such run or folder")
    return runs


def device_key(doc):
    o = doc["omnishadow"]
    return "; ".join(f"{b}: {d.get('renderer', '')} {d.get('version', '')}"
                     for b, d in sorted(o.get("devices", {}).items()))


def frame_ms(case):
    """The median per-repetition frame time (ms), the figure compare tests; runs before the rounds give the median
    frame; None for a case never timed."""
    t = case.get("timing", {})
    per = t.get("per_repetition", {}).get("frame_ms") or []
    if per:
        return float(np.median(per))
    return t["frame_wall_ms"]["median"] if "frame_wall_ms" in t else None


def case_times(doc):
    """Per case id: frame_ms of every timed case."""
    return {c["id"]: frame_ms(c) for c in doc["omnishadow"].get("cases", []) if frame_ms(c) is not None}


# Images compared exactly, by the SHA-256 of the file the run wrote (same pixels, same encoder, same bytes).
IMAGE_ROLES = ("lit", "cube_faces", "shadow_factor_png")


def image_digest(run_dir, relative):
    """The image file's SHA-256, or, for a run fetched from the results store (`omnishadow fetch`, history and
    report --db), the hash the store kept when the run was stored (image_hashes.json: path -> SHA-256)."""
    try:
        with open(os.path.join(run_dir, relative), "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()[:16]
    except OSError:
        pass
    stored = stored_image_hashes(run_dir).get(relative)
    return stored[:16] if isinstance(stored, str) else None


@functools.lru_cache(maxsize=None)
def stored_image_hashes(run_dir):
    """A fetched run's image_hashes.json (path -> SHA-256), read once per run; {} for any other run."""
    try:
        with open(os.path.join(run_dir, "image_hashes.json")) as f:
            hashes = json.load(f)
    except (OSError, ValueError):
        return {}
    return hashes if isinstance(hashes, dict) else {}


def metrics(case, run_dir="."):
    """(metric, value, exact) of one case in one run."""
    t = case.get("timing", {})
    if frame_ms(case) is not None:
        yield "frame_ms", frame_ms(case), False
    for p in ("shadow", "lighting"):
        for kind in ("cpu_wall_ms", "gpu_ms"):
            if kind in t.get(p, {}):
                yield f"{p}_{kind}", t[p][kind]["median"], False
        for name, value in case.get("counters", {}).get(p, {}).items():
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                yield f"{p}_{name}", value, True
    yield "status", case.get("status"), True
    if "accuracy" in case:
        yield "misclassified_percent", case["accuracy"].get("misclassified_percent"), True
    if "cube_texels" in case:
        yield "cube_texel_bad_percent", case["cube_texels"].get("bad_percent"), True
    for role in IMAGE_ROLES:
        if role in case.get("images", {}):
            yield f"image_{role}", image_digest(run_dir, case["images"][role]), True


def commit_order(docs, repo):
    """(date, commit) per run: the recorded commit date, else git's, else the run's own date."""
    keys = []
    for doc in docs:
        o = doc["omnishadow"]
        commit = o.get("commit", "unknown")
        date = o.get("commit_date")
        if not date and repo:
            done = subprocess.run(["git", "-C", repo, "log", "-1", "--format=%cI", commit.replace("-dirty", "")],
                                  capture_output=True, text=True)
            date = done.stdout.strip() if done.returncode == 0 else None
        keys.append((date or doc.get("context", {}).get("date", ""), commit))
    return keys


def load_accepted(path):
    """The accepted steps; none while the file does not exist yet (nothing accepted so far)."""
    if not path or not os.path.exists(path):
        return []
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"--accepted {path}: cannot read: {e}")
    steps = doc.get("steps", []) if isinstance(doc, dict) else None
    if not isinstance(steps, list):
        fail(f"--accepted {path}: /steps: a list of accepted steps is required")
    for i, s in enumerate(steps):
        for field in ("case", "metric", "commit", "reason"):
            if not isinstance(s.get(field), str) or not s[field]:
                fail(f"{path}: /steps/{i}/{field}: a non-empty string is required")
    return steps


def load_thresholds(path):
    """Rows {"device": regex, "metric": regex, and "alpha" with "min_effect", or "percent"}; threshold_for picks
    the row that applies to a metric."""
    if not path:
        return []
    try:
        with open(path) as f:
            rows = json.load(f).get("thresholds")
    except (OSError, ValueError, AttributeError) as e:
        fail(f"--thresholds {path}: cannot read: {e}")
    if not isinstance(rows, list):
        fail(f"--thresholds {path}: /thresholds: a list is required")
    for i, t in enumerate(rows):
        for field in ("device", "metric"):
            if not isinstance(t.get(field), str) or not t[field]:
                fail(f"--thresholds {path}: /thresholds/{i}/{field}: a non-empty pattern is required")
        if ("percent" in t) == ("alpha" in t or "min_effect" in t) or (
                "percent" not in t and not ("alpha" in t and "min_effect" in t)):
            fail(f"--thresholds {path}: /thresholds/{i}: give percent, or alpha with min_effect")
    return rows


def threshold_for(thresholds, key, metric):
    """The row for this device key and metric: rows naming a device (not the catch-all ".*") first, then rows
    naming a metric, then in the given order."""
    ranked = sorted(thresholds, key=lambda t: (t["device"] == ".*", t["metric"] == ".*"))
    return next((t for t in ranked if re.search(t["device"], key) and re.search(t["metric"], metric)), None)


def relative_change(before, after):
    if isinstance(before, str) or isinstance(after, str) or before is None or after is None:
        return 1.0
    return after / before - 1.0 if before else (0.0 if after == before else 1.0)


def regressed(metric, before, after, change):
    """A status that leaves ok, a changed image, or a figure that grew (times, work, error)."""
    if metric == "status":
        return before == "ok" and after != "ok"
    return change > 0


# An accepted step silences alerts placed within this many commits of it: the estimated position of a step moves
# by a commit or two as runs arrive after it.
ACCEPT_WINDOW = 3


def accepted_indices(commits, case_id, metric, accepted):
    """Positions in this series of the accepted steps that match its case and metric."""
    out = []
    for s in accepted:
        if re.search(s["case"], case_id) and re.search(s["metric"], metric):
            out += [i for i, c in enumerate(commits)
                    if c.startswith(s["commit"]) or s["commit"].startswith(c.replace("-dirty", ""))]
    return out


def persistent(series, accepted_at, find):
    """Steps found both with and without the newest commit (within a commit of each other): a split that one new
    run creates and the next one dissolves is noise, and waiting one commit removes most of those."""
    now = steps_after_accepted(series, accepted_at, find)
    if len(series) < 2:
        return now
    before = steps_after_accepted(series[:-1], accepted_at, find)
    return [s for s in now if any(abs(s["index"] - b["index"]) <= 1 for b in before)]


def steps_after_accepted(series, accepted_at, find):
    """The steps `find` gives on the series from its latest accepted step on (what came before was judged), less
    those placed within ACCEPT_WINDOW commits of an accepted step; indices into the whole series."""
    start = max(accepted_at, default=0)
    steps = []
    for s in find(series[start:], history=series):
        s = dict(s, index=start + s["index"])
        if all(abs(s["index"] - a) > ACCEPT_WINDOW for a in accepted_at):
            steps.append(s)
    return steps


def timing_find(values, history, gate=None):
    return changepoints.timing_steps(values, history=history, **(gate or TIMING_GATE))


def timing_gate(threshold):
    """The timing gate for one series: the default, its alpha and minimum effect from a threshold row, or with a
    fixed percentage no test at all (any step of PELT's of at least that size)."""
    if not threshold:
        return TIMING_GATE
    if "percent" in threshold:
        return dict(TIMING_GATE, alpha=2.0, min_effect=threshold["percent"] / 100.0)
    return dict(TIMING_GATE, alpha=threshold["alpha"], min_effect=threshold["min_effect"])


def analyse(runs, accepted, repo, key=None, thresholds=()):
    docs = [load(r) for r in runs]
    keys = Counter(device_key(d) for d in docs)
    key = key or keys.most_common(1)[0][0]
    docs = [d for d in docs if device_key(d) == key]
    if not docs:
        fail(f"no run of device key {key!r}; keys found: {', '.join(keys)}")
    order = sorted(zip(commit_order(docs, repo), docs), key=lambda kv: kv[0][0])
    commits = []
    values = {}  # (case, metric) -> {commit: [values]}
    exact = {}
    for (date, commit), doc in order:
        if commit not in commits:
            commits.append(commit)
        for case in doc["omnishadow"].get("cases", []):
            run_dir = doc["_path"] if os.path.isdir(doc["_path"]) else os.path.dirname(doc["_path"])
            for metric, value, is_exact in metrics(case, run_dir):
                if value is None:
                    continue
                values.setdefault((case["id"], metric), {}).setdefault(commit, []).append(value)
                exact[(case["id"], metric)] = is_exact
    alerts = []
    for (case_id, metric), by_commit in sorted(values.items()):
        series_commits = [c for c in commits if c in by_commit]
        # Timings: the median of a commit's runs. Exact figures: the first run's (they agree unless the driver does not).
        series = [by_commit[c][0] if exact[(case_id, metric)] else float(np.median(by_commit[c]))
                  for c in series_commits]
        accepted_at = accepted_indices(series_commits, case_id, metric, accepted)
        threshold = threshold_for(thresholds, key, metric)
        if exact[(case_id, metric)]:
            steps = steps_after_accepted(series, accepted_at, changepoints.exact_steps)
            if threshold and "percent" in threshold:  # a fixed percentage: smaller changes are no step
                steps = [s for s in steps if abs(relative_change(s["before"], s["after"])) >= threshold["percent"] / 100]
        else:
            gate = timing_gate(threshold)
            steps = persistent(series, accepted_at, lambda values, history: timing_find(values, history, gate))
        for s in steps:
            i = s["index"]
            change = relative_change(s["before"], s["after"])
            alerts.append({"case": case_id, "metric": metric, "commit": series_commits[i],
                           "previous_commit": series_commits[i - 1] if i > 0 else None,
                           "before": s["before"], "after": s["after"], "step": change, "exact": exact[(case_id, metric)],
                           "confidence": s.get("confidence", 1.0),
                           "regression": regressed(metric, s["before"], s["after"], change),
                           "threshold": threshold, "series": series, "commits": series_commits, "index": i})
    alerts.sort(key=lambda a: (not a["regression"], -abs(a["step"])))
    return {"device_key": key, "runs": len(docs), "commits": commits, "alerts": alerts, "gate": TIMING_GATE}


def value_cells(alert):
    """Before, after and the step as the tables print them (a status or an image hash as is: "changed")."""
    if isinstance(alert["before"], str) or isinstance(alert["after"], str):
        return alert["before"], alert["after"], "changed"
    return f"{alert['before']:.4g}", f"{alert['after']:.4g}", f"{100 * alert['step']:+.1f}%"


def markdown(result):
    md = [f"# History: {result['device_key']}\n",
          f"{result['runs']} runs over {len(result['commits'])} commits ({result['commits'][0]} .. "
          f"{result['commits'][-1]}); {len(result['alerts'])} alerts, regressions first.\n"]
    if result["alerts"]:
        md += ["| case | metric | first commit after | before | after | step | confidence |", "|---|---|---|---|---|---|---|"]
        for a in result["alerts"]:
            confidence = "exact" if a["exact"] else f"{a['confidence']:.4f}"
            before, after, step = value_cells(a)
            md.append(f"| `{a['case']}` | {a['metric']} | {a['commit']} | {before} | {after} | {step} | {confidence} |")
        md.append("\nAccept a step (it stops alerting; a new step alerts again): add "
                  '`{"case": "<regex>", "metric": "<regex>", "commit": "<sha>", "reason": "..."}` to '
                  "results/accepted_steps.json.")
    return "\n".join(md) + "\n"


def alerts_markdown(result):
    """The alerts alone, each with its commit range: what `omnishadow alerts` prints."""
    md = [f"# Alerts: {result['device_key']}\n",
          f"{len(result['alerts'])} not accepted, over {result['runs']} runs of {len(result['commits'])} commits "
          f"({result['commits'][0]} .. {result['commits'][-1]}); regressions first.\n"]
    if result["alerts"]:
        md += ["| case | metric | commits | before | after | step | regression |", "|---|---|---|---|---|---|---|"]
        for a in result["alerts"]:
            before, after, step = value_cells(a)
            md.append(f"| `{a['case']}` | {a['metric']} | {a['previous_commit']}..{a['commit']} | {before} | {after} | "
                      f"{step} | {'yes' if a['regression'] else 'no'} |")
        md.append("\nAccept a step (it stops alerting): `omnishadow accept --db URL --case REGEX --metric REGEX "
                  "--commit SHA --reason WHY`.")
    return "\n".join(md) + "\n"


def write_atomic(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--out", default=".")
    parser.add_argument("--accepted", action="append",
                        help="accepted steps, repeatable (default results/accepted_steps.json; a file not there yet: "
                             "nothing accepted)")
    parser.add_argument("--thresholds", help="per device and metric: alpha and min_effect, or percent")
    parser.add_argument("--alerts", action="store_true", help="write only the alerts: alerts.json, alerts.md")
    parser.add_argument("--repo", default=ROOT)
    parser.add_argument("--device-key")
    args = parser.parse_args()
    accepted = [s for path in args.accepted or [os.path.join(ROOT, "results", "accepted_steps.json")]
                for s in load_accepted(path)]
    runs = find_runs(args.runs)
    if not runs:
        fail(f"no run (no results.json) in {', '.join(args.runs)}")
    result = analyse(runs, accepted, args.repo, args.device_key, load_thresholds(args.thresholds))
    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        fail(f"--out {args.out}: cannot create: {e.strerror}")
    name = "alerts" if args.alerts else "history"
    text = alerts_markdown(result) if args.alerts else markdown(result)
    kept = [{k: v for k, v in a.items() if k not in ("series", "commits")} for a in result["alerts"]]
    write_atomic(os.path.join(args.out, f"{name}.json"),
                 json.dumps(dict(result, alerts=kept) if args.alerts else result, indent=1))
    write_atomic(os.path.join(args.out, f"{name}.md"), text)
    print(text)
    sys.exit(1 if result["alerts"] else 0)


if __name__ == "__main__":
    main()
