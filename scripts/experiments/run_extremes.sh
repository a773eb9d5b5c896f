#!/usr/bin/env bash
# The numerical-stability suite: every scene of scenes/extremes/ (each names its purpose) across storages, depth
# formats and both filter kinds, with the error against the ray-cast reference, NaN/Inf counts and flicker
# (--stability: the next frame compared), then cube sizes 1, 2, 16 and beyond what memory allows on one scene.
# Then every remedy on and off (--remedy), PCF radii, the moments filters' hazards and the layouts at seams. Writes OUT/matrix,
# OUT/remedies, OUT/pcf, OUT/cube_sizes and OUT/moments_* (run folders) and OUT/extremes.md
# (scripts/analysis/extremes_table.py).
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
# The moments filters' hazards (--moments-tuning, docs/extremes.md "Moments filters' hazards"), each with --check:
# light bleeding and its reduction swept; exponents about the format's overflow limit, with the far plane fitted so
# that z reaches 1; the variance floor and moment bias off on nearly singular moments; VSM in world units; seams.
# --check exits 1 when a case fails its checks, which these runs are meant to show; other exits still stop the suite.
hazard() { "$bin" run "$@" || [ $? -eq 1 ]; }
moments=(--cube 512 --technique six_pass --frames 1 --warmup 0 --benchmark_repetitions=1 --light-radius 0 --check
  --no-images --scenes-dir "$here/scenes/extremes")
hazard "${moments[@]}" --scene bleeding --filter hard,pcf_disk20,vsm,evsm2,evsm4,msm \
  --moments-tuning none,lbr0.2,lbr0.4,lbr0.6,lbr0.8 --out "$out/moments_bleeding" "$@"
hazard "${moments[@]}" --scene nf_25 --optimize fit --filter esm,evsm2,evsm4 --depth-format d32f,d16 \
  --moments-tuning exp0.5,none,exp0.99,exp1.01 --out "$out/moments_exponents" "$@"
hazard "${moments[@]}" --scene flat_moments,nf_25 --filter vsm,msm --depth-format d32f,d16 \
  --moments-tuning floor0,none,floor10 --remedy none,bias0 --out "$out/moments_floor" "$@"
hazard "${moments[@]}" --scene nf_25,nf_1e3 --filter vsm --depth-format d32f,d16 --moments-tuning none,world \
  --remedy none,bias0 \
  --out "$out/moments_world" "$@"
hazard "${moments[@]}" --scene nf_25,seams --filter hard,pcf_disk20,vsm,esm,evsm2,evsm4,msm \
  --out "$out/moments_seams" "$@"
# Layouts at their extremes: face_array and tetrahedral against the cube where faces meet (seams: casters
# on the cube's diagonals; tetra_seams: on the tetrahedral faces' corners, edges and tie planes) and at grazing
# angles, with the filters that read across a seam (hw_compare2x2's 2x2, vsm's bilinear) beside the NEAREST ones;
# --check holds each layout's texels and lookups to its own rule.
hazard "${moments[@]}" --scene nf_25,seams,tetra_seams,grazing --layout cube,face_array,tetrahedral \
  --filter hard,pcf_disk20,hw_compare2x2,vsm \
  --out "$out/layouts_seams" "$@"
# dual_paraboloid at its own extremes: the equator where its two layers meet (seams' diagonal casters cross it, grazing's
# receivers lie along it) and coarse tessellation (1: each of the room's walls two triangles), beside the cube.
hazard "${moments[@]}" --scene nf_25,seams,grazing --layout cube,dual_paraboloid --tessellate 1,4,16 \
  --filter hard,pcf_disk20 --max-error 100 --out "$out/layouts_paraboloid" "$@"
/usr/bin/python3 "$here/scripts/analysis/extremes_table.py" "$out/matrix" "$out/cube_sizes" --remedies "$out/remedies" \
  --pcf "$out/pcf" --moments "$out" --out "$out/extremes.md"
