#!/usr/bin/env bash
# scripts/ci/gate_against_base.sh played on a toy repository (the real script and instruction_counts.py copied in;
# its build and count replaced by stubs that read the toy's files): the same work passes, +1% per frame fails,
# a "Work-Change:" line since the base lets it through, an unbuildable base is exit 2, an absent base turns the
# gate off (exit 0, said).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
toy="$tmp/toy"
mkdir -p "$toy/scripts/ci"
cp "$here/scripts/ci/gate_against_base.sh" "$here/scripts/ci/instruction_counts.py" "$toy/scripts/ci/"
cd "$toy"
git init -q && git config user.email t@example.com && git config user.name toy
cat > count.sh <<'SH'
mkdir -p "$1"
printf '{"format": "omnishadow-instructions/1", "instructions_per_frame": {"room/six_pass": %s}}\n' "$(cat work.txt)" > "$1/instructions.json"
SH
echo 1000000 > work.txt
echo ok > build.txt
commit() { git add -A && git commit -qm "$1" && git rev-parse HEAD; }
export OMNISHADOW_GATE_BUILD='test "$(cat build.txt)" = ok' OMNISHADOW_GATE_COUNT='bash count.sh'
failed=0
n=0
expect() {  # expect CODE BASE WHAT [TEXT]: runs the gate against BASE
  local code="$1" base="$2" what="$3" text="${4:-}" got=0
  n=$((n + 1))
  OMNISHADOW_GATE_BASE="$base" bash scripts/ci/gate_against_base.sh "$tmp/out$n" >"$tmp/log$n" 2>&1 || got=$?
  if [ "$got" -ne "$code" ] || { [ -n "$text" ] && ! grep -qF "$text" "$tmp/log$n"; }; then
    echo "FAILED: $what: exit $got (expected $code${text:+, saying '$text'})"; cat "$tmp/log$n"; failed=1
  else
    echo "ok: $what (exit $got)"
  fi
}
c0="$(commit 'base')"
echo "docs" > notes.txt; c1="$(commit 'same work')"
expect 0 "$c0" "the same instructions per frame pass"
echo 1010000 > work.txt; c2="$(commit 'one percent more work')"
expect 1 "$c1" "+1% per frame fails" "CHANGED"
git commit -q --allow-empty -m "explain" -m "Work-Change: the toy's extra pass"
expect 0 "$c1" "a Work-Change line since the base lets it through" "the work changed, as a commit since the base says"
expect 0 "0123456789abcdef0123456789abcdef01234567" "an absent base turns the gate off" "instruction gate OFF"
echo broken > build.txt; c4="$(commit 'breaks the build')"
echo ok > build.txt; commit 'fixes it' >/dev/null
expect 2 "$c4" "an unbuildable base is exit 2" "does not build"
[ "$failed" -eq 0 ] && echo "gate_against_base: $n of $n cases as expected"
exit "$failed"
