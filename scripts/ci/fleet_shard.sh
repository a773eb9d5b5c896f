#!/usr/bin/env bash
# One shard of the GPU fleet's matrix on this runner: `omnishadow run --shard auto`, which reads the shard from the
# CI engine (GitLab `parallel:` CI_NODE_INDEX/CI_NODE_TOTAL, our GitHub workflow's OMNISHADOW_SHARD_INDEX/COUNT
# from its strategy, Slurm arrays, Kubernetes indexed jobs; bench/run/matrix.h). Usage:
#   scripts/ci/fleet_shard.sh OUT_DIR [omnishadow run arguments]
# Without arguments: the fleet's matrix, scripts/ci/fleet_matrix.args (its one definition: the baselines the fan-in
# compares with are merged runs of it). OMNISHADOW_BIN: the binary (the fleet passes its build job's install).
# Every shard runs with --check; its failed checks do not fail the job (exit 1 is kept as 0): the fan-in job's
# comparison decides (scripts/ci/fleet_compare.sh), where a case ok in the baseline and failed here is a status
# regression. Errors (exit 2 and above) fail the job.
set -euo pipefail
out="$1"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
if [ "$#" -eq 0 ]; then
  mapfile -t matrix < <(grep -v '^[[:space:]]*\(#\|$\)' "$here/scripts/ci/fleet_matrix.args")
  set -- "${matrix[@]}"
fi
status=0
"${OMNISHADOW_BIN:-$here/build/release/omnishadow}" run --shard auto --check --out "$out" "$@" || status=$?
if [ "$status" -eq 1 ]; then
  echo "fleet_shard: a case failed or failed a check; the fleet's compare step reports it"
  status=0
fi
exit "$status"
