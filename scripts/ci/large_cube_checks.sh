#!/usr/bin/env bash
# No false alarm at the large cubes: every correct case of a wide matrix passes its checks at cube faces of 1024 and
# 2048 texels, where the mutation suite (scripts/experiments/mutants.py) runs its matrices at 256 only. A tolerance
# that scales wrongly with the face size (a depth edge's width in texels, the far bound's, a 16-bit depth format's
# step over a longer texel) shows here as a failed_check on code under no planted bug; the same matrix at 256 is the
# mutants' baseline. Both APIs, room and heavy, every storage and depth format, the layouts cube, face_array,
# tetrahedral, dual_paraboloid and atlas, hard and pcf_disk20 (--max-error 100: a layout's own error against exact
# visibility is its table's figure, not an alarm). Judged by scripts/analysis/judge_checks.py: PASS when no case
# failed. About 25 minutes on 2 cores with the CPU drivers; a step of scripts/ci/extended.sh.
# Usage: scripts/ci/large_cube_checks.sh [OUT] (default: a temporary folder); a built build/release/omnishadow.
#   SWEEP_TECHNIQUES  the techniques (default six_pass,geometry_shader,geometry_shader_instanced,vs_layer: multiview
#                     is left out on the CPU drivers, whose lavapipe writes every view into one face, a driver bug
#                     the checks name; add it, nv_swizzle and mesh_shader on a GPU that has them)
#   SWEEP_CUBES       the cube sizes (default 1024,2048)
#   SWEEP_BACKENDS    the APIs (default gl,vulkan)
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-$(mktemp -d)/large-cube-checks}"
bin=./build/release/omnishadow
[ -x "$bin" ] || { echo "large_cube_checks.sh: $bin is not built (scripts/build.sh builds it)" >&2; exit 2; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
run_status=0
"$bin" run --backend "${SWEEP_BACKENDS:-gl,vulkan}" --scene room,heavy --cube "${SWEEP_CUBES:-1024,2048}" \
  --technique "${SWEEP_TECHNIQUES:-six_pass,geometry_shader,geometry_shader_instanced,vs_layer}" \
  --layout cube,face_array,tetrahedral,dual_paraboloid,atlas --storage linear_depth,r32f_distance,hardware_depth \
  --depth-format d16,d24,d32f --filter hard,pcf_disk20 --max-error 100 --check --images none --frames 1 --warmup 0 \
  --settle-s 0 --benchmark_repetitions=1 --out "$out" >"$out.log" 2>&1 || run_status=$?
# 1 is the run's verdict on its checks (the judge says which case); anything else is a run that did not finish.
if [ "$run_status" -gt 1 ]; then
  tail -n 5 "$out.log" >&2
  echo "large_cube_checks.sh: the run exited $run_status (its log: $out.log)" >&2
  exit 2
fi
echo "large_cube_checks.sh: $out (log $out.log)"
/usr/bin/python3 scripts/analysis/judge_checks.py "$out"
