#!/usr/bin/env bash
# The test suite (including the CLI tests' small GL and Vulkan matrices) under AddressSanitizer,
# UndefinedBehaviorSanitizer and LeakSanitizer. Driver-library leaks are suppressed by name only
# (tests/sanitizers/lsan_driver_leaks.supp). Slow: not for timing.
# Usage: scripts/sanitize.sh [--memory]
#   (none)    every test of the suite, a process per test (about 15 minutes on 2 cores; scripts/ci/extended.sh)
#   --memory  the memory pass (CI): the C++ test binaries, one process each, without the tests that only add cases
#             through code the others walk (tests/CMakeLists.txt lists them); builds only what those need
set -euo pipefail
cd "$(dirname "$0")/.."
preset=asan
targets=()
case "${1:-}" in
  "") ;;
  --memory) preset=asan-memory; targets=(--target unit_tests backend_tests gl_backend_tests vk_backend_tests cli_tests omnishadow) ;;
  *) echo "sanitize.sh: unknown option '$1' (--memory)" >&2; exit 2 ;;
esac
bash scripts/setup.sh
cmake --preset asan >/dev/null
cmake --build --preset asan "${targets[@]}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
ctest --preset "$preset" -j2
