#!/usr/bin/python3
"""Times captured traces replayed on this machine's driver, as Google Benchmark JSON: a trace from a user's GPU
(`omnishadow run --capture`, docs/guide.md) becomes a benchmark of its own, which Google Benchmark's compare.py
compares across drivers or commits as it compares the harness's own results.json (`compare.py benchmarks A.json
B.json`), as Mesa's trace CI replays its traces on every commit.

Each trace is replayed once untimed (the driver's shader caches warm), then --rounds times, each round timed from
the replayer's start to its exit (wall time, and the replayer's CPU time): the harness never presents, so its
captures have no frame boundaries, and a replay is the whole capture, device creation and pipeline builds included.
Vulkan traces (.gfxr) replay with gfxrecon-replay (Debian's gfxreconstruct), by default with its memory translation
`rebind` (--memory-translation), which binds resources to the replaying GPU's own memory types: a trace captured on
another GPU (a user's) then replays here as well as one captured on this one. RenderDoc captures (.rdc, GL or
Vulkan: one frame, the check frame) replay with scripts/replay_renderdoc.py (python3-renderdoc) in one process: the
capture is loaded once and its frame replayed --warmup + --rounds times, each round's wall and CPU time that of the
frame's replay alone, and `gpu_time` (ms) beside them where the driver has RenderDoc's GPU duration counter; the
replayed image's SHA-256 is in the context's `images`, so that a trace's image compares across drivers and commits
as a checksum (scripts/ci/fleet_replay.sh does). A replay that fails (a non-zero exit, or an exit 0 that says the
trace is cut short or broken) is an entry with error_occurred and the line that says why, and the others go on; the
file is written atomically.

Usage: scripts/replay_trace.py TRACE [TRACE...] --out FILE [--rounds N] [--warmup N] [--memory-translation MODE]
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
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RENDERDOC = os.path.join(ROOT, "scripts", "replay_renderdoc.py")
REPLAYERS = {".gfxr": ("gfxrecon-replay", "gfxreconstruct"),  # suffix: (replayer, Debian package)
             ".rdc": ("renderdoc", "python3-renderdoc")}


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
    if suffix == ".rdc":
        if subprocess.run(["/usr/bin/python3", "-c", "import renderdoc, PIL"], capture_output=True).returncode:
            fail(f"{trace}: RenderDoc's Python module or PIL is missing (Debian packages {package}, python3-pil)")
        return RENDERDOC
    path = shutil.which(tool)
    if not path:
        fail(f"{trace}: {tool} not found (Debian package {package})")
    return path


def version_of(replayer):
    if replayer == RENDERDOC:
        ask = "import renderdoc; print(renderdoc.GetVersionString())"
        return "RenderDoc " + subprocess.run(["/usr/bin/python3", "-c", ask], capture_output=True,
                                             text=True).stdout.strip()
    out = subprocess.run([replayer, "--version"], capture_output=True, text=True).stdout
    line = next((l for l in out.splitlines() if "Version" in l), out.strip().splitlines()[0] if out.strip() else "")
    return line.strip()


# What the replayer says of a trace it could not replay whole, while it still exits 0 (gfxrecon-replay 0.9.18 does
# for a file cut short).
BROKEN = ("Incomplete block", "ERROR")
MEMORY_TRANSLATIONS = ("none", "remap", "realign", "rebind")  # gfxrecon-replay -m


def replay_once(replayer, trace, options=()):
    """(wall ms, CPU ms of the replayer, exit code or -1 for a broken trace, the line that says why)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([replayer, *options, trace], capture_output=True, text=True)
    wall = (time.perf_counter() - start) * 1e3
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = ((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)) * 1e3
    lines = (done.stdout + done.stderr).strip().splitlines()
    broken = [l for l in lines if any(b in l for b in BROKEN)]
    if done.returncode == 0 and broken:
        return wall, cpu, -1, broken[0]
    return wall, cpu, done.returncode, lines[-1] if lines else ""


