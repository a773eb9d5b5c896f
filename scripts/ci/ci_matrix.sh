#!/usr/bin/env bash
# The CI matrix: small enough for a minute on llvmpipe, wide enough to touch every technique family and both
# filter kinds, with per-face culling on and off (so a change that loses culling shows as a work change in the
# GS and vs_layer counters). Usage: scripts/ci/ci_matrix.sh OUT_DIR [extra omnishadow run arguments]
# Nine interleaved repetitions give the U-test room: with 24 cases Holm needs p < 0.05/24, and 9 vs 9 values
# can reach p = 4e-5. CI_MATRIX_FRAMES (default 3) sets the timed frames per repetition (scripts/experiments/sensitivity.py
# --frames), OMNISHADOW_BIN the binary. OMNISHADOW_WRAPPER prefixes the command (scripts/ci/instruction_counts.sh runs it under callgrind).
set -euo pipefail
out="$1"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
${OMNISHADOW_WRAPPER:-} "${OMNISHADOW_BIN:-$here/build/release/omnishadow}" run --backend gl --scene room,ogldev --cube 128 \
  --technique six_pass,geometry_shader,vs_layer --filter hard,pcf_disk20 --optimize none,cull --frame 160x120 \
  --frames "${CI_MATRIX_FRAMES:-3}" --warmup 1 --light-radius 0 --images all --out "$out" \
  --benchmark_repetitions=9 --benchmark_enable_random_interleaving=true "$@"
