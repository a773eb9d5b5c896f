#!/usr/bin/env bash
# The CI entry points' stage timing (scripts/lib/stages.sh): a passing and a failing stage are both in the table
# printed at exit, with their exit codes, and the entry point ends with the failing stage's code; extended.sh
# refuses an unknown stage in one line with exit 2 before it runs anything.
# Usage: tests/ci_stages_test.sh SOURCE_DIR
set -uo pipefail
root="${1:?usage: ci_stages_test.sh SOURCE_DIR}"
fail() { echo "FAIL: $*"; exit 1; }
out="$(bash -c "set -euo pipefail; source '$root/scripts/lib/stages.sh'; stage fine true; stage broken bash -c 'exit 3'; stage never true" 2>&1)"
rc=$?
[ "$rc" -eq 3 ] || fail "the entry point ended with $rc, not the failing stage's 3: $out"
grep -q '^| fine | [0-9]* | 0 |$' <<<"$out" || fail "no row for the passing stage: $out"
grep -q '^| broken | [0-9]* | 3 |$' <<<"$out" || fail "no row for the failing stage with its exit code: $out"
grep -q 'never' <<<"$out" && fail "a stage after the failing one ran: $out"
err="$(bash "$root/scripts/ci/extended.sh" no_such_stage 2>&1)"
rc=$?
[ "$rc" -eq 2 ] || fail "extended.sh no_such_stage exited $rc, not 2"
[ "$(wc -l <<<"$err")" -eq 1 ] && grep -q "unknown stage 'no_such_stage'" <<<"$err" || fail "extended.sh's refusal: $err"
echo "stages timed and tabled, failures carried; extended.sh refuses an unknown stage"
