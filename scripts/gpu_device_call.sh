#!/usr/bin/env bash
# One lent device call's worth of scripts/gpu_acceptance.sh, the steps the open work owes a GPU, in order of value,
# each cut at its own budget and none started without the time it needs, so that the folder is complete and
# archived before the call's limit. A lent call is 10 minutes of command time at most and one session holds 15
# minutes of device time, start included: TOTAL_S (default 540) is what this script may spend.
#   1. singlepass, GL then Vulkan (nv_swizzle and mesh_shader natively, against six_pass, with --check)
#   2. capture (a failed case captured and replayed on the GPU's driver, both APIs)
#   3. suite (ctest as scripts/test.sh runs it: 0 failed on a vendor GPU), given what the call has left (at least
#      150 s, at most 420): the suite has grown past what a fixed share fits, and a cut one says only how far it got
#   4. lights, then policies, then atlas, each GL then Vulkan (the many-light tables and the policies' target)
# Each step writes OUT/<api or all>/<step>/ and its section of that folder's summary.md; OUT/plan.md lists what ran,
# its exit and seconds, and what was left for lack of time. At the end OUT is archived as OUT.tgz beside it (the
# files a device call brings back are few and bounded: the archive is the one to fetch).
# PLAN (default "singlepass capture suite lights policies atlas") picks and orders the steps: the first call
# reaches about the suite; a second one runs PLAN="lights policies atlas" (walk and replan, named, run like them).
# Usage, on the device machine: bash .gpu/device.sh bash scripts/gpu_device_call.sh "$OUT/acc"
#   (docs/gpu.md: the bundle, the carried packages, and what the lent machine's settings allow: nothing changed)
# Exit: 0 when every step that ran passed, 1 otherwise (the plan says which), 2 on bad input.
set -uo pipefail
out="${1:?usage: scripts/gpu_device_call.sh OUT}"
here="$(cd "$(dirname "$0")/.." && pwd)"
total="${TOTAL_S:-540}"
steps="${PLAN:-singlepass capture suite lights policies atlas}"
# A mistyped PLAN is refused before the first step spends the call.
for step in $steps; do
  case " singlepass suite capture lights policies atlas walk replan " in
    *" $step "*) ;;
    *) echo "gpu_device_call: PLAN names '$step' (singlepass suite capture lights policies atlas walk replan)" >&2; exit 2 ;;
  esac
done
start=$(date +%s)
mkdir -p "$out"
plan="$out/plan.md"
echo "# Device call plan (TOTAL_S $total)" >"$plan"
echo "| step | API | budget s | exit | seconds |" >>"$plan"
echo "|---|---|---|---|---|" >>"$plan"
status=0
left() { echo $((total - ($(date +%s) - start))); }
# run_step STEP API BUDGET_VAR BUDGET NEED: runs when NEED seconds remain (the budget plus the step's own
# untimed tail: tables, judging), with the budget variable set (- for a step whose commands bound themselves),
# and is cut at NEED.
run_step() {
  local step=$1 api=$2 var=$3 budget=$4 need=$5 t0 code
  if [ "$(left)" -lt "$need" ]; then
    echo "| $step | $api | $budget | not run: $(left) s left, $need needed | - |" >>"$plan"
    return
  fi
  t0=$(date +%s)
  local budget_env=()
  [ "$var" = - ] || budget_env=("$var=$budget")
  env "${budget_env[@]}" ACCEPTANCE_BACKENDS="${api/all/gl,vulkan}" \
    timeout -k 5 "$need" bash "$here/scripts/gpu_acceptance.sh" "$out/$api" "$step" >"$out/$api-$step.log" 2>&1
  code=$?
  [ "$code" -eq 0 ] || status=1
  echo "| $step | $api | $budget | $code | $(($(date +%s) - t0)) |" >>"$plan"
}
for step in $steps; do
  case "$step" in
    singlepass)  # its matrix cut at 70 s, then the hall's nv_swizzle check (at most 60 s)
      run_step singlepass gl SINGLEPASS_BUDGET_S 70 140
      run_step singlepass vulkan SINGLEPASS_BUDGET_S 70 140 ;;
    suite)  # what is left, less the archive's margin: at least 150 s, at most 420
      budget=$(($(left) - 20))
      [ "$budget" -le 420 ] || budget=420
      [ "$budget" -ge 150 ] || budget=150
      run_step suite all SUITE_BUDGET_S "$budget" $((budget + 20)) ;;
    capture) run_step capture all - - 90 ;;
    lights | policies | atlas | walk | replan)
      var="$(tr '[:lower:]' '[:upper:]' <<<"$step")_BUDGET_S"
      run_step "$step" gl "$var" 40 60
      run_step "$step" vulkan "$var" 40 60 ;;
  esac
done
echo "" >>"$plan"
echo "Spent $(($(date +%s) - start)) s of $total; exit $status." >>"$plan"
cat "$plan"
tar -czf "$out.tgz" -C "$(dirname "$out")" "$(basename "$out")" 2>/dev/null
exit "$status"
