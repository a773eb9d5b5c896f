#!/usr/bin/env bash
# The main job: dependencies, build, then the default matrix on this machine's default driver.
# Writes results/default-<UTC time>/ (results.json, summary.md, images/). Extra arguments go to `omnishadow run`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
out="results/default-$(date -u +%Y%m%d-%H%M%S)"
# Three interleaved repetitions of three frames each: on a shared or software-rendered machine noise comes in
# bursts lasting seconds, and interleaving spreads every case over the whole run instead of one burst. On a GPU a
# repetition grows to 100 ms of frames (--repetition-ms), so these counts are minimums there.
# No warm-up frames: every case's cold first frame (shader compiles) is rendered in the untimed part, a GPU still
# warms each repetition up for 100 ms (--warmup-ms), and on a CPU driver, whose frames take tens of milliseconds, a
# warm-up frame changed nothing measurable (median case 1.005x without one) at a fifth of the timed part.
./build/release/omnishadow run --out "$out" --frames 3 --warmup 0 \
  --benchmark_repetitions=3 --benchmark_enable_random_interleaving=true "$@"
