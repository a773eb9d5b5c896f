#!/usr/bin/env bash
# The numerical-stability suite: every scene of scenes/extremes/ (each names its purpose) across storages, depth
# formats and both filter kinds, with the error against the ray-cast reference, NaN/Inf counts and flicker
# (--stability: the next frame compared), then cube sizes 1, 2, 16 and beyond what memory allows on one scene.
# Then every remedy on and off (--remedy). Writes OUT/matrix, OUT/remedies and OUT/cube_sizes (run folders) and
# OUT/extremes.md (scripts/analysis/extremes_table.py).
# Usage: scripts/experiments/run_extremes.sh OUT [extra omnishadow run arguments, e.g. --backend gl,vulkan]
set -euo pipefail
out="${1:?usage: scripts/experiments/run_extremes.sh OUT [run arguments]}"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bin="$here/build/release/omnishadow"
scenes=$(cd "$here/scenes/extremes" && ls *.json | sed 's/\.json$//' | paste -sd, -)
mkdir -p "$out"
"$bin" run --scenes-dir "$here/scenes/extremes" --scene "$scenes" --cube 512 --technique six_pass \
  --filter hard,pcf_disk20 --storage linear_depth,r32f_distance,hardware_depth --depth-format d16,d24,d32f \
  --frames 1 --warmup 0 --benchmark_repetitions=1 --light-radius 0 --stability --max-error 1 --out "$out/matrix" "$@"
# Remedies on and off: linear depth in D32F, both filter kinds.
"$bin" run --scenes-dir "$here/scenes/extremes" --scene "$scenes" --cube 512 --technique six_pass \
  --filter hard,pcf_disk20 --remedy none,rebase,bias0,slope_bias,normal_offset,two_sided \
  --frames 1 --warmup 0 --benchmark_repetitions=1 --light-radius 0 --no-images --max-error 1 --out "$out/remedies" "$@"
# PCF radius from 0 (one direction) to 20x the tutorials' kernels.
"$bin" run --scenes-dir "$here/scenes/extremes" --scene nf_25,grazing,seams --cube 512 --technique six_pass \
  --filter pcf_grid64,pcf_disk20 --pcf-scale 0,1,5,20 --frames 1 --warmup 0 --benchmark_repetitions=1 \
  --light-radius 0 --no-images --out "$out/pcf" "$@"
"$bin" run --scenes-dir "$here/scenes/extremes" --scene nf_25 --cube 1,2,16,4096,16384 \
  --technique six_pass,geometry_shader --filter hard --frames 1 --warmup 0 --benchmark_repetitions=1 \
  --light-radius 0 --no-images --out "$out/cube_sizes" "$@"
/usr/bin/python3 "$here/scripts/analysis/extremes_table.py" "$out/matrix" "$out/cube_sizes" --remedies "$out/remedies" \
  --pcf "$out/pcf" --out "$out/extremes.md"
