#!/usr/bin/python3
"""Compares two replays of the same traces (scripts/replay_trace.py's JSON: a device's baseline and this commit's),
as Mesa's trace CI compares its replays: a trace that replayed in the baseline and fails now, or whose replayed
image's checksum changed (RenderDoc captures: the image is the frame's last colour target), is a regression; a
trace that failed in both is listed as still failing; the timings (median wall, and GPU where the driver measured
it) are reported as ratios, not judged (a replay times device creation and resource uploads as well as the frame,
so its noise is the machine's; the harness's own cases are what the fleet's gate times). Writes markdown to stdout.

A new trace has nothing to be compared with: listed, never failed. The images are compared per device key: a
driver update that changes a trace's image legitimately fails it until the baseline is refreshed
(scripts/ci/fleet_baseline.sh), as Mesa's expectations are.

Usage: scripts/ci/replay_compare.py BASE_REPLAY.json NEW_REPLAY.json
Exit: 0, 1 on a regression, 2 on bad input (one line). A BASE that does not exist compares nothing and says so.
"""
import json
import os
import statistics
import sys


def fail(message):
    print(f"replay_compare: error: {message}", file=sys.stderr)
    sys.exit(2)


def load(path):
    try:
        with open(path) as f:
            doc = json.load(f)
        return doc["benchmarks"], doc["context"].get("images", {})
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail(f"{path}: not a replay_trace.py result ({e})")


def traces(path):
    """{trace name: {"error": message or None, "wall": median ms, "gpu": median ms or None, "image": sha or None}}."""
    entries, images = load(path)
    found = {}
    for e in entries:
        name = e.get("run_name", e.get("name"))
        t = found.setdefault(name, {"error": None, "walls": [], "gpus": [], "image": images.get(name)})
        if e.get("error_occurred"):
            t["error"] = e.get("error_message", "failed")
        elif e.get("run_type") == "iteration":
            t["walls"].append(e["real_time"])
            if "gpu_time" in e:
                t["gpus"].append(e["gpu_time"])
    return {name: {"error": t["error"], "image": t["image"],
                   "wall": statistics.median(t["walls"]) if t["walls"] else None,
                   "gpu": statistics.median(t["gpus"]) if t["gpus"] else None} for name, t in found.items()}


def ratio(base, new):
    return f"{new / base:.2f}x" if base and new is not None else "-"


def verdict(b, n):
    """(regression?, what the row says) for one trace in both replays."""
    if n["error"]:
        return (not b["error"]), ("still fails: " if b["error"] else "**fails now**: ") + n["error"]
    if b["error"]:
        return False, "replays again (failed in the baseline)"
    if b["image"] and n["image"] and b["image"] != n["image"]:
        return True, f"**image changed**: {b['image'][:12]} -> {n['image'][:12]}"
    return False, "ok" + (", same image" if n["image"] and b["image"] else "")


def main():
    if len(sys.argv) != 3:
        fail("usage: replay_compare.py BASE_REPLAY.json NEW_REPLAY.json")
    base_path, new_path = sys.argv[1], sys.argv[2]
    new = traces(new_path)
    print("\n### Replayed traces\n")
    if not os.path.exists(base_path):
        print(f"No baseline replays ({base_path}): {len(new)} trace(s) replayed, nothing compared. "
              "scripts/ci/fleet_baseline.sh keeps a merged run's replay.json as the device's baseline.")
        sys.exit(0)
    base = traces(base_path)
    rows, regressions = [], 0
    for name in sorted(set(base) | set(new)):
        if name not in new:
            rows.append(f"| `{name}` | - | - | not replayed now (only in the baseline) |")
            continue
        n = new[name]
        if name not in base:
            rows.append(f"| `{name}` | - | - | new trace: " + (n["error"] or "replays") + " |")
            continue
        b = base[name]
        bad, says = verdict(b, n)
        regressions += bad
        rows.append(f"| `{name}` | {ratio(b['wall'], n['wall'])} | {ratio(b['gpu'], n['gpu'])} | {says} |")
    print(f"{len(new)} trace(s), {regressions} regression(s) (a replay that fails now, or a changed image).\n")
    print("| trace | wall new/base (median) | GPU new/base (median) | verdict |")
    print("|---|---|---|---|")
    print("\n".join(rows))
    sys.exit(1 if regressions else 0)


if __name__ == "__main__":
    main()
