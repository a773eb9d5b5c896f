#!/usr/bin/python3
"""The CI gates, both sides: scripts/ci/instruction_counts.py --compare passes a change within its threshold and
fails one beyond it (exit 1), or bad input (exit 2); scripts/experiments/sensitivity.py's gate choice takes the
smallest minimum effect whose false alarms are at most 1% per case, or none; the gate file it writes is what
`omnishadow compare --gate` reads, and a gate file out of range is a one-line error."""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "experiments"))
import sensitivity  # noqa: E402

COUNTS = os.path.join(ROOT, "scripts", "ci", "instruction_counts.py")
BIN = os.environ.get("OMNISHADOW_BIN", os.path.join(ROOT, "build", "release", "omnishadow"))
failures = []


def check(condition, what):
    print(("ok: " if condition else "FAILED: ") + what)
    if not condition:
        failures.append(what)


def counts_file(folder, name, counts):
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump({"format": "omnishadow-instructions/1", "instructions_per_frame": counts}, f)
    return path


def compare_counts(base, new):
    return subprocess.run(["/usr/bin/python3", COUNTS, "--compare", base, new, "--threshold", "0.002"],
                          capture_output=True, text=True)


def instruction_gate(tmp):
    base = counts_file(tmp, "base", {"a": 1e6, "b": 2e6, "gone": 5e5})
    within = counts_file(tmp, "within", {"a": 1.0019e6, "b": 2e6 * 0.9985, "added": 7})
    beyond = counts_file(tmp, "beyond", {"a": 1.0021e6, "b": 2e6})
    fewer = counts_file(tmp, "fewer", {"a": 1e6, "b": 2e6 * 0.997})
    check(compare_counts(base, within).returncode == 0, "instructions: +0.19% and -0.15% pass a 0.2% gate")
    r = compare_counts(base, beyond)
    check(r.returncode == 1 and "CHANGED" in r.stdout, "instructions: +0.21% fails it (exit 1, marked)")
    check(compare_counts(base, fewer).returncode == 1, "instructions: -0.3% fails it too (work lost is a change)")
    bad = os.path.join(tmp, "bad.json")
    with open(bad, "w") as f:
        f.write("{not json")
    check(compare_counts(base, bad).returncode == 2, "instructions: an unreadable file is exit 2")


def row(alpha, effect, false_alarms):
    return {"alpha": alpha, "min_effect": effect, "same": {"case_rate": false_alarms, "run_rate": 0},
            "slow5": {"case_rate": 0.5, "run_rate": 0}, "slow10": {"case_rate": 0.9, "run_rate": 0}}


def gate_choice():
    grid = [row(0.05, 0.0, 0.04), row(0.01, 0.0, 0.02), row(0.05, 0.03, 0.012), row(0.01, 0.03, 0.008),
            row(0.05, 0.05, 0.002), row(0.01, 0.05, 0.0)]
    gate = sensitivity.choose_gate(grid)
    check(gate is not None and (gate["alpha"], gate["min_effect"]) == (0.01, 0.03),
          "gate: the smallest minimum effect with <= 1% false alarms (alpha 0.01, 3%)")
    check(sensitivity.choose_gate([row(0.05, 0.05, 0.02)]) is None, "gate: none where every row cries wolf")
    return gate


def gate_file_read_by_compare(tmp, gate):
    run = os.path.join(tmp, "run")
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    # Skipped only for the reason `list` gives (no OpenGL here); a run that fails or crashes where GL is up fails.
    listed = subprocess.run([BIN, "list"], capture_output=True, text=True, env=env)
    unavailable = [line for line in listed.stdout.splitlines() if "gl: unavailable" in line]
    if unavailable:
        print(f"SKIP: {unavailable[0].strip()}")
        sys.exit(77)
    check(listed.returncode == 0, f"omnishadow list exits 0 (exit {listed.returncode})")
    made = subprocess.run([BIN, "run", "--backend", "gl", "--scene", "room", "--cube", "16", "--frame", "32x24",
                           "--technique", "six_pass", "--filter", "hard", "--frames", "1", "--warmup", "0",
                           "--benchmark_repetitions=3", "--no-images", "--no-accuracy", "--out", run],
                          capture_output=True, text=True, env=env)
    if made.returncode != 0:  # a signal is a negative code: a crash fails as any other exit does
        last = made.stderr.strip().splitlines()[-1] if made.stderr.strip() else "no message"
        check(False, f"omnishadow run on GL exited {made.returncode}: {last}")
        return
    path = os.path.join(tmp, "baselines", "key", "gate.json")
    sensitivity.write_gate_file(path, "cpu", gate, 6)
    r = subprocess.run([BIN, "compare", run, run, "--gate", path, "--out", os.path.join(tmp, "cmp")],
                       capture_output=True, text=True)
    check(r.returncode == 0 and "alpha 0.01" in r.stdout and "minimum effect 3%" in r.stdout,
          "gate file: compare --gate applies alpha 0.01 and minimum effect 3% " + r.stdout[-200:].replace("\n", " "))
    with open(path, "w") as f:
        json.dump({"metric": "cpu", "alpha": 2, "min_effect": 0.03}, f)
    r = subprocess.run([BIN, "compare", run, run, "--gate", path], capture_output=True, text=True)
    check(r.returncode == 2 and "alpha" in r.stderr and len(r.stderr.strip().splitlines()) == 1,
          "gate file: alpha 2 is a one-line error naming the field")


with tempfile.TemporaryDirectory() as tmp:
    instruction_gate(tmp)
    gate_file_read_by_compare(tmp, gate_choice())
print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
