#!/usr/bin/python3
"""scripts/replay_trace.py on captures the harness makes here (`run --capture all`: Vulkan on lavapipe through
GFXReconstruct, GL on llvmpipe through RenderDoc): the timed replays as Google Benchmark JSON that compare.py reads,
a RenderDoc trace's replayed image checksummed (and the checksum that of the harness's own lit image), a replay
that fails as an error entry (exit 1, the others kept), and bad input as one line with exit 2; then the fleet's
steps around it: scripts/ci/fleet_replay.sh (the first shard only, FLEET_TRACES) and scripts/ci/replay_compare.py
(a trace that fails now or whose image changed is a regression, one that still fails or is new is not).
Usage: replay_trace_test.py OMNISHADOW_BINARY"""
import glob
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "replay_trace.py")
FLEET_REPLAY = os.path.join(ROOT, "scripts", "ci", "fleet_replay.sh")
REPLAY_COMPARE = os.path.join(ROOT, "scripts", "ci", "replay_compare.py")
COMPARE = "/usr/share/benchmark/compare.py"
CASE = ["--scene", "room", "--cube", "16", "--frame", "32x24", "--technique", "six_pass", "--filter", "hard",
        "--frames", "1", "--warmup", "0", "--benchmark_repetitions=1", "--capture", "all"]


def script(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True)


def renderdoc_here():
    return shutil.which("renderdoccmd") and subprocess.run(["/usr/bin/python3", "-c", "import renderdoc, PIL"],
                                                            capture_output=True).returncode == 0


def captured(binary, run, backend, images):
    """(the capture's path or None, why not): the case run on one API with `--capture all`."""
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    made = subprocess.run([binary, "run", "--backend", backend, *CASE, "--images", images, "--out", run],
                          capture_output=True, text=True, env=env)
    captures = json.load(open(os.path.join(run, "captures.json")))["captures"] if made.returncode == 0 else []
    if not captures or captures[0]["status"] != "captured":
        return None, f"no {backend} capture (exit {made.returncode}): {made.stderr.strip()[-300:]} {captures}"
    return os.path.join(run, captures[0]["file"]), ""


def gl_trace(binary, tmp, problems):
    """A RenderDoc capture of the GL case and the harness's lit image of it, or (None, None)."""
    trace, why = captured(binary, os.path.join(tmp, "glrun"), "gl", "all")
    if not trace:
        problems.append(why)
        return None, None
    lit = glob.glob(os.path.join(trace[:-len(".rdc")] + ".run", "images", "**", "lit.png"), recursive=True)
    return trace, lit[0] if lit else None


def check_renderdoc_replay(binary, tmp, problems):
    """The .rdc trace timed and checksummed: the checksum is the harness's own lit image's. Returns the JSON."""
    trace, lit = gl_trace(binary, tmp, problems)
    if not trace:
        return None
    out = os.path.join(tmp, "rdc.json")
    done = script(trace, "--rounds", "2", "--warmup", "1", "--out", out)
    if done.returncode != 0:
        problems.append(f"RenderDoc replay exit {done.returncode}: {done.stdout} {done.stderr}")
        return None
    doc = json.load(open(out))
    name = "replay/" + os.path.splitext(os.path.basename(trace))[0]
    rounds = [b for b in doc["benchmarks"] if b["run_type"] == "iteration"]
    if len(rounds) != 2 or not all(b["real_time"] > 0 and b.get("gpu_time", 0) >= 0 for b in rounds):
        problems.append(f"two timed RenderDoc rounds expected: {rounds}")
    from PIL import Image
    want = hashlib.sha256(Image.open(lit).convert("RGBA").tobytes()).hexdigest() if lit else None
    if doc["context"]["images"].get(name) != want:
        problems.append(f"the replayed image's checksum {doc['context']['images']} is not the harness's {want}")
    return out


