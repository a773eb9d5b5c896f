#!/usr/bin/env bash
# The GL-only shader variants (nv_swizzle's passthrough GS, mesh_shader's NV task and mesh stages) compile with
# glslang as OpenGL GLSL 4.50: Mesa cannot run them, so this is where a GLSL error in them is caught.
# Usage: gl_shaders_glslang.sh GL_SHADER_SOURCES_BINARY
set -euo pipefail
if ! command -v glslangValidator >/dev/null; then
  echo "SKIP: glslangValidator not installed (Debian: glslang-tools; scripts/setup.sh installs it)"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$1" "$dir" > "$dir/list"
count=0
while read -r file; do
  if ! out=$(glslangValidator "$file" 2>&1); then
    echo "FAIL: $file"
    echo "$out" | head -20
    exit 1
  fi
  count=$((count + 1))
done < "$dir/list"
echo "$count GL shader stages compiled with glslang"
[ "$count" -gt 0 ]
