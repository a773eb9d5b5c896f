#!/usr/bin/python3
"""The harness's timed frame against the point-shadow tutorial's own way of rendering it. A benchmark,
not a test.

Alternates, in one sitting, the harness (`run --backend gl --scene room --cube 1024 --frame 800x600 --technique
geometry_shader --filter hard,pcf_grid64,pcf_disk20`) with samples/tutorial (the same room, camera and light
rendered as the tutorial renders it: one RGBA8 colour buffer and a depth buffer, cleared each frame, the chapter's
shaders; with its diffuse texture, and with the harness's constant albedo). Both time a pass from its first command
to glFinish. Reports per filter the median over rounds of each program's median lighting and shadow pass, and the
harness's lighting pass as a multiple of the sample's (target: at most 1.2).

Usage: scripts/experiments/tutorial_ab.py [--rounds 5] [--frames 30] [--out DIR] [--docs]
--docs writes docs/tutorial-ab.md.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "build", "release")
FILTERS = ["hard", "pcf_grid64", "pcf_disk20"]


def run_harness(out, frames):
    cmd = [os.path.join(BUILD, "omnishadow"), "run", "--backend", "gl", "--scene", "room", "--cube", "1024",
           "--frame", "800x600", "--technique", "geometry_shader", "--filter", ",".join(FILTERS),
           "--frames", str(frames), "--warmup", "5", "--no-accuracy", "--no-images", "--benchmark_repetitions=1",
           "--out", out]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"tutorial_ab: {' '.join(cmd)} failed:\n{done.stderr[-1500:]}")
    with open(os.path.join(out, "results.json")) as f:
        cases = json.load(f)["omnishadow"]["cases"]
    return {c["axes"]["filter"]: {p: c["timing"][p]["cpu_wall_ms"]["median"] for p in ("shadow", "lighting")}
            for c in cases}


def run_sample(filter_name, albedo, frames):
    # The harness's depth format (D32F), named: the tutorial's unsized format is 24-bit on NVIDIA.
    cmd = [os.path.join(BUILD, "omnishadow_tutorial_sample"), "--filter", filter_name, "--albedo", albedo,
           "--depth-format", "d32f", "--frames", str(frames), "--warmup", "5"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"tutorial_ab: {' '.join(cmd)} failed: {done.stderr.strip()}")
    r = json.loads(done.stdout)
    return {"shadow": r["shadow_ms"], "lighting": r["lighting_ms"], "renderer": r["renderer"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--out", default="/tmp/omnishadow-tutorial-ab")
    parser.add_argument("--docs", action="store_true")
    args = parser.parse_args()
    for exe in ("omnishadow", "omnishadow_tutorial_sample"):
        if not os.path.exists(os.path.join(BUILD, exe)):
            sys.exit(f"tutorial_ab: {exe} missing; run scripts/build.sh first")
    if os.path.exists(args.out):
        shutil.rmtree(args.out)  # the harness refuses a folder that already holds a run
    os.makedirs(args.out)
    arms = ["harness", "sample_texture", "sample_constant"]
    samples = {arm: {f: {"shadow": [], "lighting": []} for f in FILTERS} for arm in arms}
    renderer = ""
    started = time.time()
    for r in range(args.rounds):
        order = arms if r % 2 == 0 else arms[::-1]  # neither program always runs first
        for arm in order:
            if arm == "harness":
                got = run_harness(os.path.join(args.out, f"harness{r}"), args.frames)
            else:
                got = {}
                for f in FILTERS:
                    got[f] = run_sample(f, arm.split("_")[1], args.frames)
                    renderer = got[f]["renderer"]
            for f in FILTERS:
                for p in ("shadow", "lighting"):
                    samples[arm][f][p].append(got[f][p])
        print(f"round {r + 1}/{args.rounds} done ({time.time() - started:.0f} s)", flush=True)

    med = {arm: {f: {p: statistics.median(v) for p, v in samples[arm][f].items()} for f in FILTERS} for arm in arms}
    md = [f"# The harness's timed frame against the tutorial's sample\n",
          f"`scripts/experiments/tutorial_ab.py --rounds {args.rounds} --frames {args.frames}` on {renderer}: the room at "
          "800x600, cube 1024, geometry-shader shadow pass, light at the origin. Rounds alternate the harness and "
          "`omnishadow_tutorial_sample` (the tutorial's framebuffer, shaders and texture; `constant`: the harness's "
          "albedo instead of the texture). Medians over rounds of each run's median pass time (ms, first command to "
          "glFinish).\n",
          "| filter | harness lighting | sample lighting (texture) | sample lighting (constant) | harness / sample "
          "(texture) | harness / sample (constant) | harness shadow | sample shadow |",
          "|---|---|---|---|---|---|---|---|"]
    result = {"rounds": args.rounds, "frames": args.frames, "renderer": renderer, "medians": med, "samples": samples}
    for f in FILTERS:
        h, t, c = med["harness"][f], med["sample_texture"][f], med["sample_constant"][f]
        md.append(f"| {f} | {h['lighting']:.2f} | {t['lighting']:.2f} | {c['lighting']:.2f} | "
                  f"{h['lighting'] / t['lighting']:.2f}x | {h['lighting'] / c['lighting']:.2f}x | {h['shadow']:.2f} | "
                  f"{t['shadow']:.2f} |")
    text = "\n".join(md) + "\n"
    print(text)
    with open(os.path.join(args.out, "tutorial_ab.json"), "w") as f:
        json.dump(result, f, indent=2)
    if args.docs:
        with open(os.path.join(ROOT, "docs", "tutorial-ab.md"), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
