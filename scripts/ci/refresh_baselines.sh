#!/usr/bin/env bash
# Re-measures the CI matrix on this machine and stores it as the baseline for this machine's device key
# (results/baselines/<key>/): results.json plus the images compare reads (lit, shadow factor, cube faces). The GPU
# fleet's baselines are merged runs of the fleet's own matrix instead: scripts/ci/fleet_baseline.sh.
# Commit the folder after looking at its summary. Usage: scripts/ci/refresh_baselines.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
bash scripts/ci/ci_matrix.sh "$tmp/run" >/dev/null 2>"$tmp/log" || { cat "$tmp/log"; exit 2; }
key="$(./build/release/omnishadow device-key "$tmp/run" | head -n 1)"
dest="results/baselines/$key"
bash scripts/ci/store_baseline.sh "$tmp/run" "$dest" >/dev/null
echo "baseline for device key $key: $dest ($(du -sh "$dest" | cut -f1))"
# Instruction counts for this CPU and valgrind (scripts/ci/ci_compare.sh compares them when they exist).
cpu="$(bash scripts/ci/cpu_key.sh)"  # model and instruction-set extensions
vg="$(valgrind --version 2>/dev/null || echo none)"
if [ "$vg" != none ]; then
  bash scripts/ci/instruction_counts.sh "$tmp/instructions" >/dev/null
  cp "$tmp/instructions/instructions.json" "$dest/instructions-$cpu-$vg.json"
  echo "instruction counts: $dest/instructions-$cpu-$vg.json"
fi
