#!/usr/bin/env bash
# scripts/gpu_acceptance.sh's `suite` step, judged on a stand-in ctest (first on PATH) whose output is written here:
# a suite that passes is PASS; one that fails says its exit; one cut at SUITE_BUDGET_S says how many tests passed
# and failed before the cut and lists the tests it did not finish, which is all a device call that ran out of time
# brings back. The step itself runs the real ctest on a GPU; this holds the verdict's reading of ctest's lines.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "gpu_acceptance_suite_test: $*" >&2; exit 1; }
mkdir -p "$tmp/bin"
# The stand-in: `-N` lists three tests (a parametrised name carries ctest's comment after it, as gtest's do);
# otherwise it prints what STUB_MODE asks for, as ctest -j does, and exits as ctest would.
cat >"$tmp/bin/ctest" <<'EOF'
#!/usr/bin/env bash
if [[ " $* " == *" -N "* ]]; then
  printf 'Test project /x\n  Test   #1: Cube.A\n  Test   #2: Table/Cli.B/case1  # GetParam() = 16-byte object <5B>\n'
  printf '  Test   #3: Cube.C\n\nTotal Tests: 3\n'
  exit 0
fi
echo "Test project /x"
echo "    Start 2: Table/Cli.B/case1"
echo "1/3 Test #2: Table/Cli.B/case1  # GetParam() = 16-byte object <5B> ....   Passed    0.40 sec"
case "$STUB_MODE" in
  pass) echo "2/3 Test #1: Cube.A ....   Passed    0.1 sec"; echo "3/3 Test #3: Cube.C ....   Passed    0.1 sec"
        echo "100% tests passed, 0 tests failed out of 3"; exit 0 ;;
  fail) echo "2/3 Test #1: Cube.A ....***Failed    0.1 sec"; echo "3/3 Test #3: Cube.C ....   Passed    0.1 sec"
        echo "67% tests passed, 1 tests failed out of 3"; exit 8 ;;
  cut) echo "2/3 Test #1: Cube.A ....***Failed    0.1 sec"; exec sleep 60 ;;
esac
EOF
chmod +x "$tmp/bin/ctest"
step() {  # MODE BUDGET: runs the step into $tmp/MODE; its exit code is echoed
  local code=0
  PATH="$tmp/bin:$PATH" STUB_MODE="$1" SUITE_BUDGET_S="$2" bash "$here/scripts/gpu_acceptance.sh" "$tmp/$1" suite \
    >"$tmp/$1.out" 2>&1 || code=$?
  echo "$code"
}

[ "$(step pass 30)" -eq 0 ] || fail "a passing suite: $(cat "$tmp/pass.out")"
grep -q -- "- PASS: ctest, 0 failed" "$tmp/pass/summary.md" || fail "no PASS line: $(cat "$tmp/pass/summary.md")"

[ "$(step fail 30)" -eq 1 ] || fail "a failing suite did not exit 1: $(cat "$tmp/fail.out")"
grep -q -- "- FAIL: ctest exit 8" "$tmp/fail/summary.md" || fail "no exit line: $(cat "$tmp/fail/summary.md")"
grep -q -- "  - Test #1: Cube.A ....\*\*\*Failed" "$tmp/fail/summary.md" || fail "the failed test is not listed"

[ "$(step cut 2)" -eq 1 ] || fail "a cut suite did not exit 1: $(cat "$tmp/cut.out")"
want="- FAIL: ctest cut at SUITE_BUDGET_S 2 s: 1 passed and 1 failed before the cut, 1 of 3 not finished"
grep -qF -- "$want (suite/not_run.txt)" "$tmp/cut/summary.md" || fail "cut line: $(cat "$tmp/cut/summary.md")"
[ "$(cat "$tmp/cut/suite/not_run.txt")" = "Cube.C" ] || fail "not_run.txt: $(cat "$tmp/cut/suite/not_run.txt")"

# A mistyped step (or device-call PLAN) is refused with exit 2 before any step runs: the suite named before it
# leaves no folder, and the device call writes no plan.
code=0
PATH="$tmp/bin:$PATH" STUB_MODE=pass bash "$here/scripts/gpu_acceptance.sh" "$tmp/typo" suite suiet >"$tmp/typo.out" 2>&1 ||
  code=$?
[ "$code" -eq 2 ] || fail "a mistyped step exited $code: $(cat "$tmp/typo.out")"
grep -q "unknown step 'suiet'" "$tmp/typo.out" || fail "the mistyped step is not named: $(cat "$tmp/typo.out")"
[ ! -e "$tmp/typo/suite" ] || fail "the suite ran before the mistyped step was refused"
code=0
PLAN="suite suiet" bash "$here/scripts/gpu_device_call.sh" "$tmp/call" >"$tmp/call.out" 2>&1 || code=$?
[ "$code" -eq 2 ] && grep -q "PLAN names 'suiet'" "$tmp/call.out" || fail "a mistyped PLAN: exit $code: $(cat "$tmp/call.out")"
[ ! -e "$tmp/call" ] || fail "the device call started before the mistyped PLAN was refused"
echo "gpu_acceptance_suite_test: ok"
