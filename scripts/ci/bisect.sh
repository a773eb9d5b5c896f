#!/usr/bin/env bash
# Finds the commit that introduced a regression (one the history or a comparison found) with `git bisect run`:
# in a scratch clone, builds GOOD and runs the matrix once as the base, then at every step builds, runs the
# matrix and lets `omnishadow compare BASE STEP <compare arguments>` decide: 0 good, 1 bad, anything else (and a
# build that fails: 125) skip. The compare is this checkout's binary, so the verdict's rules do not move with the
# commits bisected. Usage:
#   scripts/ci/bisect.sh GOOD BAD [--repo DIR] [--work DIR] [--build CMD] [--run CMD] -- [compare arguments]
#   --repo   the repository to bisect (default: this one); it is cloned, never checked out in place
#   --work   the scratch clone (default /tmp/omnishadow-bisect; kept, so later builds are incremental)
#   --build  run in the clone at each commit (default: cmake --preset release && cmake --build --preset release)
#   --run    run in the clone with $OUT set: writes a run folder there (default: the CI matrix, 5 repetitions)
# Example: scripts/ci/bisect.sh v1.2 HEAD -- --no-timing            (a work-counter or image change)
#          scripts/ci/bisect.sh abc123 HEAD -- --alpha 0.01 --min-effect 0.05 --metric cpu
# Prints the first bad commit and leaves it in WORK/bisect.txt; exit 0 when found, 1 otherwise.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
[ "$#" -ge 2 ] || { sed -n '2,16p' "$0" >&2; exit 2; }
good="$1"; bad="$2"; shift 2
repo="$here"; work="/tmp/omnishadow-bisect"
build='cmake --preset release >/dev/null && cmake --build --preset release'
# The CI matrix from its one definition (this checkout's scripts/ci/ci_matrix.sh, whatever commit is built), run by
# the commit's own binary; 5 repetitions (Google Benchmark takes the last value given). A commit too old for one of
# its options fails its run and is skipped.
run="OMNISHADOW_BIN=./build/release/omnishadow bash '$here/scripts/ci/ci_matrix.sh' \"\$OUT\" --benchmark_repetitions=5"
while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do
  case "$1" in
    --repo) repo="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --run) run="$2"; shift 2 ;;
    *) echo "bisect: unknown option $1" >&2; exit 2 ;;
  esac
done
[ "${1:-}" = "--" ] && shift
compare_bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
[ -x "$compare_bin" ] || { echo "bisect: $compare_bin missing; run scripts/build.sh first" >&2; exit 2; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"

[ -d "$work/.git" ] || git clone -q "$repo" "$work"
git -C "$work" fetch -q "$repo" '+refs/heads/*:refs/remotes/bisected/*' 'HEAD:refs/remotes/bisected/HEAD' 2>/dev/null || true
git -C "$work" bisect reset >/dev/null 2>&1 || true
good_sha="$(git -C "$repo" rev-parse --verify "$good^{commit}")"
bad_sha="$(git -C "$repo" rev-parse --verify "$bad^{commit}")"
git -C "$work" fetch -q "$repo" "$good_sha" "$bad_sha" 2>/dev/null || true
steps="$work/.bisect-runs"
rm -rf "$steps"; mkdir -p "$steps"

echo "bisect: base run at good ${good_sha:0:12}"
git -C "$work" checkout -q --force "$good_sha"
(cd "$work" && bash -c "$build") >"$steps/base-build.log" 2>&1 || { echo "bisect: GOOD does not build ($steps/base-build.log)"; exit 2; }
(cd "$work" && OUT="$steps/base" bash -c "$run") >"$steps/base-run.log" 2>&1 || { echo "bisect: the run failed at GOOD ($steps/base-run.log)"; exit 2; }

export BISECT_BUILD="$build" BISECT_RUN="$run" BISECT_BASE="$steps/base" BISECT_STEPS="$steps" BISECT_COMPARE_BIN="$compare_bin"
cd "$work"
git bisect start "$bad_sha" "$good_sha" >/dev/null
git bisect run bash "$here/scripts/ci/bisect_step.sh" "$@" >"$steps/bisect.log" 2>&1 || true
first="$(git bisect log | sed -n 's/^# first bad commit: \[\([0-9a-f]*\)\].*/\1/p')"
git bisect reset >/dev/null 2>&1
if [ -z "$first" ]; then
  echo "bisect: no first bad commit found (see $steps/bisect.log)"
  exit 1
fi
echo "$first" > "$work/bisect.txt"
echo "bisect: first bad commit $first: $(git -C "$work" log -1 --format=%s "$first")"
