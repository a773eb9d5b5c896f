#!/usr/bin/env bash
# The fleet's build job: builds the omnishadow executable once per device key and installs it, relocatable, into
# OUT (OUT/bin/omnishadow, OUT/share/omnishadow: scenes and the report's scripts; CMakeLists.txt's install rules),
# which the engine hands to that device's shards and fan-in job as an artifact (OMNISHADOW_BIN=OUT/bin/omnishadow).
# Usage: scripts/ci/fleet_build.sh OUT
set -euo pipefail
out="$(mkdir -p "$1" && cd "$1" && pwd)"
cd "$(dirname "$0")/../.."
cmake --preset release >/dev/null
cmake --build --preset release --target omnishadow
cmake --install build/release --prefix "$out" >/dev/null
"$out/bin/omnishadow" --help >/dev/null  # the installed binary starts (its libraries are on this runner)
echo "fleet_build: $out/bin/omnishadow ($(git rev-parse --short HEAD 2>/dev/null || echo 'no git'))"
