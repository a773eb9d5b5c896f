#!/usr/bin/env bash
# The fan-in job's verdict: compares a merged run with the fleet baseline of its device key at the merge-base commit
# (results/fleet_baselines/<key>/ as committed there: a merged run of scripts/ci/fleet_matrix.args, stored by
# scripts/ci/fleet_baseline.sh) or with BASE_RUN when given, writes RUN/compare/summary.md, posts it
# where the engine shows it, and fails on regressions and on a gated comparison too small to flag any (exit 1); 2 is
# an input error. Without a baseline it compares nothing and says so where the engine shows it, with how to make one.
# Usage: scripts/ci/fleet_compare.sh RUN [BASE_RUN]
#   FLEET_TARGET_BRANCH  the branch whose merge-base holds the baseline (default: the merge request's target,
#                        CI_MERGE_REQUEST_TARGET_BRANCH_NAME or GITHUB_BASE_REF, as origin/<name>; else origin/main,
#                        then main); none of them found is exit 2
#   GITHUB_STEP_SUMMARY  set by GitHub Actions: the summary is appended to the job's page
#   FLEET_GITLAB_TOKEN   with GitLab's CI_MERGE_REQUEST_IID: the summary is posted as a merge-request note
#   OMNISHADOW_STORE_URL a results store (docs/store.md) the default branch's fleet stores into: the baseline is then
#                        the stored run of this device key of the newest commit on the merge-base's first-parent line
#                        (FLEET_STORE_DEPTH commits back, 20 by default), with the gate committed beside the git
#                        baseline at the merge-base if there is one; none stored there: the git baseline, as without it
set -euo pipefail
run="$1"; base="${2:-}"; matrix_note=""
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
# The baselines fetched or unpacked for this call (the comparison itself is written under RUN/compare).
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
key="$("$bin" device-key "$run" | head -n 1)"
# Appends a markdown file to the job's page (GitHub) and posts it as a merge-request note (GitLab).
publish() {
  local file="$1"
  if [ -n "${GITHUB_STEP_SUMMARY:-}" ]; then { echo "## $key"; cat "$file"; } >> "$GITHUB_STEP_SUMMARY"; fi
  if [ -n "${FLEET_GITLAB_TOKEN:-}" ] && [ -n "${CI_MERGE_REQUEST_IID:-}" ]; then
    body="$(/usr/bin/python3 -c 'import json,sys; print(json.dumps({"body": "## " + sys.argv[1] + "\n\n" + open(sys.argv[2]).read()[:900000]}))' "$key" "$file")"
    if ! command -v curl >/dev/null; then
      echo "fleet_compare: WARNING: curl is missing (scripts/setup.sh installs it): no merge-request note" >&2
    elif ! curl -sS -f -X POST -H "PRIVATE-TOKEN: $FLEET_GITLAB_TOKEN" -H "Content-Type: application/json" \
        --data "$body" "$CI_API_V4_URL/projects/$CI_PROJECT_ID/merge_requests/$CI_MERGE_REQUEST_IID/notes" >/dev/null; then
      echo "fleet_compare: WARNING: posting the merge-request note failed (curl's error above); the artifact keeps the summary" >&2
    fi
  fi
}
# The store's run of this device at the newest commit it holds from MERGE_BASE back along the first parents, not
# of RUN's own commit (on the default branch the merge-base is that commit, and its run was just stored): prints
# "FOLDER COMMIT"; 1 when there is none, 2 (said) when the store cannot be read.
store_baseline() {
  local commit found folder="$scratch/store" own
  mkdir -p "$folder"
  own="$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["omnishadow"].get("commit", "")[:12])' "$run/results.json")"
  for commit in $(git -C "$here" rev-list --first-parent -n "${FLEET_STORE_DEPTH:-20}" "$1"); do
    [ "${commit:0:12}" != "$own" ] || continue
    rm -rf "$folder/runs"
    if ! "$bin" fetch --db "$OMNISHADOW_STORE_URL" --device-key "$key" --commit "$commit" --out "$folder/runs" >/dev/null; then
      echo "fleet_compare: the store named by OMNISHADOW_STORE_URL cannot be read (its error above)" >&2
      return 2
    fi
    found="$(find "$folder/runs" -mindepth 2 -maxdepth 2 -name results.json | sort | tail -n 1)"
    if [ -n "$found" ]; then echo "$(dirname "$found") $commit"; return 0; fi
  done
  echo "fleet_compare: no stored run of device key '$key' in the ${FLEET_STORE_DEPTH:-20} commits before merge-base ${1:0:12}: the git baseline, if any" >&2
  return 1
}
if [ -z "$base" ]; then
  requested="${CI_MERGE_REQUEST_TARGET_BRANCH_NAME:-${GITHUB_BASE_REF:-main}}"
  target=""
  if [ -n "${FLEET_TARGET_BRANCH:-}" ]; then candidates=("$FLEET_TARGET_BRANCH"); else candidates=("origin/$requested" "$requested"); fi
  for candidate in "${candidates[@]}"; do
    if git -C "$here" rev-parse -q --verify "$candidate^{commit}" >/dev/null; then target="$candidate"; break; fi
  done
  [ -n "$target" ] || { echo "fleet_compare: target branch '${FLEET_TARGET_BRANCH:-origin/$requested}' is not in this clone (fetch it, or set FLEET_TARGET_BRANCH)" >&2; exit 2; }
  merge_base="$(git -C "$here" merge-base HEAD "$target")" || { echo "fleet_compare: no merge-base of HEAD and $target" >&2; exit 2; }
  if [ -n "${OMNISHADOW_STORE_URL:-}" ]; then
    status=0
    stored="$(store_baseline "$merge_base")" || status=$?
    [ "$status" -ne 2 ] || exit 2
  fi
