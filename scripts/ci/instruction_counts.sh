#!/usr/bin/env bash
# Deterministic work per case: the CI matrix under callgrind with llvmpipe rasterising on the calling thread
# (LP_NUM_THREADS=0, so no thread interleaving can change the count), counting exactly the timed frames of each
# case (client requests in bench/run/gbench_glue.cpp), one repetition. Writes OUT/instructions.json
# ({case id: instructions per frame}) via scripts/ci/instruction_counts.py. Counts depend on the CPU features LLVM
# JITs for (valgrind's emulated CPU) and the Mesa build: compare only within one device key.
# Usage: scripts/ci/instruction_counts.sh OUT [extra omnishadow run arguments]
set -euo pipefail
out="${1:?usage: scripts/ci/instruction_counts.sh OUT [run arguments]}"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
command -v valgrind >/dev/null || { echo "instruction_counts: valgrind not found (bash scripts/setup.sh installs it)" >&2; exit 2; }
mkdir -p "$out"
rm -f "$out"/callgrind.*
export LP_NUM_THREADS=0
export OMNISHADOW_WRAPPER="valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=$out/callgrind.%p"
# One process (--isolation none): callgrind follows no worker process, and the frames it counts are the run's own.
bash "$here/scripts/ci/ci_matrix.sh" "$out/run" --no-images --no-accuracy --benchmark_repetitions=1 \
  --benchmark_enable_random_interleaving=false --isolation none "$@" > "$out/run.log" 2>&1 || { tail -20 "$out/run.log"; exit 2; }
/usr/bin/python3 "$here/scripts/ci/instruction_counts.py" "$out"
