#!/usr/bin/python3
"""Every SPIR-V module the Vulkan backend embeds declares only capabilities its device can enable, and nv_swizzle's
passthrough geometry stage still holds the inputs it passes on.

Two ways a module that glslang and spirv-val accept is still wrong on a device (both seen on NVIDIA):
- glslang's full gl_MeshPerPrimitiveEXT block made the mesh stage declare FragmentShadingRateKHR, a feature
  vk_context.cpp never enables (the first mesh_shader case died with SIGSEGV);
- spirv-opt (-O) removed the PassthroughNV inputs of shadow_swizzle.geom, which its code never reads: the stage
  passed nothing on and the cube stayed empty.
A self-test compiles the passthrough stage with -O (where glslc is present) and shows the check fails on it.

Usage: spirv_modules_test.py SPIRV_DIR SHADER_DIR GLSLC
"""
import pathlib
import struct
import subprocess
import sys
import tempfile

OP_CAPABILITY, OP_DECORATE = 17, 71
DECORATION_PASSTHROUGH_NV = 5250
# Capabilities and the device feature that vk_context.cpp enables for them (core ones need none).
ALLOWED = {
    1: "Shader", 2: "Geometry (geometryShader)", 32: "ClipDistance (shaderClipDistance)",
    34: "ImageCubeArray", 45: "SampledCubeArray (imageCubeArray, layout cube_array)", 49: "StorageImageExtendedFormats (shaderStorageImageExtendedFormats)",
    50: "ImageQuery", 57: "MultiViewport (multiViewport, nv_swizzle)", 69: "ShaderLayer (shaderOutputLayer)",
    70: "ShaderViewportIndex (shaderOutputViewportIndex: vs_layer into an atlas)",
    4427: "DrawParameters", 4439: "MultiView (multiview)",
    5251: "GeometryShaderPassthroughNV (VK_NV_geometry_shader_passthrough)",
    5254: "ShaderViewportIndexLayerEXT (shaderOutputLayer)", 5255: "ShaderViewportMaskNV (VK_NV_viewport_array2)",
    5283: "MeshShadingEXT (VK_EXT_mesh_shader)",
}
NAMES = {4422: "FragmentShadingRateKHR", 5266: "MeshShadingNV", 33: "CullDistance", 35: "SampleRateShading"}


def instructions(words):
    i = 5  # after the header
    while i < len(words):
        count, opcode = words[i] >> 16, words[i] & 0xFFFF
        if count == 0:
            raise ValueError("malformed SPIR-V: an instruction of 0 words")
        yield opcode, words[i + 1:i + count]
        i += count


def problems(path):
    data = path.read_bytes()
    words = struct.unpack(f"<{len(data) // 4}I", data)
    if not words or words[0] != 0x07230203:
        return [f"{path.name}: not a little-endian SPIR-V module"]
    capabilities = [ops[0] for op, ops in instructions(words) if op == OP_CAPABILITY]
    passthrough = sum(1 for op, ops in instructions(words) if op == OP_DECORATE and ops[1] == DECORATION_PASSTHROUGH_NV)
    found = [f"{path.name}: capability {NAMES.get(c, c)} is not one the device enables"
             for c in capabilities if c not in ALLOWED]
    if 5251 in capabilities:
        # gl_in's gl_Position always; the world position too unless the variant writes depth only.
        want = 1 if "DEPTH_ONLY" in path.name else 2
        if passthrough != want:
            found.append(f"{path.name}: {passthrough} PassthroughNV input(s), want {want} (an optimiser removed them?)")
    return found


def self_test(shader_dir, glslc):
    if not pathlib.Path(glslc).exists():
        print(f"self-test not run: {glslc} is missing (Debian package glslc)")
        return True
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "shadow_swizzle.geom.TECHNIQUE_NV_SWIZZLE.spv"
        subprocess.run([glslc, "--target-env=vulkan1.2", "-O", "-DTECHNIQUE_NV_SWIZZLE",
                        str(shader_dir / "shadow_swizzle.geom"), "-o", str(out)], check=True)
        caught = problems(out)
    print(f"self-test: the passthrough stage compiled with -O is {'caught' if caught else 'NOT caught'}")
    return bool(caught)


def main():
    spirv_dir, shader_dir, glslc = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), sys.argv[3]
    if not spirv_dir.is_dir():  # a carried build (../shared/gpu/bundle.sh) holds the binaries, not the modules
        print(f"SKIP: {spirv_dir} is not here: the build's SPIR-V modules were not carried with it")
        return 77
    modules = sorted(spirv_dir.glob("*.spv"))
    found = [p for m in modules for p in problems(m)]
    for p in found:
        print(p)
    swizzle = [m for m in modules if m.name.startswith("shadow_swizzle.geom") and "EMULATE" not in m.name]
    mesh = [m for m in modules if m.name.startswith("shadow_mesh.")]
    print(f"{len(modules)} modules checked ({len(swizzle)} passthrough, {len(mesh)} task/mesh), {len(found)} problem(s)")
    ok = self_test(shader_dir, glslc)
    return 0 if modules and swizzle and mesh and not found and ok else 1


if __name__ == "__main__":
    sys.exit(main())
