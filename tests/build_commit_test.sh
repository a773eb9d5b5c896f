#!/usr/bin/env bash
# cmake/build_commit.cmake, run at every build: the file it writes names the commit checked out now (a new commit
# without configuring again included), "-dirty" while a tracked file differs from it, "unknown" outside a git
# checkout, and it is left untouched when the commit has not changed (a build at the same commit recompiles nothing).
set -euo pipefail
if ! command -v git >/dev/null; then
  echo "build_commit_test: skipped: git is not installed (Debian package git)"
  exit 77
fi
here="$(cd "$(dirname "$0")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "build_commit_test: $*" >&2; exit 1; }
repo="$tmp/repo" out="$tmp/build_commit.cpp"
record() { cmake -DSOURCE_DIR="$1" -DOUTPUT="$out" -P "$here/cmake/build_commit.cmake"; }
names() { grep -q "build_commit() { return \"$1\"; }" "$out" || fail "expected commit '$1': $(cat "$out")"; }
g() { git -C "$repo" -c user.name=t -c user.email=t@localhost "$@"; }

mkdir -p "$repo" && g init -q && echo a >"$repo/f" && g add f && g commit -q -m A
record "$repo"
names "$(g rev-parse --short=12 HEAD)"
grep -q "build_commit_date() { return \"$(g log -1 --format=%cI HEAD)\"; }" "$out" || fail "no commit date: $(cat "$out")"

touch -d 2000-01-01 "$out"
record "$repo"
[ "$(stat -c %Y "$out")" = "$(date -d 2000-01-01 +%s)" ] || fail "rewritten at the same commit (every build would recompile it)"

echo b >"$repo/f"
record "$repo"
names "$(g rev-parse --short=12 HEAD)-dirty"
echo untracked >"$repo/new"
g commit -q -am B
record "$repo"
names "$(g rev-parse --short=12 HEAD)"  # a new commit, no configure: its own hash; untracked files are not dirt

mkdir "$tmp/tarball"
record "$tmp/tarball"
names unknown
echo "build_commit: the checked-out commit at every build, -dirty, unknown outside git, untouched when unchanged"
