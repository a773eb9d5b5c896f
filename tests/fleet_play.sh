#!/usr/bin/env bash
# Plays the GPU fleet's shell steps here (the steps .gitlab-ci.yml and .github/workflows/gpu-fleet.yml call): three
# shards numbered as GitLab numbers them, one as our GitHub workflow does, the fan-in merge, and the comparison.
# The merged run must hold exactly the unsharded run's cases, and comparing the two must pass (same work, same
# images). Usage: tests/fleet_play.sh (from ctest; needs build/release/omnishadow and OpenGL).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
# Skipped (ctest SKIP_RETURN_CODE 77) only for the reason `list` gives; a failing `list` fails the test.
if reason="$(XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" "$bin" list | grep -m1 'gl: unavailable')"; then
  echo "fleet play skipped: OpenGL backend unavailable here: $reason"
  exit 77
fi
# fleet_compare.sh reads the target branch's baseline from git: a copy of the tree without .git (a build carried
# to a GPU machine) cannot play it, and says so.
if ! git -C "$here" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "SKIP: fleet play needs a git checkout (fleet_compare.sh reads the target branch, origin/main, from it); $here is not one"
  exit 77
fi
if ! git -C "$here" rev-parse --verify --quiet origin/main >/dev/null &&
   ! git -C "$here" rev-parse --verify --quiet main >/dev/null; then
  echo "SKIP: fleet play compares against origin/main (or main), which the clone at $here lacks (git fetch it)"
  exit 77
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
matrix=(--backend gl --scene room --cube 32 --frame 64x48 --technique six_pass,geometry_shader
        --filter hard,pcf_disk20 --frames 1 --warmup 0 --no-accuracy --images all --benchmark_repetitions=2)
for i in 1 2 3; do
  CI_NODE_INDEX=$i CI_NODE_TOTAL=3 bash "$here/scripts/ci/fleet_shard.sh" "$work/shards/$i" "${matrix[@]}" \
    >"$work/shard$i.log" 2>&1 || { cat "$work/shard$i.log"; exit 1; }
  grep -q "GitLab CI_NODE_INDEX -> shard $((i - 1))/3" "$work/shard$i.log" || { echo "shard $i: no --shard auto line"; exit 1; }
done
bash "$here/scripts/ci/fleet_merge.sh" "$work/merged" "$work"/shards/* >/dev/null
"$bin" run --out "$work/whole" "${matrix[@]}" >/dev/null 2>&1
# GitHub numbering (0-based, exported by the workflow) gives the same slice as GitLab's shard 2.
OMNISHADOW_SHARD_INDEX=1 OMNISHADOW_SHARD_COUNT=3 bash "$here/scripts/ci/fleet_shard.sh" "$work/github1" "${matrix[@]}" \
  >/dev/null 2>&1
/usr/bin/python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
ids = lambda run: sorted(c["id"] for c in json.load(open(f"{work}/{run}/results.json"))["omnishadow"]["cases"])
merged, whole = ids("merged"), ids("whole")
assert merged == whole and len(whole) == 4, f"merged {merged} != unsharded {whole}"
assert ids("github1") == ids("shards/2"), "GitHub's shard 1 is GitLab's shard 2"
bench = [b for b in json.load(open(f"{work}/merged/results.json"))["benchmarks"] if b.get("run_type") == "iteration"]
assert len(bench) == 8, f"every shard's repetitions kept: {len(bench)} of 8"
PY
bash "$here/scripts/ci/fleet_compare.sh" "$work/merged" "$work/whole" >"$work/compare.log" 2>&1 || { cat "$work/compare.log"; exit 1; }
test -s "$work/merged/compare/summary.md"
# A baseline with a proven gate: compare takes metric, alpha and minimum effect from it; 2 against 2 repetitions
# can flag nothing at alpha 0.01 over 4 cases, so the gated comparison is blind and must fail, saying so.
echo '{"metric": "cpu", "alpha": 0.01, "min_effect": 0.3}' >"$work/whole/gate.json"
status=0
bash "$here/scripts/ci/fleet_compare.sh" "$work/merged" "$work/whole" >"$work/compare2.log" 2>&1 || status=$?
[ "$status" -eq 1 ] && grep -q "BLIND: 4 timed cases" "$work/compare2.log" || {
  echo "a blind gated comparison must fail (exit $status)"; cat "$work/compare2.log"; exit 1; }
/usr/bin/python3 -c 'import json, sys; c = json.load(open(sys.argv[1])); assert (c["metric"], c["alpha"], c["min_effect"]) == ("cpu", 0.01, 0.3), c' \
  "$work/merged/compare/comparison.json"
# A device without a baseline at the merge-base: nothing is compared, and the job's page says so and how to start.
cp -r "$work/merged" "$work/unknown"
rm -rf "$work/unknown/compare"
/usr/bin/python3 -c 'import json, sys; p = sys.argv[1]; d = json.load(open(p)); d["omnishadow"]["devices"]["gl"]["renderer"] = "No Such GPU"; json.dump(d, open(p, "w"))' \
  "$work/unknown/results.json"
GITHUB_STEP_SUMMARY="$work/step_summary.md" bash "$here/scripts/ci/fleet_compare.sh" "$work/unknown" \
  >"$work/compare3.log" 2>&1 || { cat "$work/compare3.log"; exit 1; }
grep -q "No baseline for this device key" "$work/step_summary.md" && grep -q "results/fleet_baselines/gl-no-such-gpu" "$work/step_summary.md" || {
  echo "no word on the job's page about the missing baseline"; cat "$work/compare3.log" "$work/step_summary.md" 2>/dev/null; exit 1; }
# A target branch that is not in the clone is an input error naming it (exit 2), not git's 128.
status=0
FLEET_TARGET_BRANCH=no-such-branch bash "$here/scripts/ci/fleet_compare.sh" "$work/unknown" >"$work/compare4.log" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q "target branch 'no-such-branch' is not in this clone" "$work/compare4.log" || {
  echo "a missing target branch must be exit 2 naming it (exit $status)"; cat "$work/compare4.log"; exit 1; }
echo "fleet play: 3 shards merged to the unsharded run's 4 cases; compare passed without a gate, failed blind with one; a missing baseline is said on the job's page"
