#!/usr/bin/env bash
# Makes a merged fleet run (a fan-in job's `merged` artifact, or `omnishadow merge` of fleet_shard.sh runs) the GPU
# fleet's baseline for its device key: results/fleet_baselines/<key>/ with what compare reads, this commit's
# scripts/ci/fleet_matrix.args (so fleet_compare.sh can say when the matrix changed since) and, with --gate, the
# timing gate (metric, alpha, min_effect: scripts/experiments/sensitivity.py measures one; without a gate the
# fleet's timing is reported, not failed) and the merged run's replay.json (the traces' replays and images). Commit the folder on the target branch. The CI matrix's baselines
# (results/baselines/) are a different matrix: scripts/ci/refresh_baselines.sh.
# Usage: scripts/ci/fleet_baseline.sh MERGED_RUN [--gate GATE_JSON]
set -euo pipefail
run="${1:?usage: scripts/ci/fleet_baseline.sh MERGED_RUN [--gate GATE_JSON]}"; shift
gate=""
while [ "$#" -gt 0 ]; do
  case "$1" in
    --gate) gate="${2:?fleet_baseline: --gate needs a file}"; shift 2 ;;
    *) echo "fleet_baseline: unknown option '$1'" >&2; exit 2 ;;
  esac
done
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
[ -f "$run/results.json" ] || { echo "fleet_baseline: $run holds no results.json (pass the merged run's folder)" >&2; exit 2; }
/usr/bin/python3 -c 'import json,sys; o=json.load(open(sys.argv[1]))["omnishadow"]; sys.exit(0 if o.get("complete", False) else 1)' \
  "$run/results.json" || { echo "fleet_baseline: $run is incomplete (a shard missing or a run stopped): not a baseline" >&2; exit 2; }
key="$("$bin" device-key "$run" | head -n 1)"
dest="$here/results/fleet_baselines/$key"
bash "$here/scripts/ci/store_baseline.sh" "$run" "$dest" >/dev/null
cp "$here/scripts/ci/fleet_matrix.args" "$dest/fleet_matrix.args"
# The traces' replays (scripts/ci/fleet_replay.sh), what replay_compare.py holds the next replays to.
if [ -f "$run/replay.json" ]; then cp "$run/replay.json" "$dest/replay.json"; fi
if [ -n "$gate" ]; then cp "$gate" "$dest/gate.json"; fi
echo "fleet baseline for device key $key: results/fleet_baselines/$key ($(du -sh "$dest" | cut -f1))${gate:+, gate $gate}"
