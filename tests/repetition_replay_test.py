#!/usr/bin/python3
"""scripts/experiments/repetition_replay.py on two small real runs: its mirror of the harness's --precision rule stops every
case arm where the harness stopped it, and every fixed count up to the recorded one is replayed and compared."""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.environ["OMNISHADOW_BIN"]


def run(out, *extra):
    # Two cases, each four times in the same rounds (A/A and A/B arms), two frames a repetition: seconds here.
    cmd = [BINARY, "run", "--backend", "gl", "--scene", "room", "--cube", "64", "--frame", "64x48",
           "--technique", "six_pass,geometry_shader", "--filter", "hard", "--frames", "2", "--warmup", "0",
           "--no-images", "--no-accuracy", "--inject-fragment-work", "0,20", "--replicas", "2", "--out", out, *extra]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          env={**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR", "/tmp")})
    assert done.returncode == 0, f"{' '.join(cmd)}: exit {done.returncode}\n{done.stderr[-2000:]}"


def main():
    with tempfile.TemporaryDirectory() as work:
        os.symlink(BINARY, os.path.join(work, "omnishadow"))
        run(os.path.join(work, "t00-fixed10"), "--benchmark_repetitions=10")
        # 3%: here some arms stop between the minimum and the cap, the others are held to "never met it sooner".
        run(os.path.join(work, "t00-precision3"), "--benchmark_repetitions=7", "--precision", "3",
            "--max-repetitions", "10")
        done = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "experiments", "repetition_replay.py"), work,
                               "--precision", "3,10", "--minimum", "7", "--bootstrap", "20"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert done.returncode == 0, done.stderr[-2000:]
        with open(os.path.join(work, "repetition_replay.json")) as f:
            report = json.load(f)
    rows = report["rows"]
    assert sorted(r for r in rows if r.startswith("fixed")) == [f"fixed{n}" for n in (10, 7, 8, 9)], rows.keys()
    assert rows["fixed7"]["spent"] == 2 * 7 and rows["fixed10"]["spent"] == 2 * 10, rows
    for name in ("precision3/min7", "precision10/min7"):
        assert 2 * 7 <= rows[name]["spent"] <= 2 * 10, (name, rows[name])
    real = report["real"]["3"]
    assert real["total"] == 8 and real["agree"] == real["total"], real  # 2 cases x 4 arms, each stopped alike
    assert real["minimum"] == 7 and real["cap"] == 10, real
    print("repetition_replay: mirror agrees on", real["total"], "case arms;", len(rows), "rules replayed")


if __name__ == "__main__":
    main()
