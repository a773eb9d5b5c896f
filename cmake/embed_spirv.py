#!/usr/bin/python3
"""Compiles every SPIR-V variant the Vulkan backend can ask for and embeds them in one C++ file.

LIST holds one "file:DEFINE,DEFINE" key per line (written by list_spirv_variants from the C++ tables). Each module
is compiled by glslc from SHADER_DIR, in parallel, into a content-addressed cache shared by every build tree on the
machine (release, asan, the fleet plays' builds, the gate's base commit): a module's cache name is a hash of glslc's
version, its flags and the text of its file and every file that file includes, so a tree whose shaders did not
change compiles nothing. The modules are copied to SPIRV_DIR/<file>.<defines>.spv (tests read them there) and
concatenated into SPIRV_DIR/modules.pack, which OUTPUT (a C++ file defining omnishadow::vk::embedded_spirv())
includes with the assembler's .incbin: the 8 MB of words never pass through the C++ compiler as text.

Usage: embed_spirv.py --glslc G --list L --shader-dir S --spirv-dir D --output O [--cache C] [--jobs N]
                      [--optimization performance|size|none]
"""
import argparse
import concurrent.futures
import functools
import hashlib
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
# A passthrough geometry stage (NV_geometry_shader_passthrough) reads none of the inputs it passes on: only their
# PassthroughNV decoration uses them, and spirv-opt (-O) removes them as dead, leaving a stage that passes nothing
# (NVIDIA rendered an empty cube). Such a file is compiled unoptimised; tests/spirv_modules_test.py checks the
# inputs are there.
PASSTHROUGH = re.compile(r"layout\s*\(\s*passthrough")
# --optimization: glslc's level for every other module. "none" hands the driver's compiler the program as glslang
# wrote it, as an engine that ships unoptimised SPIR-V does (on lavapipe that alone doubled the tetrahedral
# pcf_disk20 lighting: docs/layouts.md).
OPTIMIZATION_FLAGS = {"performance": "-O", "size": "-Os", "none": "-O0"}
CACHE_DAYS = 14  # cache entries unused for this long are removed


