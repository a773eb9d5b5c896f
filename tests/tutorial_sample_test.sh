#!/usr/bin/env bash
# The tutorial's sample renders and reports both passes, and exits 0: a crash after its JSON line fails (ctest's
# PASS_REGULAR_EXPRESSION alone would have ignored the exit code). Both passes must take time: 0 ms means a pass
# was not measured. Usage: tutorial_sample_test.sh SAMPLE_BINARY ARGS...
set -uo pipefail
out="$("$@" 2>&1)"
code=$?
echo "$out"
[ "$code" -eq 0 ] || { echo "FAIL: the sample exited $code"; exit 1; }
positive='([1-9][0-9]*(\.[0-9]*)?|0\.[0-9]*[1-9][0-9]*)'
grep -Eq "\"shadow_ms\": $positive, \"lighting_ms\": $positive" <<<"$out" ||
  { echo "FAIL: no line with both passes' positive times"; exit 1; }
echo "tutorial sample: both passes timed, exit 0"