fi
if [ -n "${stored:-}" ]; then
  base="${stored% *}"
  echo "fleet_compare: $run against the stored run of ${stored##* } (OMNISHADOW_STORE_URL), merge-base ${merge_base:0:12}"
  git -C "$here" show "$merge_base:results/fleet_baselines/$key/gate.json" > "$base/gate.json" 2>/dev/null ||
    rm -f "$base/gate.json"
  git -C "$here" show "$merge_base:results/fleet_baselines/$key/replay.json" > "$base/replay.json" 2>/dev/null ||
    rm -f "$base/replay.json"
elif [ -z "$base" ]; then
  base="$scratch/baseline"
  mkdir -p "$base"
  if ! git -C "$here" archive "$merge_base" "results/fleet_baselines/$key" 2>/dev/null | tar -x -C "$base" --strip-components=3 2>/dev/null; then
    mkdir -p "$run/compare"
    cat > "$run/compare/summary.md" <<MD
**No baseline for this device key at merge-base ${merge_base:0:12}: nothing was compared.** This run's results are
in the job's artifacts. To start tracking this device, make its merged run the baseline on the target branch
(docs/regressions.md, "A GPU fleet on GitLab CI or GitHub Actions"): download this job's artifact and run
\`scripts/ci/fleet_baseline.sh fleet/merged\` (optionally \`--gate gate.json\`), then commit
\`results/fleet_baselines/$key/\`.
MD
    echo "fleet_compare: no baseline for device key '$key' at merge-base ${merge_base:0:12}: nothing compared (said in the summary)"
    publish "$run/compare/summary.md"
    exit 0
  fi
  echo "fleet_compare: $run against results/fleet_baselines/$key at merge-base ${merge_base:0:12}"
  if ! cmp -s "$base/fleet_matrix.args" "$here/scripts/ci/fleet_matrix.args"; then
    matrix_note="The fleet's matrix (scripts/ci/fleet_matrix.args) differs from the baseline's: cases in only one of
them are not compared; refresh the baseline from a merged run of this matrix (scripts/ci/fleet_baseline.sh)."
  fi
else
  echo "fleet_compare: $run against $base"
fi
gate=(--timing-report-only)
if [ -f "$base/gate.json" ]; then
  gate=(--gate "$base/gate.json")
fi
status=0
"$bin" compare "$base" "$run" "${gate[@]}" --out "$run/compare" || status=$?
summary="$run/compare/summary.md"
if [ -n "${matrix_note:-}" ]; then echo "fleet_compare: $matrix_note" | tee -a "$summary"; fi
# A gated comparison whose repetitions cannot reach significance would pass any slowdown: fail loudly.
if [ -f "$base/gate.json" ] && [ -f "$run/compare/comparison.json" ]; then
  blind="$(/usr/bin/python3 -c 'import json,sys; print(sum(1 for c in json.load(open(sys.argv[1]))["cases"] if c.get("base_n") and c.get("new_n") and not c.get("resolvable", True)))' "$run/compare/comparison.json")"
  if [ "$blind" -gt 0 ]; then
    echo "fleet_compare: BLIND: $blind timed cases cannot be flagged at the gate's alpha whatever their change (too few repetitions); run more" | tee -a "$summary"
    [ "$status" -ne 0 ] || status=1
  fi
fi
# The traces' replays (scripts/ci/fleet_replay.sh) against the baseline's: a trace that fails now or whose image
# changed fails the fan-in; a baseline without replays compares nothing and says so.
if [ -f "$run/replay.json" ]; then
  mkdir -p "$run/compare"
  replay_status=0
  /usr/bin/python3 "$here/scripts/ci/replay_compare.py" "$base/replay.json" "$run/replay.json" >>"$summary" || replay_status=$?
  [ "$replay_status" -eq 0 ] || [ "$status" -gt 1 ] || status=$replay_status
  [ "$replay_status" -eq 0 ] || echo "fleet_compare: the replayed traces regressed (the summary's Replayed traces)"
fi
[ -f "$summary" ] && publish "$summary"
exit $status
