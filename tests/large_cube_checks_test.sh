#!/usr/bin/env bash
# scripts/ci/large_cube_checks.sh end to end at a small cube, so that the script itself (its variables under set -u,
# the options it passes, the judge it calls) is held by every CI run and not only by the extended stage, where a
# fault shows after 40 minutes: both parts run and are judged PASS with cases checked, on both APIs; a run that
# cannot finish (an unknown technique) stops the script with exit 2 and names the log, never a PASS.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:?OMNISHADOW_BIN names the built omnishadow}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "large_cube_checks_test: $*" >&2; exit 1; }
sweep() {
  OMNISHADOW_BIN="$bin" SWEEP_SCENES=room SWEEP_TECHNIQUES="$1" bash "$here/scripts/ci/large_cube_checks.sh" "$2"
}

# Cube 16, one technique and one scene: the smallest matrix that still runs every storage, depth format and layout,
# and every remedy, through both parts.
code=0
SWEEP_CUBES=16 sweep six_pass "$tmp/ok" >"$tmp/ok.out" 2>&1 || code=$?
[ "$code" -eq 0 ] || fail "exit $code on correct code: $(tail -n 20 "$tmp/ok.out")"
for part in formats remedies; do
  [ -f "$tmp/ok/$part/results.json" ] || fail "no $part/results.json"
done
[ "$(grep -c '^- PASS' "$tmp/ok.out")" -eq 2 ] || fail "expected two PASS verdicts: $(cat "$tmp/ok.out")"
/usr/bin/python3 - "$tmp/ok" <<'EOF' || fail "a part did not check cases on both APIs"
import json, sys
for part in ("formats", "remedies"):
    cases = json.load(open(f"{sys.argv[1]}/{part}/results.json"))["omnishadow"]["cases"]
    apis = {c["id"].split("/")[0] for c in cases if c["status"] == "ok"}
    assert apis == {"gl", "vulkan"}, (part, apis)
EOF

# A run that stops on bad input: exit 2, its log named, no verdict.
code=0
SWEEP_CUBES=16 sweep no_such_technique "$tmp/bad" >"$tmp/bad.out" 2>&1 || code=$?
[ "$code" -eq 2 ] || fail "exit $code for a run that did not finish (want 2): $(cat "$tmp/bad.out")"
grep -q "its log: $tmp/bad/formats.log" "$tmp/bad.out" || fail "the log is not named: $(cat "$tmp/bad.out")"
grep -q PASS "$tmp/bad.out" && fail "a PASS after a run that did not finish: $(cat "$tmp/bad.out")"
echo "large_cube_checks_test: ok"
