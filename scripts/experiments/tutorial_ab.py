#!/usr/bin/python3
"""The harness's timed frame against the point-shadow tutorial's own way of rendering it. A benchmark,
not a test.

Alternates, in one sitting, the harness (`run --backend gl --scene room --cube 1024 --frame 800x600 --technique
geometry_shader --filter hard,pcf_grid64,pcf_disk20`) with samples/tutorial (the same room, camera and light
rendered as the tutorial renders it: one RGBA8 colour buffer and a depth buffer, cleared each frame, the chapter's
shaders; with its diffuse texture, and with the harness's constant albedo). Both time a pass from its first command
to glFinish. Same formats in both: the cube D32F, and the camera's depth buffer D32F as the harness's lighting
target (the sample's GLFW-default D24S8 is measured beside it: a cheaper depth buffer makes a cheaper lighting
pass). Reports per filter the median over rounds of each program's median lighting and shadow pass, and the
harness's passes as multiples of the sample's, wall and GPU time (timer queries in both): PASS where at most
1.1x, exit 1 otherwise.

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
LIMIT = 1.1  # a pass above 1.1x the tutorial's own rendering on a GPU means the harness adds something


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
    out = {}
    for c in cases:
        t = c["timing"]
        out[c["axes"]["filter"]] = {p: t[p]["cpu_wall_ms"]["median"] for p in ("shadow", "lighting")}
        # GPU time where the harness's timer passed its sanity check (results.json has it only then).
        for p in ("shadow", "lighting"):
            gpu = t[p].get("gpu_ms") if c.get("gpu_timer", {}).get("reliable", True) else None
            out[c["axes"]["filter"]][p + "_gpu"] = gpu["median"] if gpu else None
    return out


def run_sample(filter_name, albedo, camera_depth, frames):
    # The harness's cube format (D32F), named: the tutorial's unsized format is 24-bit on NVIDIA.
    cmd = [os.path.join(BUILD, "omnishadow_tutorial_sample"), "--filter", filter_name, "--albedo", albedo,
           "--depth-format", "d32f", "--camera-depth", camera_depth, "--frames", str(frames), "--warmup", "5"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"tutorial_ab: {' '.join(cmd)} failed: {done.stderr.strip()}")
    r = json.loads(done.stdout)
    return {"shadow": r["shadow_ms"], "lighting": r["lighting_ms"], "shadow_gpu": r["shadow_gpu_ms"],
            "lighting_gpu": r["lighting_gpu_ms"], "renderer": r["renderer"]}


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
    # sample_texture: the tutorial's shaders and texture at the harness's formats (the verdict's reference);
    # sample_constant: the harness's albedo; sample_d24s8: the camera depth of GLFW's default framebuffer.
    arms = ["harness", "sample_texture", "sample_constant", "sample_d24s8"]
    passes = ("shadow", "lighting", "shadow_gpu", "lighting_gpu")
    samples = {arm: {f: {p: [] for p in passes} for f in FILTERS} for arm in arms}
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
                    albedo = "constant" if arm == "sample_constant" else "texture"
                    got[f] = run_sample(f, albedo, "d24s8" if arm == "sample_d24s8" else "d32f", args.frames)
                    renderer = got[f]["renderer"]
            for f in FILTERS:
                for p in passes:
                    if got[f][p] is not None:
                        samples[arm][f][p].append(got[f][p])
        print(f"round {r + 1}/{args.rounds} done ({time.time() - started:.0f} s)", flush=True)

    med = {arm: {f: {p: statistics.median(v) if v else None for p, v in samples[arm][f].items()} for f in FILTERS}
           for arm in arms}
    md = [f"# The harness's timed frame against the tutorial's sample\n",
          f"`scripts/experiments/tutorial_ab.py --rounds {args.rounds} --frames {args.frames}` on {renderer}: the room at "
          "800x600, cube 1024, geometry-shader shadow pass, light at the origin. Rounds alternate the harness and "
          "`omnishadow_tutorial_sample` (the tutorial's framebuffer, shaders and texture; `constant`: the harness's "
          "albedo instead of the texture; `d24s8`: GLFW's default camera depth instead of the harness's D32F). "
          "Medians over rounds of each run's median pass time (ms, first command to glFinish) and GPU time (timer "
          "queries around the pass). The harness's passes against the sample's at the same depth formats (cube and "
          f"camera D32F), wall and GPU: PASS where at most {LIMIT}x.\n",
          "| filter | harness lighting | sample lighting (texture) | sample lighting (constant) | sample lighting "
          "(texture, D24S8 camera) | harness / sample (texture) | harness / sample (constant) | harness / sample "
          "(D24S8 camera) | harness lighting GPU | sample lighting GPU | sample lighting GPU (D24S8 camera) | "
          "harness shadow | sample shadow |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    result = {"rounds": args.rounds, "frames": args.frames, "renderer": renderer, "medians": med, "samples": samples}
    for f in FILTERS:
        h, t, c, d = (med[a][f] for a in ("harness", "sample_texture", "sample_constant", "sample_d24s8"))
        gpu = lambda v: "-" if v is None else f"{v:.3f}"
        md.append(f"| {f} | {h['lighting']:.2f} | {t['lighting']:.2f} | {c['lighting']:.2f} | {d['lighting']:.2f} | "
                  f"{h['lighting'] / t['lighting']:.2f}x | {h['lighting'] / c['lighting']:.2f}x | "
                  f"{h['lighting'] / d['lighting']:.2f}x | {gpu(h['lighting_gpu'])} | {gpu(t['lighting_gpu'])} | "
                  f"{gpu(d['lighting_gpu'])} | {h['shadow']:.2f} | {t['shadow']:.2f} |")
    # The apples-to-apples verdict: the harness's pass against the sample's, the sample as the tutorial ships it
    # (texture), wall and GPU time; a pass above LIMIT says what the harness adds there.
    md += ["", "| filter | pass | time | harness ms | sample ms | ratio | verdict |", "|---|---|---|---|---|---|---|"]
    failed = []
    for f in FILTERS:
        for p in ("shadow", "lighting"):
            for kind, key in (("wall", p), ("GPU", p + "_gpu")):
                h, t = med["harness"][f][key], med["sample_texture"][f][key]
                if h is None or t is None or t <= 0:
                    md.append(f"| {f} | {p} | {kind} | - | - | - | no {kind} time |")
                    continue
                ratio = h / t
                verdict = "PASS" if ratio <= LIMIT else "FAIL"
                if verdict == "FAIL":
                    failed.append(f"{f} {p} {kind} {ratio:.2f}x")
                md.append(f"| {f} | {p} | {kind} | {h:.3f} | {t:.3f} | {ratio:.2f}x | {verdict} |")
    md += ["", f"**{'PASS' if not failed else 'FAIL'}**: harness within {LIMIT}x of the sample"
           + ("" if not failed else ": " + ", ".join(failed))]
    result["verdict"] = {"limit": LIMIT, "failed": failed}
    text = "\n".join(md) + "\n"
    print(text)
    with open(os.path.join(args.out, "tutorial_ab.json"), "w") as f:
        json.dump(result, f, indent=2)
    if args.docs:
        with open(os.path.join(ROOT, "docs", "tutorial-ab.md"), "w") as f:
            f.write(text)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
