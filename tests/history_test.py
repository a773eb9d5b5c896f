#!/usr/bin/python3
"""scripts/lib/changepoints.py and scripts/analysis/history.py on histories written as run folders: PELT finds what it must,
a timing step is found at its commit, an exact counter change is a step, an accepted step stops alerting and a new
one alerts again, and a malformed accepted file is named."""
import json
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:  # a machine without Debian's package: say which, and skip (ctest SKIP_RETURN_CODE 77)
    print("SKIP: needs python3-numpy (Debian package; scripts/setup.sh installs it)")
    sys.exit(77)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "lib"))
import changepoints  # noqa: E402

HISTORY = os.path.join(ROOT, "scripts", "analysis", "history.py")


def write_run(folder, commit, day, frame_ms, draws, lit=b"lit pixels"):
    os.makedirs(folder)
    with open(os.path.join(folder, "lit.png"), "wb") as f:
        f.write(lit)
    case = {"id": "gl/room/c512/six_pass/hard", "status": "ok", "images": {"lit": "lit.png"},
            "timing": {"per_repetition": {"frame_ms": list(frame_ms)}},
            "counters": {"shadow": {"valid": True, "draw_calls": draws}, "lighting": {"valid": True, "draw_calls": 1}}}
    doc = {"context": {"date": f"2026-11-{day:02d}T00:00:00"},
           "omnishadow": {"format": "omnishadow-results/1", "commit": commit,
                          "commit_date": f"2026-10-01T00:00:00+00:00".replace("01T", f"{day:02d}T"),
                          "devices": {"gl": {"renderer": "llvmpipe", "version": "4.5"}}, "cases": [case]}}
    with open(os.path.join(folder, "results.json"), "w") as f:
        json.dump(doc, f)


def history(runs_dir, accepted, out):
    done = subprocess.run(["/usr/bin/python3", HISTORY, runs_dir, "--accepted", accepted, "--out", out, "--repo", ""],
                          capture_output=True, text=True)
    with open(os.path.join(out, "history.json")) as f:
        return done.returncode, json.load(f), done.stdout + done.stderr


def check(condition, message):
    if not condition:
        sys.exit(f"history_test: {message}")


def main():
    check(changepoints.pelt(np.r_[np.zeros(20), np.full(20, 10.0)], 3 * np.log(40)) == [20], "PELT: one clear step")
    check(changepoints.pelt(np.zeros(40), 3 * np.log(40)) == [], "PELT: no step in a constant series")
    check(changepoints.exact_steps([5, 5, 6, 6, 5]) == [{"index": 2, "before": 5, "after": 6},
                                                      {"index": 4, "before": 6, "after": 5}], "exact steps")
    rng = np.random.default_rng(7)
    with tempfile.TemporaryDirectory() as tmp:
        runs = os.path.join(tmp, "runs")
        # 30 commits, 2% noise; commit 20 is 8% slower; commit 25 draws one more call per frame.
        for i in range(30):
            level = 1.08 if i >= 20 else 1.0
            write_run(os.path.join(runs, f"r{i:02d}"), f"c{i:02d}", i + 1, level * np.exp(rng.normal(0, 0.02, 5)),
                      7 if i >= 25 else 6, b"new pixels" if i >= 27 else b"lit pixels")
        accepted = os.path.join(tmp, "accepted.json")
        code, result, log = history(runs, accepted, os.path.join(tmp, "h1"))
        found = {(a["metric"], a["commit"]) for a in result["alerts"]}
        check(code == 1, f"alerts must exit 1: {log}")
        check(("frame_ms", "c20") in found, f"the 8% step at c20: {found}")
        check(("shadow_draw_calls", "c25") in found, f"the counter change at c25: {found}")
        check(("image_lit", "c27") in found, f"the image change at c27: {found}")
        check(len([a for a in result["alerts"] if a["metric"] == "frame_ms"]) == 1, f"one timing step: {found}")
        check(result["alerts"][0]["regression"], "regressions first")
        with open(accepted, "w") as f:
            json.dump({"steps": [{"case": "room", "metric": ".*", "commit": "c20", "reason": "bigger shader"},
                                 {"case": "room", "metric": "draw_calls", "commit": "c25", "reason": "a new pass"},
                                 {"case": "room", "metric": "image", "commit": "c27", "reason": "new colours"}]}, f)
        code, result, log = history(runs, accepted, os.path.join(tmp, "h2"))
        check(code == 0 and not result["alerts"], f"accepted steps stop alerting: {result['alerts']}")
        for i in range(30, 40):  # a new step after the accepted ones alerts again
            write_run(os.path.join(runs, f"r{i:02d}"), f"c{i:02d}", i + 1, 1.2 * np.exp(rng.normal(0, 0.02, 5)), 7,
                      b"new pixels")
        code, result, log = history(runs, accepted, os.path.join(tmp, "h3"))
        check([a["commit"] for a in result["alerts"]] == ["c30"], f"the new step at c30 alerts: {result['alerts']}")
        with open(accepted, "w") as f:
            json.dump({"steps": [{"case": "room", "commit": "c20"}]}, f)
        done = subprocess.run(["/usr/bin/python3", HISTORY, runs, "--accepted", accepted, "--out", tmp],
                              capture_output=True, text=True)
        check(done.returncode != 0 and "/steps/0/metric" in done.stderr, f"malformed accepted file: {done.stderr}")
    print("history: steps found, accepted steps silenced, a new step alerts")


if __name__ == "__main__":
    main()
