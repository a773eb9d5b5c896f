#!/usr/bin/python3
"""Times captured traces replayed on this machine's driver, as Google Benchmark JSON: a trace from a user's GPU
(`omnishadow run --capture`, docs/guide.md) becomes a benchmark of its own, which Google Benchmark's compare.py
compares across drivers or commits as it compares the harness's own results.json (`compare.py benchmarks A.json
B.json`), as Mesa's trace CI replays its traces on every commit.

Each trace is replayed once untimed (the driver's shader caches warm), then --rounds times, each round timed from
the replayer's start to its exit (wall time, and the replayer's CPU time): the harness never presents, so its
captures have no frame boundaries, and a replay is the whole capture, device creation and pipeline builds included.
Vulkan traces (.gfxr) replay with gfxrecon-replay (Debian's gfxreconstruct). A replay that fails (a non-zero exit,
or an exit 0 that says the trace is cut short or broken) is an entry with error_occurred and the line that says
why, and the others go on; the file is written atomically.

Usage: scripts/replay_trace.py TRACE [TRACE...] --out FILE [--rounds N] [--warmup N]
Exit: 0, 1 when a replay failed, 2 on bad input (one line naming the trace or option).
"""
import argparse
import datetime
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import time

REPLAYERS = {".gfxr": ("gfxrecon-replay", "gfxreconstruct")}  # suffix: (replayer, Debian package)


def fail(message):
    print(f"replay_trace: error: {message}", file=sys.stderr)
    sys.exit(2)


def replayer_for(trace):
    suffix = os.path.splitext(trace)[1]
    if suffix not in REPLAYERS:
        fail(f"{trace}: unknown trace format '{suffix}' (known: {', '.join(REPLAYERS)})")
    if not os.path.isfile(trace):
        fail(f"{trace}: no such file")
    tool, package = REPLAYERS[suffix]
    path = shutil.which(tool)
    if not path:
        fail(f"{trace}: {tool} not found (Debian package {package})")
    return path


def version_of(replayer):
    out = subprocess.run([replayer, "--version"], capture_output=True, text=True).stdout
    line = next((l for l in out.splitlines() if "Version" in l), out.strip().splitlines()[0] if out.strip() else "")
    return line.strip()


# What the replayer says of a trace it could not replay whole, while it still exits 0 (gfxrecon-replay 0.9.18 does
# for a file cut short).
BROKEN = ("Incomplete block", "ERROR")


def replay_once(replayer, trace):
    """(wall ms, CPU ms of the replayer, exit code or -1 for a broken trace, the line that says why)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([replayer, trace], capture_output=True, text=True)
    wall = (time.perf_counter() - start) * 1e3
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = ((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)) * 1e3
    lines = (done.stdout + done.stderr).strip().splitlines()
    broken = [l for l in lines if any(b in l for b in BROKEN)]
    if done.returncode == 0 and broken:
        return wall, cpu, -1, broken[0]
    return wall, cpu, done.returncode, lines[-1] if lines else ""


def entry(name, index, rounds, wall, cpu):
    return {"name": name, "family_index": index, "per_family_instance_index": 0, "run_name": name,
            "run_type": "iteration", "repetitions": rounds, "threads": 1, "iterations": 1,
            "real_time": wall, "cpu_time": cpu, "time_unit": "ms"}


def aggregates(name, index, rounds, walls, cpus):
    out = []
    for aggregate, pick in (("mean", statistics.mean), ("median", statistics.median)):
        e = entry(name, index, rounds, pick(walls), pick(cpus))
        e.update({"name": f"{name}_{aggregate}", "run_type": "aggregate", "aggregate_name": aggregate})
        out.append(e)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("traces", nargs="+")
    parser.add_argument("--out", required=True, help="the Google Benchmark JSON to write")
    parser.add_argument("--rounds", type=int, default=5, help="timed replays of each trace (>= 1)")
    parser.add_argument("--warmup", type=int, default=1, help="untimed replays first (>= 0)")
    args = parser.parse_args()
    if args.rounds < 1:
        fail(f"--rounds {args.rounds}: at least 1")
    if args.warmup < 0:
        fail(f"--warmup {args.warmup}: at least 0")
    replayers = [replayer_for(t) for t in args.traces]  # every trace checked before any replay
    benchmarks, failed = [], 0
    for index, (trace, replayer) in enumerate(zip(args.traces, replayers)):
        name = "replay/" + os.path.splitext(os.path.basename(trace))[0]
        walls, cpus, error = [], [], None
        for r in range(args.warmup + args.rounds):
            wall, cpu, code, last = replay_once(replayer, trace)
            if code != 0:
                error = f"{os.path.basename(replayer)} " + (f"exited {code}" if code > 0 else "exited 0") + \
                    f": {last}"
                break
            if r >= args.warmup:
                walls.append(wall)
                cpus.append(cpu)
        if error:
            failed += 1
            e = entry(name, index, args.rounds, 0.0, 0.0)
            e.update({"error_occurred": True, "error_message": error})
            benchmarks.append(e)
            print(f"{name}: {error}")
            continue
        benchmarks += [entry(name, index, args.rounds, w, c) for w, c in zip(walls, cpus)]
        benchmarks += aggregates(name, index, args.rounds, walls, cpus)
        print(f"{name}: median {statistics.median(walls):.1f} ms wall over {args.rounds} replays")
    doc = {"context": {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                       "host_name": platform.node(), "executable": "scripts/replay_trace.py",
                       "num_cpus": os.cpu_count(), "library_build_type": "release",
                       "replayers": sorted({version_of(r) for r in replayers}),
                       "traces": [os.path.abspath(t) for t in args.traces]},
           "benchmarks": benchmarks}
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(tmp, args.out)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
