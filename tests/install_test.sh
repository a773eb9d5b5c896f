#!/usr/bin/env bash
# `cmake --install` gives a relocatable tree: installed to a scratch prefix and moved elsewhere, the binary finds
# its scenes and the report's scripts beside itself (share/omnishadow), runs a case and writes the report.
# Usage: install_test.sh BUILD_DIR
set -euo pipefail
build="$1"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
mv "$tmp/prefix" "$tmp/moved"
bin="$tmp/moved/bin/omnishadow"
fail() { echo "install test: $*"; exit 1; }
# The installed report renders its charts with matplotlib: without Debian's package the report cannot run.
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "SKIP: the installed report needs python3-matplotlib (Debian package; scripts/setup.sh installs it)"; exit 77; }
list="$("$bin" list)"
if grep -q "gl: unavailable" <<<"$list"; then echo "install test skipped: OpenGL backend unavailable here"; exit 77; fi
grep -qF "scenes ($tmp/moved/share/omnishadow/scenes)" <<<"$list" || fail "the moved binary does not read its own scenes: $(grep scenes <<<"$list")"
"$bin" run --backend gl --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard --frames 1 \
  --warmup 0 --benchmark_repetitions=1 --no-accuracy --out "$tmp/run" >"$tmp/run.log" 2>&1 || { cat "$tmp/run.log"; fail "run failed"; }
# The installed copy of the report script says so when it runs, so the test knows which one ran.
echo 'print("the installed report script ran")' >>"$tmp/moved/share/omnishadow/scripts/analysis/report.py"
"$bin" report "$tmp/run" --out "$tmp/report.html" >"$tmp/report.log" 2>&1 || { cat "$tmp/report.log"; fail "report failed"; }
grep -qF "the installed report script ran" "$tmp/report.log" || fail "report did not run the installed script: $(head -1 "$tmp/report.log")"
[ -s "$tmp/report.html" ] || fail "no report written"
echo "install test: run and report from a moved install"
