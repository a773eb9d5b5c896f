#!/usr/bin/python3
"""cmake/embed_spirv.py's --optimization: each level embeds what glslc writes at its own flag, a passthrough stage
stays unoptimised at every level (spirv-opt removes the inputs it passes on), the embedded C++ says which level it
holds (the Vulkan backend reports it in results.json), and an unknown level is refused naming the option.

Run on two variants in a private cache, so it neither reads nor fills the build's.

Usage: embed_spirv_test.py EMBED_SPIRV SHADER_DIR GLSLC
"""
import pathlib
import subprocess
import sys
import tempfile

LIGHTING = "lighting.frag:STORAGE_LINEAR_DEPTH,FILTER_PCF_DISK20,LAYOUT_TETRAHEDRAL"
PASSTHROUGH = "shadow_swizzle.geom:TECHNIQUE_NV_SWIZZLE"
FLAGS = {"performance": "-O", "size": "-Os", "none": "-O0"}


def glslc_module(glslc, shader_dir, key, level, out):
    file, _, defines = key.partition(":")
    subprocess.run([glslc, "--target-env=vulkan1.2", level, *[f"-D{d}" for d in defines.split(",")],
                    str(shader_dir / file), "-o", str(out)], check=True)
    return out.read_bytes()


def embed(script, glslc, shader_dir, tmp, level):
    run_dir = tmp / level
    run_dir.mkdir()
    (run_dir / "list.txt").write_text(f"{LIGHTING}\n{PASSTHROUGH}\n")
    return subprocess.run(["/usr/bin/python3", str(script), "--glslc", glslc, "--list", str(run_dir / "list.txt"),
                           "--shader-dir", str(shader_dir), "--spirv-dir", str(run_dir / "spirv"),
                           "--output", str(run_dir / "embedded.cpp"), "--cache", str(tmp / "cache"),
                           "--optimization", level], capture_output=True, text=True), run_dir


def main():
    script, shader_dir, glslc = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), sys.argv[3]
    if not pathlib.Path(glslc).exists():  # a carried build (../shared/gpu/bundle.sh) runs where no glslc is
        print(f"SKIP: {glslc} is missing here (Debian package glslc): nothing to compile the levels with")
        return 77
    failures = []
    with tempfile.TemporaryDirectory() as t:
        tmp = pathlib.Path(t)
        lighting_modules = {}
        for level, flag in FLAGS.items():
            run, run_dir = embed(script, glslc, shader_dir, tmp, level)
            if run.returncode != 0:
                failures.append(f"--optimization {level}: exit {run.returncode}: {run.stderr.strip()}")
                continue
            name = LIGHTING.replace(":", ".").replace(",", "_") + ".spv"
            lighting = (run_dir / "spirv" / name).read_bytes()
            lighting_modules[level] = lighting
            if lighting != glslc_module(glslc, shader_dir, LIGHTING, flag, tmp / f"{level}.spv"):
                failures.append(f"--optimization {level}: the lighting module is not glslc {flag}'s")
            passthrough = (run_dir / "spirv" / (PASSTHROUGH.replace(":", ".") + ".spv")).read_bytes()
            if passthrough != glslc_module(glslc, shader_dir, PASSTHROUGH, "-O0", tmp / f"{level}_pt.spv"):
                failures.append(f"--optimization {level}: the passthrough stage is not glslc -O0's")
            said = f'return "{level} (glslc {flag})";'
            if said not in (run_dir / "embedded.cpp").read_text():
                failures.append(f"--optimization {level}: the embedded C++ does not say {said}")
        if len(set(lighting_modules.values())) != len(lighting_modules):
            failures.append("two levels embedded the same lighting module: the level never reached glslc")
        run, _ = embed(script, glslc, shader_dir, tmp, "fast")
        if run.returncode != 2 or "--optimization" not in run.stderr:
            failures.append(f"--optimization fast: exit {run.returncode}, stderr {run.stderr.strip()!r} "
                            "(want 2, naming the option)")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(FLAGS)} levels and one unknown checked, {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
