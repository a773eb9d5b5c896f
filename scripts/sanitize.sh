#!/usr/bin/env bash
# The test suite (including the CLI tests' small GL and Vulkan matrices) under AddressSanitizer,
# UndefinedBehaviorSanitizer and LeakSanitizer. Driver-library leaks are suppressed by name only
# (tests/sanitizers/lsan_driver_leaks.supp). Slow: not for timing.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset asan >/dev/null
cmake --build --preset asan
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
ctest --preset asan -j2
