#!/usr/bin/env bash
# No false alarm at the large cubes: every correct case of a wide matrix passes its checks at cube faces of 1024 and
# 2048 texels, where the mutation suite (scripts/experiments/mutants.py) runs its matrices at 256 only. A tolerance
# that scales wrongly with the face size (a depth edge's width in texels, the far bound's, a 16-bit depth format's
# step over a longer texel) shows here as a failed_check on code under no planted bug; the same matrix at 256 is the
# mutants' baseline. Both APIs, room and heavy, every storage and depth format, the layouts cube, face_array,
# tetrahedral, dual_paraboloid and atlas, hard and pcf_disk20 (--max-error 100: a layout's own error against exact
# visibility is its table's figure, not an alarm). Judged by scripts/analysis/judge_checks.py: PASS when no case
# failed. Untimed (--no-timing): about 45 minutes on 2 cores with the CPU drivers; a stage of scripts/ci/extended.sh.
# Usage: scripts/ci/large_cube_checks.sh [OUT] (default: a temporary folder; OUT/formats and OUT/remedies, each a run
# folder with its log beside it); a built build/release/omnishadow (OMNISHADOW_BIN names another).
#   SWEEP_TECHNIQUES  the techniques (default six_pass,geometry_shader,geometry_shader_instanced,vs_layer: multiview
#                     is left out on the CPU drivers, whose lavapipe writes every view into one face, a driver bug
#                     the checks name; add it, nv_swizzle and mesh_shader on a GPU that has them)
#   SWEEP_CUBES       the cube sizes (default 1024,2048)
#   SWEEP_BACKENDS    the APIs (default gl,vulkan)
#   SWEEP_SCENES      the scenes (default room,heavy)
# Exit: 0 when both parts pass, 1 when a case failed its checks, 2 when a run did not finish (bad input, a lost run).
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-$(mktemp -d)/large-cube-checks}"
bin="${OMNISHADOW_BIN:-./build/release/omnishadow}"
[ -x "$bin" ] || { echo "large_cube_checks.sh: $bin is not built (scripts/build.sh builds it)" >&2; exit 2; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
# One matrix into a run folder, its log beside it; exits 2 (the script's input error) when the run did not finish:
# 1 is the run's verdict on its checks, which the judge reads.
sweep() {
  local dir="$1"
  shift
  local status=0
  "$bin" run --backend "${SWEEP_BACKENDS:-gl,vulkan}" --scene "${SWEEP_SCENES:-room,heavy}" --max-error 100 --check \
    --no-timing --images none --out "$dir" "$@" >"$dir.log" 2>&1 || status=$?
  if [ "$status" -gt 1 ]; then
    tail -n 5 "$dir.log" >&2
    echo "large_cube_checks.sh: the run exited $status (its log: $dir.log)" >&2
    exit 2
  fi
}
techniques="${SWEEP_TECHNIQUES:-six_pass,geometry_shader,geometry_shader_instanced,vs_layer}"
cubes="${SWEEP_CUBES:-1024,2048}"
mkdir -p "$out"
# Every storage and depth format in every layout.
sweep "$out/formats" --cube "$cubes" --technique "$techniques" \
  --layout cube,face_array,tetrahedral,dual_paraboloid,atlas --storage linear_depth,r32f_distance,hardware_depth \
  --depth-format d16,d24,d32f --filter hard,pcf_disk20
# What moves the stored depths or the lookup: the far plane fitted to the scene, per-face culling, the biases and the
# normal offset, at the largest cube.
sweep "$out/remedies" --cube "${cubes##*,}" --technique "$techniques" --layout cube,tetrahedral,atlas \
  --optimize cull,fit,cull+fit --remedy none,slope_bias,normal_offset --filter hard,pcf_disk20
echo "large_cube_checks.sh: $out (logs beside each run)"
status=0
for run in formats remedies; do
  echo "$run:"
  /usr/bin/python3 scripts/analysis/judge_checks.py "$out/$run" || status=1
done
exit $status
