#!/usr/bin/env bash
# One shard of the GPU fleet's matrix on this runner: `omnishadow run --shard auto`, which reads the shard from the
# CI engine (GitLab `parallel:` CI_NODE_INDEX/CI_NODE_TOTAL, our GitHub workflow's OMNISHADOW_SHARD_INDEX/COUNT
# from its matrix, Slurm arrays, Kubernetes indexed jobs; bench/run/matrix.h). Usage:
#   scripts/ci/fleet_shard.sh OUT_DIR [omnishadow run arguments]
# Without arguments: the default matrix, 10 frames after 2 warm-up frames, 8 repetitions in rounds: the fewest at
# which the fan-in compare can flag a case at all (exact U test, Holm over up to 322 cases: 8 against 8 reach
# p = 1.6e-4; 5 against 5 reach only 7.9e-3, blind over the 48-60 cases of the default matrix). fleet_compare.sh
# fails when a gated comparison is blind anyway.
# Every shard runs with --check; its failed checks do not fail the job (exit 1 is kept as 0): the fan-in job's
# comparison decides (scripts/ci/fleet_compare.sh), where a case ok in the baseline and failed here is a status
# regression. Errors (exit 2 and above) fail the job.
set -euo pipefail
out="$1"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
if [ "$#" -eq 0 ]; then set -- --frames 10 --warmup 2 --benchmark_repetitions=8; fi
status=0
"${OMNISHADOW_BIN:-$here/build/release/omnishadow}" run --shard auto --check --out "$out" "$@" || status=$?
if [ "$status" -eq 1 ]; then
  echo "fleet_shard: a case failed or failed a check; the fleet's compare step reports it"
  status=0
fi
exit "$status"