def replay_renderdoc(trace, warmup, rounds):
    """(walls, cpus, gpus, image sha256, error or None): one replay process, its frame replayed warmup + rounds
    times."""
    with tempfile.TemporaryDirectory() as tmp:
        png, timings = os.path.join(tmp, "frame.png"), os.path.join(tmp, "timings.json")
        env = dict(os.environ, EGL_PLATFORM="surfaceless", XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
        done = subprocess.run(["/usr/bin/python3", RENDERDOC, trace, "--out", png, "--rounds", str(warmup + rounds),
                               "--json", timings], capture_output=True, text=True, env=env)
        if done.returncode != 0 or not os.path.exists(timings):
            lines = (done.stdout + done.stderr).strip().splitlines()
            return [], [], [], None, f"replay_renderdoc.py exited {done.returncode}: {lines[-1] if lines else ''}"
        doc = json.load(open(timings))
    return doc["wall_ms"][warmup:], doc["cpu_ms"][warmup:], doc["gpu_ms"][warmup:], doc["image_sha256"], None


def replay_process(replayer, trace, warmup, rounds, options):
    """The same for a replayer that replays the whole trace per process (gfxrecon-replay): no image."""
    walls, cpus = [], []
    for r in range(warmup + rounds):
        wall, cpu, code, last = replay_once(replayer, trace, options)
        if code != 0:
            return [], [], [], None, f"{os.path.basename(replayer)} " + \
                (f"exited {code}" if code > 0 else "exited 0") + f": {last}"
        if r >= warmup:
            walls.append(wall)
            cpus.append(cpu)
    return walls, cpus, [], None, None


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
    parser.add_argument("--memory-translation", default="rebind",
                        help="gfxrecon-replay's -m: none, remap, realign or rebind (default: a trace from another GPU "
                        "replays)")
    args = parser.parse_args()
    if args.memory_translation not in MEMORY_TRANSLATIONS:
        fail(f"--memory-translation {args.memory_translation}: not one of {', '.join(MEMORY_TRANSLATIONS)}")
    if args.rounds < 1:
        fail(f"--rounds {args.rounds}: at least 1")
    if args.warmup < 0:
        fail(f"--warmup {args.warmup}: at least 0")
    replayers = [replayer_for(t) for t in args.traces]  # every trace checked before any replay
    benchmarks, failed, images = [], 0, {}
    for index, (trace, replayer) in enumerate(zip(args.traces, replayers)):
        name = "replay/" + os.path.splitext(os.path.basename(trace))[0]
        measure = replay_renderdoc if replayer == RENDERDOC else \
            lambda t, w, r, replayer=replayer: replay_process(replayer, t, w, r, ["-m", args.memory_translation])
        walls, cpus, gpus, image, error = measure(trace, args.warmup, args.rounds)
        if error:
            failed += 1
            e = entry(name, index, args.rounds, 0.0, 0.0)
            e.update({"error_occurred": True, "error_message": error})
            benchmarks.append(e)
            print(f"{name}: {error}")
            continue
        rounds = [entry(name, index, args.rounds, w, c) for w, c in zip(walls, cpus)]
        for e, g in zip(rounds, gpus):
            e["gpu_time"] = g  # a user counter (ms): the frame's GPU time, where the driver measures it
        benchmarks += rounds + aggregates(name, index, args.rounds, walls, cpus)
        if image:
            images[name] = image
        print(f"{name}: median {statistics.median(walls):.1f} ms wall over {args.rounds} replays" +
              (f", {statistics.median(gpus):.3f} ms GPU" if gpus else "") + (f", image {image[:12]}" if image else ""))
    doc = {"context": {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                       "host_name": platform.node(), "executable": "scripts/replay_trace.py",
                       "num_cpus": os.cpu_count(), "library_build_type": "release",
                       "replayers": sorted({version_of(r) for r in replayers}),
                       "traces": [os.path.abspath(t) for t in args.traces], "images": images,
                       "gfxr_memory_translation": args.memory_translation},
           "benchmarks": benchmarks}
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(tmp, args.out)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