def default_cache():
    if os.environ.get("OMNISHADOW_SPIRV_CACHE"):
        return pathlib.Path(os.environ["OMNISHADOW_SPIRV_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or (os.path.join(os.environ["HOME"], ".cache") if "HOME" in os.environ else None)
    return pathlib.Path(base or tempfile.gettempdir()) / "omnishadow" / "spirv"


def texts_with_includes(shader_dir, name, seen=None):
    """The file's text and, depth first, the text of every file it includes (each once)."""
    seen = set() if seen is None else seen
    if name in seen:
        return []
    seen.add(name)
    text = (shader_dir / name).read_text()
    out = [name, text]
    for inc in INCLUDE.findall(text):
        out += texts_with_includes(shader_dir, inc, seen)
    return out


@functools.lru_cache(maxsize=None)
def sources_of(shader_dir, file):
    return tuple(texts_with_includes(shader_dir, file))


def variant(shader_dir, key, glslc_version, optimization="performance"):
    file, _, defines = key.partition(":")
    define_list = [d for d in defines.split(",") if d]
    text = (shader_dir / file).read_text()
    level = "-O0" if PASSTHROUGH.search(text) else OPTIMIZATION_FLAGS[optimization]
    flags = ["--target-env=vulkan1.2", level] + [f"-D{d}" for d in define_list]
    digest = hashlib.sha256("\0".join([glslc_version, *flags, *sources_of(shader_dir, file)]).encode())
    return {"key": key, "file": file, "flags": flags, "hash": digest.hexdigest(),
            "name": f"{file}.{'_'.join(define_list)}.spv"}


def compile_into_cache(glslc, shader_dir, cache, v):
    target = cache / f"{v['hash']}.spv"
    if target.exists():
        os.utime(target)  # keeps a used entry out of the pruning
        return False
    fd, tmp = tempfile.mkstemp(dir=cache, suffix=".tmp")
    os.close(fd)
    run = subprocess.run([glslc, *v["flags"], str(shader_dir / v["file"]), "-o", tmp], capture_output=True, text=True)
    if run.returncode != 0:
        os.unlink(tmp)
        raise RuntimeError(f"glslc {v['key']}: {run.stderr.strip()}")
    os.replace(tmp, target)  # atomic: a build beside this one never reads half a module
    return True


def write_if_different(path, data):
    if path.exists() and path.read_bytes() == data:
        return
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def prune(cache):
    cutoff = time.time() - CACHE_DAYS * 86400
    for entry in cache.glob("*.spv"):
        try:
            if entry.stat().st_mtime < cutoff:
                entry.unlink()
        except FileNotFoundError:
            pass  # another build pruned it first


def cpp_file(pack_path, table, pack_hash, optimization="performance"):
    rows = "".join(f'      {{"{key}", {{{offset}, {count}}}}},\n' for key, offset, count in table)
    # The pack's hash is a string the compiler sees, so a changed pack changes this file's preprocessed text (ccache
    # and make rebuild it); .incbin's file is invisible to both.
    return f"""// Generated by cmake/embed_spirv.py from shaders/ compiled by glslc; do not edit.
#include "backends/vulkan/vk_spirv.h"

#include <utility>

// The modules, little-endian 32-bit words back to back, 4-byte aligned (SPIR-V's word size).
__asm__(".pushsection .rodata\\n"
        ".balign 4\\n"
        "omnishadow_spirv_pack:\\n"
        ".incbin \\"{pack_path}\\"\\n"
        ".popsection\\n");
extern "C" const uint32_t omnishadow_spirv_pack[] __asm__("omnishadow_spirv_pack");

namespace omnishadow::vk {{
const char* embedded_spirv_pack_hash() {{ return "{pack_hash}"; }}
const char* embedded_spirv_optimization() {{ return "{optimization} (glslc {OPTIMIZATION_FLAGS[optimization]})"; }}

const std::map<std::string, std::vector<uint32_t>>& embedded_spirv() {{
  static const std::map<std::string, std::vector<uint32_t>> modules = [] {{
    // key -> {{first word, word count}} in the pack
    const std::pair<const char*, std::pair<size_t, size_t>> rows[] = {{
{rows}    }};
    std::map<std::string, std::vector<uint32_t>> out;
    for (const auto& [key, span] : rows)
      out.emplace(key, std::vector<uint32_t>(omnishadow_spirv_pack + span.first, omnishadow_spirv_pack + span.first + span.second));
    return out;
  }}();
  return modules;
}}
}}  // namespace omnishadow::vk
"""


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--glslc", required=True)
    p.add_argument("--list", required=True, type=pathlib.Path)
    p.add_argument("--shader-dir", required=True, type=pathlib.Path)
    p.add_argument("--spirv-dir", required=True, type=pathlib.Path)
    p.add_argument("--output", required=True, type=pathlib.Path)
    p.add_argument("--cache", type=pathlib.Path, default=None)
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    p.add_argument("--optimization", choices=sorted(OPTIMIZATION_FLAGS), default="performance",
                   help="glslc's level for every module but a passthrough stage (always -O0)")
    a = p.parse_args()
    cache = a.cache or default_cache()
    cache.mkdir(parents=True, exist_ok=True)
    a.spirv_dir.mkdir(parents=True, exist_ok=True)
    glslc_version = subprocess.run([a.glslc, "--version"], capture_output=True, text=True, check=True).stdout
    keys = [k.strip() for k in a.list.read_text().splitlines() if k.strip()]
    variants = [variant(a.shader_dir, k, glslc_version, a.optimization) for k in keys]
    try:
        with concurrent.futures.ThreadPoolExecutor(max(1, a.jobs)) as pool:
            compiled = sum(pool.map(lambda v: compile_into_cache(a.glslc, a.shader_dir, cache, v), variants))
    except RuntimeError as e:
        print(f"embed_spirv: {e}", file=sys.stderr)
        return 1
    pack, table = bytearray(), []
    for v in variants:
        words = (cache / f"{v['hash']}.spv").read_bytes()
        if len(words) % 4:
            print(f"embed_spirv: {v['key']}: {len(words)} bytes is not a whole number of SPIR-V words", file=sys.stderr)
            return 1
        write_if_different(a.spirv_dir / v["name"], words)
        table.append((v["key"], len(pack) // 4, len(words) // 4))
        pack += words
    pack_path = (a.spirv_dir / "modules.pack").resolve()
    if any(c in str(pack_path) for c in '"\\\n'):
        print(f"embed_spirv: --spirv-dir {a.spirv_dir}: a path with a quote, backslash or newline cannot be .incbin'd",
              file=sys.stderr)
        return 1
    write_if_different(pack_path, bytes(pack))
    pack_hash = hashlib.sha256(pack).hexdigest()
    a.output.parent.mkdir(parents=True, exist_ok=True)
    write_if_different(a.output, cpp_file(pack_path, table, pack_hash, a.optimization).encode())
    prune(cache)
    print(f"embed_spirv: {len(variants)} modules, {compiled} compiled, {len(variants) - compiled} from {cache}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
