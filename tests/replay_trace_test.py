#!/usr/bin/python3
"""scripts/replay_trace.py on a capture the harness makes here (`run --capture all`, Vulkan on lavapipe): the timed
replays as Google Benchmark JSON that compare.py reads, a replay that fails as an error entry (exit 1, the others
kept), and bad input as one line with exit 2. Usage: replay_trace_test.py OMNISHADOW_BINARY"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "replay_trace.py")
COMPARE = "/usr/share/benchmark/compare.py"


def script(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True)


def main():
    binary = sys.argv[1]
    if not shutil.which("gfxrecon-replay"):
        print("SKIP: gfxrecon-replay missing (Debian package gfxreconstruct; scripts/setup.sh installs it)")
        sys.exit(77)
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        run = os.path.join(tmp, "run")
        env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
        made = subprocess.run([binary, "run", "--backend", "vulkan", "--scene", "room", "--cube", "16", "--frame",
                               "32x24", "--technique", "six_pass", "--filter", "hard", "--frames", "1", "--warmup",
                               "0", "--images", "none", "--benchmark_repetitions=1", "--capture", "all", "--out", run],
                              capture_output=True, text=True, env=env)
        captures = json.load(open(os.path.join(run, "captures.json")))["captures"] if made.returncode == 0 else []
        if not captures or captures[0]["status"] != "captured":
            print(f"SKIP: no Vulkan capture here (exit {made.returncode}): {made.stderr.strip()[-300:]} {captures}")
            sys.exit(77)
        trace = os.path.join(run, captures[0]["file"])

        out = os.path.join(tmp, "a.json")
        done = script(trace, "--rounds", "2", "--warmup", "0", "--out", out)
        if done.returncode != 0:
            problems.append(f"replay exit {done.returncode}: {done.stdout} {done.stderr}")
        else:
            doc = json.load(open(out))
            name = "replay/" + os.path.splitext(os.path.basename(trace))[0]
            rounds = [b for b in doc["benchmarks"] if b["run_type"] == "iteration"]
            if [b["name"] for b in rounds] != [name, name] or not all(b["real_time"] > 0 for b in rounds):
                problems.append(f"two timed replays named {name} expected: {rounds}")
            if {b.get("aggregate_name") for b in doc["benchmarks"] if b["run_type"] == "aggregate"} != {"mean",
                                                                                                    "median"}:
                problems.append("mean and median aggregates expected")
            compared = subprocess.run(["/usr/bin/python3", COMPARE, "benchmarks", out, out], capture_output=True,
                                      text=True)
            if compared.returncode != 0 or name not in compared.stdout:
                problems.append(f"compare.py cannot read it: {compared.returncode} {compared.stderr[-300:]}")

        # A trace cut short (its last block one byte short: gfxrecon-replay warns and exits 0) fails its replay: an
        # error entry beside the good one, exit 1, the file still written.
        cut = os.path.join(tmp, "cut.gfxr")
        with open(trace, "rb") as src, open(cut, "wb") as dst:
            dst.write(src.read()[:-1])
        both = os.path.join(tmp, "b.json")
        done = script(trace, cut, "--rounds", "1", "--warmup", "0", "--out", both)
        entries = json.load(open(both))["benchmarks"] if os.path.exists(both) else []
        errors = [b for b in entries if b.get("error_occurred")]
        if done.returncode != 1 or len(errors) != 1 or errors[0]["name"] != "replay/cut" or \
                "Incomplete block" not in errors[0]["error_message"] or len(entries) != 4:
            problems.append(f"a failed replay: exit {done.returncode}, entries {entries}")

        for args, expected in ((["/nonexistent.gfxr"], "/nonexistent.gfxr: no such file"),
                               ([trace.replace(".gfxr", ".trace")], "unknown trace format '.trace'"),
                               ([trace, "--rounds", "0"], "--rounds 0: at least 1")):
            done = script(*args, "--out", os.path.join(tmp, "x.json"))
            lines = done.stderr.strip().splitlines()
            if done.returncode != 2 or len(lines) != 1 or expected not in lines[0]:
                problems.append(f"{args}: exit {done.returncode}, {done.stderr!r} (wanted '{expected}')")
    for p in problems:
        print("FAIL", p)
    print(f"replay_trace: {len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
