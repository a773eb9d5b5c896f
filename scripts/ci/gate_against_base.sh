#!/usr/bin/env bash
# The deterministic work gate on a runner whose CPU has no committed instruction-count baseline (JIT code depends
# on the CPU, so another CPU's counts cannot be compared): builds the base commit on this runner, in a scratch
# worktree, counts its instructions per timed frame exactly as for the commit under test, and compares the two
# (scripts/ci/instruction_counts.py, threshold 0.2%). The gate is then on wherever CI runs.
#   base: $OMNISHADOW_GATE_BASE (a CI engine's merge-base, e.g. GitLab's CI_MERGE_REQUEST_DIFF_BASE_SHA or
#         GitHub's github.event.pull_request.base.sha), else the parent commit HEAD~1.
#   An intended change of work: a line "Work-Change: <why>" in a commit message since the base; the change is
#   then reported and does not fail.
# Usage: scripts/ci/gate_against_base.sh OUT. Exit codes as instruction_counts.py --compare: 0 fine, 1 changed,
# 2 the base could not be built or counted. OMNISHADOW_GATE_BUILD and OMNISHADOW_GATE_COUNT replace the build and
# the counting command (run in each tree, OUT appended) for tests/gate_against_base_test.sh.
set -euo pipefail
out="${1:?usage: scripts/ci/gate_against_base.sh OUT}"
cd "$(dirname "$0")/../.."
base_rev="${OMNISHADOW_GATE_BASE:-HEAD~1}"
if ! base_sha="$(git rev-parse --verify -q "$base_rev^{commit}")"; then
  echo "ci_compare: instruction gate OFF: base commit '$base_rev' is not in this clone (a shallow clone?); fetch it or set OMNISHADOW_GATE_BASE"
  exit 0
fi
tree="$out-base-tree"
rm -rf "$tree"
git worktree add -q --detach "$tree" "$base_sha"
trap 'git worktree remove --force "$tree" >/dev/null 2>&1 || rm -rf "$tree"' EXIT
echo "ci_compare: instructions per frame against base commit $(git rev-parse --short=12 "$base_sha") ($base_rev), built and counted on this runner"
# Through ccache where it is installed, with paths relative to the scratch tree: the files the base shares with the
# commit under test were compiled by its build minutes ago (the SPIR-V cache of cmake/embed_spirv.py does the same).
if command -v ccache >/dev/null && [ -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ]; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$(cd "$tree" && pwd)" CCACHE_NOHASHDIR=true
fi
build="${OMNISHADOW_GATE_BUILD:-cmake --preset release >/dev/null && cmake --build --preset release --target omnishadow >/dev/null}"
if ! (cd "$tree" && bash -c "$build"); then
  echo "ci_compare: the base commit does not build here" >&2
  exit 2
fi
# The base counts with its own script, wherever that commit kept it (scripts/ before the folders by purpose).
base_counter=scripts/ci/instruction_counts.sh
[ -f "$tree/$base_counter" ] || base_counter=scripts/instruction_counts.sh
base_count="${OMNISHADOW_GATE_COUNT:-bash $base_counter}"
new_count="${OMNISHADOW_GATE_COUNT:-bash scripts/ci/instruction_counts.sh}"
(cd "$tree" && bash -c "$base_count \"\$0\"" "$out-base-instructions" >/dev/null) || exit 2
bash -c "$new_count \"\$0\"" "$out-instructions" >/dev/null
status=0
/usr/bin/python3 scripts/ci/instruction_counts.py --compare "$out-base-instructions/instructions.json" \
  "$out-instructions/instructions.json" --threshold 0.002 || status=$?
# The messages are read first: `git log | grep -q` under pipefail fails whenever grep stops early (SIGPIPE).
messages="$(git log --format=%B "$base_sha..HEAD")"
if [ "$status" -eq 1 ] && grep -q '^Work-Change:' <<<"$messages"; then
  echo "ci_compare: the work changed, as a commit since the base says:"
  grep '^Work-Change:' <<<"$messages" | sed 's/^/  /'
  status=0
fi
exit $status
