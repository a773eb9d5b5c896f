#!/usr/bin/env bash
# One step of scripts/ci/bisect.sh, run by `git bisect run` in the scratch clone at the commit under test. Exit codes
# are git bisect's: 0 good, 1 bad, 125 skip (the commit does not build, or the run or compare could not decide).
set -uo pipefail
sha="$(git rev-parse --short=12 HEAD)"
out="$BISECT_STEPS/$sha"
rm -rf "$out"
if ! bash -c "$BISECT_BUILD" >"$out.build.log" 2>&1; then
  echo "bisect step $sha: build failed: skip"
  exit 125
fi
if ! OUT="$out" bash -c "$BISECT_RUN" >"$out.run.log" 2>&1; then
  echo "bisect step $sha: the run failed: skip"
  exit 125
fi
"$BISECT_COMPARE_BIN" compare "$BISECT_BASE" "$out" --out "$out/compare" "$@" >"$out.compare.log" 2>&1
status=$?
case $status in
  0) echo "bisect step $sha: good" ;;
  1) echo "bisect step $sha: bad (regression against the base)" ;;
  *) echo "bisect step $sha: compare exit $status: skip"; status=125 ;;
esac
exit $status
