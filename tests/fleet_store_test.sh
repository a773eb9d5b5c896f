#!/usr/bin/env bash
# scripts/ci/fleet_store.sh, the fan-in jobs' store step: without OMNISHADOW_STORE_URL it stores nothing and says
# so (exit 0); on the default branch it stores the merged run; on another branch or in a merge request it stores
# nothing unless FLEET_STORE_ALL=1; a store that fails is one line without the URL's password, and fails the job.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" OMNISHADOW_BIN="$bin"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bin" run --backend gl --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames 1 \
  --warmup 0 --images none --no-accuracy --benchmark_repetitions=1 --out "$tmp/run" >"$tmp/run.log" 2>&1 ||
  { cat "$tmp/run.log"; exit 1; }
store="$here/scripts/ci/fleet_store.sh"
runs() { /usr/bin/python3 -c 'import sqlite3,sys; print(sqlite3.connect(sys.argv[1]).execute("SELECT COUNT(*) FROM runs").fetchone()[0])' "$tmp/db"; }
fail() { echo "fleet_store_test: $*" >&2; exit 1; }

out="$(env -u OMNISHADOW_STORE_URL bash "$store" "$tmp/run")"
grep -q "OMNISHADOW_STORE_URL is not set" <<<"$out" || fail "no word without the variable: $out"
[ ! -e "$tmp/db" ] || fail "stored without the variable"

out="$(OMNISHADOW_STORE_URL="sqlite:$tmp/db" CI_COMMIT_BRANCH=feature CI_DEFAULT_BRANCH=main bash "$store" "$tmp/run")"
grep -q "is not the default branch 'main': not stored" <<<"$out" || fail "a branch's run: $out"
[ ! -e "$tmp/db" ] || fail "a branch's run was stored"
out="$(OMNISHADOW_STORE_URL="sqlite:$tmp/db" CI_COMMIT_BRANCH=main CI_MERGE_REQUEST_IID=7 bash "$store" "$tmp/run")"
grep -q "not stored" <<<"$out" || fail "a merge request's run: $out"

OMNISHADOW_STORE_URL="sqlite:$tmp/db" CI_COMMIT_BRANCH=main CI_DEFAULT_BRANCH=main bash "$store" "$tmp/run" >/dev/null
[ "$(runs)" = 1 ] || fail "the default branch's run is not stored"
OMNISHADOW_STORE_URL="sqlite:$tmp/db" GITHUB_REF_NAME=topic FLEET_STORE_ALL=1 bash "$store" "$tmp/run" |
  grep -q "already stored" || fail "FLEET_STORE_ALL=1 does not store (again)"

# An unreachable server: the job fails with one line, and the password is not in it.
if OMNISHADOW_STORE_URL="postgresql://fleet:s3cret@127.0.0.1:1/runs?connect_timeout=2" CI_COMMIT_BRANCH=main \
    bash "$store" "$tmp/run" >"$tmp/out" 2>"$tmp/err"; then
  fail "a store into an unreachable server passed"
fi
grep -q "fleet:\*\*\*@127.0.0.1:1" "$tmp/err" || fail "the failing store does not name the server: $(cat "$tmp/err")"
! grep -q s3cret "$tmp/out" "$tmp/err" || fail "the password was printed: $(cat "$tmp/err")"
echo "fleet_store: not set, a branch, a merge request, the default branch, FLEET_STORE_ALL and a failing server as documented"
