#!/usr/bin/env bash
# The fleet's traces replayed on this runner's GPU, as Mesa's trace CI replays its own: every capture (.gfxr, .rdc)
# under results/traces/ (a user's capture a maintainer committed, kept small: a case of the CI matrix of its own)
# and under each folder FLEET_TRACES names (colon-separated: a runner's own collection, too big for git), replayed
# by scripts/replay_trace.py into SHARD_DIR/replay.json. Only the first shard of a device key replays (GitLab's
# CI_NODE_INDEX 1, our GitHub workflow's OMNISHADOW_SHARD_INDEX 0, or no shard at all); fleet_merge.sh carries its
# replay.json into the merged run and fleet_compare.sh compares it with the device's baseline replays
# (scripts/ci/replay_compare.py: a trace that fails now or whose replayed image changed fails the fan-in). A replay
# that fails does not fail this job (exit 0, the comparison decides); a FLEET_TRACES folder that does not exist or
# a missing replayer is exit 2 with one line. No traces at all: one line, nothing written.
# Usage: scripts/ci/fleet_replay.sh SHARD_DIR      FLEET_REPLAY_ROUNDS: timed replays of each trace (default 5)
set -euo pipefail
out="${1:?usage: scripts/ci/fleet_replay.sh SHARD_DIR}"
here="$(cd "$(dirname "$0")/../.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
if [ "${CI_NODE_INDEX:-1}" != 1 ] || [ "${OMNISHADOW_SHARD_INDEX:-0}" != 0 ]; then
  echo "fleet_replay: not the first shard: the first shard of this device key replays the traces"
  exit 0
fi
folders=()
[ ! -d "$here/results/traces" ] || folders+=("$here/results/traces")
if [ -n "${FLEET_TRACES:-}" ]; then
  IFS=: read -r -a named <<<"$FLEET_TRACES"
  for folder in "${named[@]}"; do
    [ -d "$folder" ] || { echo "fleet_replay: FLEET_TRACES names '$folder', which is not a folder" >&2; exit 2; }
    folders+=("$folder")
  done
fi
traces=()
if [ "${#folders[@]}" -gt 0 ]; then
  mapfile -t traces < <(find "${folders[@]}" -type f \( -name '*.gfxr' -o -name '*.rdc' \) | sort)
fi
if [ "${#traces[@]}" -eq 0 ]; then
  echo "fleet_replay: no traces (results/traces/ and FLEET_TRACES hold no .gfxr or .rdc): nothing replayed"
  exit 0
fi
mkdir -p "$out"
status=0
/usr/bin/python3 "$here/scripts/replay_trace.py" "${traces[@]}" --out "$out/replay.json" \
  --rounds "${FLEET_REPLAY_ROUNDS:-5}" || status=$?
if [ "$status" -eq 1 ]; then
  echo "fleet_replay: a trace failed to replay (its entry in replay.json); the fleet's compare step reports it"
  status=0
fi
exit "$status"
