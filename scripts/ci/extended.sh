#!/usr/bin/env bash
# The checks too slow for every landing (.ci/run takes about half an hour): run before resolving an issue that touches
# what they cover, and on a schedule where a CI engine offers one.
#   plays     tests labelled `extended`: the GitLab and GitHub fleet pipelines played end to end over two commits
#             (tests/fleet_pipeline_play.py, four builds)
#   mutants   the mutation suite: every planted bug fails a check on both APIs (scripts/experiments/mutants.py)
#   checks    no false alarm at cubes 1024 and 2048: a wide matrix of correct cases passes every check
#             (scripts/ci/large_cube_checks.sh; the mutants' matrices run at 256)
#   sanitize  the whole suite under ASan, UBSan and LSan (.ci/run runs the tests labelled `memory` only)
#   fuzz      each file reader fuzzed for FUZZ_SECONDS (default 300; .ci/run: a fixed 20,000 runs)
# Usage: scripts/ci/extended.sh [STAGE ...] (default: all five). Each stage's time is printed, and a table at the end.
set -euo pipefail
cd "$(dirname "$0")/../.."
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
stages=("$@")
[ ${#stages[@]} -eq 0 ] && stages=(plays mutants checks sanitize fuzz)
for s in "${stages[@]}"; do
  case "$s" in
    plays | mutants | checks | sanitize | fuzz) ;;
    *) echo "extended.sh: unknown stage '$s' (plays, mutants, checks, sanitize, fuzz)" >&2; exit 2 ;;
  esac
done
source scripts/lib/stages.sh
status=0
for s in "${stages[@]}"; do
  case "$s" in
    plays) stage plays bash -c 'bash scripts/build.sh && ctest --preset extended' || status=1 ;;
    mutants) stage mutants /usr/bin/python3 scripts/experiments/mutants.py --out build/mutants || status=1 ;;
    checks)
      stage checks bash -c 'bash scripts/build.sh && rm -rf build/large-cube-checks* &&
        bash scripts/ci/large_cube_checks.sh build/large-cube-checks' || status=1
      ;;
    sanitize) stage sanitize bash scripts/sanitize.sh || status=1 ;;
    fuzz) stage fuzz bash scripts/fuzz.sh "${FUZZ_SECONDS:-300}" || status=1 ;;
  esac
done
exit $status
