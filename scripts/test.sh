#!/usr/bin/env bash
# Everything from a fresh Debian 12 machine to a passing test suite: dependencies, build, ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
ctest --preset release -j2