def check_replay_compare(replay_json, tmp, problems):
    """replay_compare.py on edits of one real replay: each verdict with its exit code."""
    doc = json.load(open(replay_json))
    name = next(iter(doc["context"]["images"]))

    def variant(label, edit):
        d = json.loads(json.dumps(doc))
        edit(d)
        path = os.path.join(tmp, label + ".json")
        json.dump(d, open(path, "w"))
        return path

    def changed(d):
        d["context"]["images"][name] = "0" * 64

    def broken(d):
        d["benchmarks"] = [{"name": name, "run_name": name, "run_type": "iteration", "error_occurred": True,
                            "error_message": "replay_renderdoc.py exited 1: boom"}]
        d["context"]["images"] = {}

    bad = os.path.join(tmp, "bad.json")
    open(bad, "w").write("{}")
    broken_path = variant("broken", broken)
    for base, new, code, says in ((replay_json, replay_json, 0, "ok, same image"),
                                  (replay_json, variant("changed", changed), 1, "**image changed**"),
                                  (replay_json, broken_path, 1, "**fails now**: replay_renderdoc.py exited 1: boom"),
                                  (broken_path, broken_path, 0, "still fails"),
                                  (broken_path, replay_json, 0, "replays again"),
                                  (os.path.join(tmp, "none.json"), replay_json, 0, "No baseline replays"),
                                  (replay_json, bad, 2, "not a replay_trace.py result")):
        done = subprocess.run(["/usr/bin/python3", REPLAY_COMPARE, base, new], capture_output=True, text=True)
        if done.returncode != code or says not in done.stdout + done.stderr:
            problems.append(f"replay_compare {os.path.basename(base)} {os.path.basename(new)}: exit "
                            f"{done.returncode} (wanted {code}, '{says}'): {done.stdout[-400:]} {done.stderr}")


def check_fleet_replay(trace_dir, tmp, problems):
    """fleet_replay.sh: the first shard replays FLEET_TRACES' traces; the others do nothing; a bad folder is exit 2."""
    env = {k: v for k, v in os.environ.items() if k not in ("CI_NODE_INDEX", "OMNISHADOW_SHARD_INDEX")}
    env.update(FLEET_TRACES=trace_dir, FLEET_REPLAY_ROUNDS="1")

    def play(shard, **extra):
        return subprocess.run(["bash", FLEET_REPLAY, os.path.join(tmp, shard)], capture_output=True, text=True,
                              env=dict(env, **extra))
    done = play("first", CI_NODE_INDEX="1")
    replay = os.path.join(tmp, "first", "replay.json")
    names = [b["name"] for b in json.load(open(replay))["benchmarks"]] if os.path.exists(replay) else []
    if done.returncode != 0 or not names:
        problems.append(f"fleet_replay.sh, first shard: exit {done.returncode}, {names}: {done.stdout} {done.stderr}")
    for shard, extra in (("second", {"CI_NODE_INDEX": "2"}), ("github1", {"OMNISHADOW_SHARD_INDEX": "1"})):
        done = play(shard, **extra)
        if done.returncode != 0 or os.path.exists(os.path.join(tmp, shard, "replay.json")):
            problems.append(f"fleet_replay.sh on shard {extra}: must replay nothing (exit {done.returncode})")
    done = play("bad", FLEET_TRACES="/nonexistent-traces")
    if done.returncode != 2 or "FLEET_TRACES names '/nonexistent-traces'" not in done.stderr:
        problems.append(f"fleet_replay.sh with a missing folder: exit {done.returncode}, {done.stderr!r}")


def main():
    binary = sys.argv[1]
    if not shutil.which("gfxrecon-replay"):
        print("SKIP: gfxrecon-replay missing (Debian package gfxreconstruct; scripts/setup.sh installs it)")
        sys.exit(77)
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        trace, why = captured(binary, os.path.join(tmp, "run"), "vulkan", "none")
        if not trace:
            print(f"SKIP: {why}")
            sys.exit(77)

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
                               ([trace, "--rounds", "0"], "--rounds 0: at least 1"),
                               ([trace, "--memory-translation", "bogus"], "--memory-translation bogus: not one of")):
            done = script(*args, "--out", os.path.join(tmp, "x.json"))
            lines = done.stderr.strip().splitlines()
            if done.returncode != 2 or len(lines) != 1 or expected not in lines[0]:
                problems.append(f"{args}: exit {done.returncode}, {done.stderr!r} (wanted '{expected}')")
        if renderdoc_here():
            replay_json = check_renderdoc_replay(binary, tmp, problems)
            if replay_json:
                check_replay_compare(replay_json, tmp, problems)
                check_fleet_replay(os.path.dirname(trace), tmp, problems)
        else:
            print("RenderDoc part skipped: needs Debian packages renderdoccmd, librenderdoc, python3-renderdoc, "
                  "python3-pil (scripts/setup.sh installs them)")
    for p in problems:
        print("FAIL", p)
    print(f"replay_trace: {len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
