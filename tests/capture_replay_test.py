#!/usr/bin/python3
"""Captures that reproduce (`run --capture`, bench/cli/capture.h): room captured on both APIs here; the GL capture
replayed by RenderDoc's own replay (scripts/replay_renderdoc.py, headless) gives the harness's lit image bit for
bit, as GL's invariance rule requires of the same commands on the same implementation (and Vulkan's, captured with
--capture-tool renderdoc, the same, as Vulkan's invariance appendix does); the GFXReconstruct capture replays to
the end in gfxrecon-replay (the harness never presents, so it has no frame to take a screenshot of); and a
planted bug (a test-only lookup perturbation of half a texel) is replayed as the bug: the replayed image is the
perturbed one, not the clean one. Usage: capture_replay_test.py OMNISHADOW_BINARY"""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPLAY = os.path.join(ROOT, "scripts", "replay_renderdoc.py")
CASE = "room_c64_f80x60_six_pass_hard_linear_depth_d32f"


def pixels(path):
    from PIL import Image
    return list(Image.open(path).convert("RGBA").getdata())


def capture(binary, out, backends, *extra):
    """`run --capture all` into `out`, named relative to its parent (the run's working folder): a capture tool that
    starts the capture run elsewhere would lose it."""
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    done = subprocess.run([binary, "run", "--backend", backends, "--scene", "room", "--cube", "64", "--frame", "80x60",
                           "--technique", "six_pass", "--filter", "hard", "--frames", "1", "--warmup", "0",
                           "--benchmark_repetitions=1", "--images", "all", "--capture", "all", "--out",
                           os.path.basename(out), *extra],
                          capture_output=True, text=True, env=env, cwd=os.path.dirname(out))
    return done


def replay_rdc(capture_file, png):
    env = dict(os.environ, EGL_PLATFORM="surfaceless", XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    return subprocess.run(["/usr/bin/python3", REPLAY, capture_file, "--out", png], capture_output=True, text=True,
                          env=env)


def harness_lit(out, api):
    found = glob.glob(os.path.join(out, "captures", f"{api}_{CASE}.run", "images", "**", "lit.png"), recursive=True)
    return found[0] if found else None


def main():
    binary = sys.argv[1]
    missing = [p for p, ok in (("renderdoccmd", shutil.which("renderdoccmd")),
                               ("gfxreconstruct", shutil.which("gfxrecon-replay")),
                               ("python3-renderdoc", os.path.exists("/usr/lib/python3/dist-packages/renderdoc.so")),
                               ("python3-pil", subprocess.run(["/usr/bin/python3", "-c", "import PIL"]).returncode == 0))
               if not ok]
    if missing:
        print(f"SKIP: needs Debian packages {', '.join(missing)} (scripts/setup.sh installs them)")
        sys.exit(77)
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        clean = os.path.join(tmp, "clean")
        done = capture(binary, clean, "gl,vulkan")
        gl_capture = os.path.join(clean, "captures", f"gl_{CASE}.rdc")
        vk_capture = os.path.join(clean, "captures", f"vulkan_{CASE}.gfxr")
        if done.returncode != 0 or not os.path.exists(gl_capture) or not os.path.exists(vk_capture):
            print(f"FAIL: captures not written (exit {done.returncode}): {done.stdout[-800:]} {done.stderr[-400:]}")
            sys.exit(1)
        replayed = os.path.join(tmp, "clean.png")
        r = replay_rdc(gl_capture, replayed)
        lit = harness_lit(clean, "gl")
        if r.returncode != 0 or not lit:
            problems.append(f"GL replay: exit {r.returncode} {r.stderr.strip()[-400:]}; harness image {lit}")
        else:
            a, b = pixels(replayed), pixels(lit)
            same = sum(x == y for x, y in zip(a, b))
            if len(a) != len(b) or same != len(a):
                problems.append(f"GL: the replayed image equals the harness's in {same} of {len(a)} pixels")
        v = subprocess.run(["gfxrecon-replay", vk_capture], capture_output=True, text=True)
        if v.returncode != 0 or "Incomplete block" in v.stdout + v.stderr:
            problems.append(f"Vulkan replay: exit {v.returncode}: {(v.stdout + v.stderr).strip()[-300:]}")

        # --capture-tool renderdoc on Vulkan: its check frame replayed by RenderDoc equals the harness's too.
        rdv = os.path.join(tmp, "rdv")
        done = capture(binary, rdv, "vulkan", "--capture-tool", "renderdoc")
        rdv_capture = os.path.join(rdv, "captures", f"vulkan_{CASE}.rdc")
        rdv_png = os.path.join(tmp, "rdv.png")
        r = replay_rdc(rdv_capture, rdv_png) if os.path.exists(rdv_capture) else None
        rdv_lit = harness_lit(rdv, "vulkan")
        listed = json.load(open(os.path.join(rdv, "captures.json")))["captures"] if done.returncode == 0 else []
        if not listed or listed[0].get("tool") != "renderdoc" or "replay_renderdoc.py" not in listed[0].get("replay", ""):
            problems.append(f"Vulkan through RenderDoc: captures.json must name RenderDoc and its replay: {listed}")
        if r is None or r.returncode != 0 or not rdv_lit:
            problems.append(f"Vulkan through RenderDoc: no capture or replay (exit {done.returncode}, "
                            f"{r and r.stderr[-300:]})")
        elif pixels(rdv_png) != pixels(rdv_lit):
            problems.append("Vulkan through RenderDoc: the replayed image differs from the harness's")

        # The planted bug, captured and replayed: the replay shows it.
        bug = os.path.join(tmp, "bug")
        done = capture(binary, bug, "gl", "--lookup-perturb", "0.5")
        bug_capture = os.path.join(bug, "captures", f"gl_{CASE}.rdc")
        bug_png = os.path.join(tmp, "bug.png")
        r = replay_rdc(bug_capture, bug_png) if os.path.exists(bug_capture) else None
        bug_lit = harness_lit(bug, "gl")
        if r is None or r.returncode != 0 or not bug_lit or not lit:
            problems.append(f"planted bug: no capture or replay (exit {done.returncode}, {r and r.stderr[-300:]})")
        else:
            replayed_bug, perturbed, clean_lit = pixels(bug_png), pixels(bug_lit), pixels(lit)
            if replayed_bug != perturbed:
                problems.append("planted bug: the replay differs from the harness's perturbed image")
            differ = sum(x != y for x, y in zip(replayed_bug, clean_lit))
            if differ == 0:
                problems.append("planted bug: the replay equals the clean image (the bug was not replayed)")
            print(f"planted bug replayed: {differ} of {len(clean_lit)} pixels differ from the clean image")
    for p in problems:
        print("FAIL", p)
    print(f"capture_replay: {len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
