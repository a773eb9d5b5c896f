#!/usr/bin/env bash
# The CI matrix: small enough for a minute on llvmpipe, wide enough to touch every technique family and both
# filter kinds, with per-face culling on and off (so a change that loses culling shows as a work change in the
# GS and vs_layer counters). Usage: scripts/ci/ci_matrix.sh OUT_DIR [extra omnishadow run arguments]
# Nine interleaved repetitions give the U-test room: with 24 cases Holm needs p < 0.05/24, and 9 vs 9 values
# can reach p = 4e-5. CI_MATRIX_FRAMES (default 3) sets the timed frames per repetition (scripts/experiments/sensitivity.py
# --frames), OMNISHADOW_BIN the binary. OMNISHADOW_WRAPPER prefixes the command (scripts/ci/instruction_counts.sh runs it under callgrind).
# CI_MATRIX_SIZE=gpu: the same cases at 1920x1080 with 1024 cubes, frames big enough for fragment work to show on a
# GPU (at 160x120 an H100's frame is mostly fixed cost: injected work of 4-20 iterations moved it by -0.7..+1.9%).
set -euo pipefail
out="$1"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
case "${CI_MATRIX_SIZE:-cpu}" in
  cpu) size=(--frame 160x120 --cube 128) ;;
  gpu) size=(--frame 1920x1080 --cube 1024) ;;
  *) echo "ci_matrix.sh: CI_MATRIX_SIZE must be cpu or gpu, not '$CI_MATRIX_SIZE'" >&2; exit 2 ;;
esac
${OMNISHADOW_WRAPPER:-} "${OMNISHADOW_BIN:-$here/build/release/omnishadow}" run --backend gl --scene room,ogldev "${size[@]}" \
  --technique six_pass,geometry_shader,vs_layer --filter hard,pcf_disk20 --optimize none,cull \
  --frames "${CI_MATRIX_FRAMES:-3}" --warmup 1 --light-radius 0 --images all --out "$out" \
  --benchmark_repetitions=9 --benchmark_enable_random_interleaving=true "$@"
