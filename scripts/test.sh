#!/usr/bin/env bash
# Everything from a fresh Debian 12 machine to a passing test suite: dependencies, build, ctest. The tests labelled
# `extended` (the fleet pipeline plays: four builds, 20 minutes) are scripts/ci/extended.sh's.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
ctest --preset release -j2
