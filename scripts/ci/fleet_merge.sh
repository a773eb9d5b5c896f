#!/usr/bin/env bash
# The fan-in step: joins the shards of one device key into one run. Usage: scripts/ci/fleet_merge.sh OUT SHARD_DIR...
# Refuses (exit 2) shards that overlap or come from different devices of the same backend. The traces' replays
# (scripts/ci/fleet_replay.sh: the first shard's replay.json) go into the merged run beside its results.
set -euo pipefail
out="$1"; shift
here="$(cd "$(dirname "$0")/../.." && pwd)"
[ "$#" -ge 1 ] || { echo "fleet_merge: no shard folders given" >&2; exit 2; }
"${OMNISHADOW_BIN:-$here/build/release/omnishadow}" merge "$out" "$@"
for shard in "$@"; do
  if [ -f "$shard/replay.json" ]; then cp "$shard/replay.json" "$out/replay.json"; fi
done
