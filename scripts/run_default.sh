#!/usr/bin/env bash
# The main job: dependencies, build, then the default matrix on this machine's default driver.
# Writes results/default-<UTC time>/ (results.json, summary.md, images/). Extra arguments go to `omnishadow run`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
out="results/default-$(date -u +%Y%m%d-%H%M%S)"
# Three interleaved repetitions of a few frames each: on a shared or software-rendered machine noise comes in
# bursts lasting seconds, and interleaving spreads every case over the whole run instead of one burst.
./build/release/omnishadow run --out "$out" --frames 4 --warmup 1 \
  --benchmark_repetitions=3 --benchmark_enable_random_interleaving=true "$@"
