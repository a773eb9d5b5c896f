#!/usr/bin/env bash
# scripts/ci/fleet_store.sh, the fan-in jobs' store step: without OMNISHADOW_STORE_URL it stores nothing and says
# so (exit 0); on the default branch it stores the merged run; on another branch or in a merge request it stores
# nothing unless FLEET_STORE_ALL=1; a store that fails is one line without the URL's password, and fails the job.
# Then scripts/ci/fleet_compare.sh taking its baseline from the store (below).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" OMNISHADOW_BIN="$bin"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bin" run --backend gl --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames 1 \
  --warmup 0 --images all --benchmark_repetitions=1 --max-error 100 --out "$tmp/run" >"$tmp/run.log" 2>&1 ||
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
# Captured, not piped into grep -q: under pipefail a writer still writing when grep has matched and gone dies of
# SIGPIPE, and the test would fail by timing.
out="$(OMNISHADOW_STORE_URL="sqlite:$tmp/db" GITHUB_REF_NAME=topic FLEET_STORE_ALL=1 bash "$store" "$tmp/run")"
grep -q "already stored" <<<"$out" || fail "FLEET_STORE_ALL=1 does not store (again): $out"

# An unreachable server: the job fails with one line, and the password is not in it.
if OMNISHADOW_STORE_URL="postgresql://fleet:s3cret@127.0.0.1:1/runs?connect_timeout=2" CI_COMMIT_BRANCH=main \
    bash "$store" "$tmp/run" >"$tmp/out" 2>"$tmp/err"; then
  fail "a store into an unreachable server passed"
fi
grep -q "fleet:\*\*\*@127.0.0.1:1" "$tmp/err" || fail "the failing store does not name the server: $(cat "$tmp/err")"
! grep -q s3cret "$tmp/out" "$tmp/err" || fail "the password was printed: $(cat "$tmp/err")"
echo "fleet_store: not set, a branch, a merge request, the default branch, FLEET_STORE_ALL and a failing server as documented"

# fleet_compare.sh with OMNISHADOW_STORE_URL: the baseline is the store's run of the newest commit on the merge-base's
# first-parent line (a scratch repository: main at A and B, a branch at C; the run stored as A's). Images compare by
# the hashes the store kept (the same pass, changed ones are named); a status regression against the stored run
# fails the job; a store without a run of
# this device there falls back to the git baseline (here none: said, exit 0); an unreadable store is exit 2.
repo="$tmp/repo"
mkdir -p "$repo/scripts/ci"
cp "$here/scripts/ci/fleet_compare.sh" "$here/scripts/ci/fleet_matrix.args" "$repo/scripts/ci/"
g() { git -C "$repo" -c user.name=t -c user.email=t@localhost "$@"; }
g init -q -b main && g add -A && g commit -q -m A
a="$(g rev-parse HEAD)"; a12="${a:0:12}"   # a run records 12 digits of its commit; git gives fetch all 40
g commit -q --allow-empty -m B && g checkout -q -b feature && g commit -q --allow-empty -m C
cp -r "$tmp/run" "$tmp/merged"
/usr/bin/python3 -c 'import json,sys; p=sys.argv[1]+"/results.json"; d=json.load(open(p)); d["omnishadow"]["commit"]=sys.argv[2]; json.dump(d, open(p, "w"))' "$tmp/merged" "$a12"
"$bin" store "$tmp/merged" --db "sqlite:$tmp/fleet.db" >/dev/null
compare() { OMNISHADOW_STORE_URL="$1" FLEET_TARGET_BRANCH=main bash "$repo/scripts/ci/fleet_compare.sh" "$2"; }
cp -r "$tmp/run" "$tmp/same"
out="$(compare "sqlite:$tmp/fleet.db" "$tmp/same")" || fail "the same run against the stored one failed: $out"
grep -q "against the stored run of $a (OMNISHADOW_STORE_URL), merge-base" <<<"$out" || fail "not the stored baseline: $out"
n="$("$bin" fetch --db "sqlite:$tmp/fleet.db" --commit abc --out "$tmp/f-short" | grep -o "fetched [0-9]*")"
[ "$n" = "fetched 0" ] || fail "a commit of 3 digits matched a stored run: $n"
/usr/bin/python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["cases"]; sys.exit(not c or any(x["image_changes"] or x["work_changes"] for x in c))' \
  "$tmp/same/compare/comparison.json" || fail "images against the stored hashes: $(cat "$tmp/same/compare/comparison.json")"
"$bin" run --backend gl --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames 1 --warmup 0 \
  --images all --benchmark_repetitions=1 --max-error 0.001 --lookup-perturb 0.5 --out "$tmp/worse" >/dev/null 2>&1 || true
status=0
compare "sqlite:$tmp/fleet.db" "$tmp/worse" >"$tmp/worse.log" 2>&1 || status=$?
[ "$status" = 1 ] || fail "a status regression against the stored run: exit $status, not 1: $(cat "$tmp/worse.log")"
grep -q "ok -> failed" "$tmp/worse/compare/summary.md" || fail "the regression is not named: $(cat "$tmp/worse/compare/summary.md")"
grep -q "lit: changed (SHA-256 against the stored run's" "$tmp/worse/compare/summary.md" ||
  fail "the changed images are not named: $(cat "$tmp/worse/compare/summary.md")"
rm -rf "$tmp/same/compare"
out="$(compare "sqlite:$tmp/empty.db" "$tmp/same" 2>&1)" || fail "a store without the device's run: $out"
grep -q "no stored run of device key" <<<"$out" && grep -q "No baseline for this device key" "$tmp/same/compare/summary.md" ||
  fail "no stored run: not the git baseline's path: $out"
status=0
compare "mysql://nowhere/x" "$tmp/same" >"$tmp/bad.log" 2>&1 || status=$?
[ "$status" = 2 ] || fail "an unreadable store: exit $status, not 2: $(cat "$tmp/bad.log")"
# On the default branch the merge-base is the run's own commit, whose run was just stored: never its own baseline.
b="$(g rev-parse main)"
for name in merged-b same-b; do
  cp -r "$tmp/run" "$tmp/$name"
  /usr/bin/python3 -c 'import json,sys; p=sys.argv[1]+"/results.json"; d=json.load(open(p)); d["omnishadow"]["commit"]=sys.argv[2]; json.dump(d, open(p, "w"))' "$tmp/$name" "${b:0:12}"
done
"$bin" store "$tmp/merged-b" --db "sqlite:$tmp/fleet.db" >/dev/null
g checkout -q main
out="$(compare "sqlite:$tmp/fleet.db" "$tmp/same-b")" || fail "B's run against A's: $out"
grep -q "against the stored run of $a " <<<"$out" || fail "B's run compared with its own stored run, not A's: $out"
echo "fleet_compare: the stored run of the merge-base as baseline (images by hash), a status regression caught, the git path without one"
