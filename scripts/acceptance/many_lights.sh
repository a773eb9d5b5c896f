#!/usr/bin/env bash
# The many-light steps, each a hall run on a time budget: lights, atlas, policies, walk and replan. Sourced by
# scripts/gpu_acceptance.sh, whose header says what each step passes on.

# A many-light run of the hall at cube 256 with --check, cut at a budget (the cases so far kept), judged and
# tabulated: many_lights_run STEP BUDGET_VARIABLE DEFAULT_SECONDS RUN_ARGS...
many_lights_run() {
  local step=$1 budget_var=$2 budget=${!2:-$3}
  shift 3
  note "## $step"
  timeout -k 20 "$budget" "$bin" run --backend "${ACCEPTANCE_BACKENDS:-gl,vulkan}" --scene hall "$@" \
    --cube 256 --check --max-error 100 --benchmark_repetitions=3 --images none --out "$out/$step/run" \
    >"$out/$step/run.log" 2>&1
  local code=$?
  [ "$code" -eq 124 ] && note "- $step run --check: cut at $budget_var (the cases so far kept)" ||
    { [ "$code" -eq 137 ] && note "- $step run --check: killed 20 s past $budget_var: a case did not end (the cases so far kept)"; } ||
    exit_note "$code" "$step run --check"
  judge_and_tabulate "$out/$step/run" many_lights_table.py "$out/$step/many-lights.md"
}

step_lights() {
  many_lights_run lights LIGHTS_BUDGET_S 420 --light-count 1,4,16,64 --layout cube_array,face_array,cube \
    --technique six_pass,geometry_shader,vs_layer,multiview,mesh_shader --light-grouping per_light,all_lights \
    --filter hard,pcf_disk20
}

step_atlas() {
  many_lights_run atlas ATLAS_BUDGET_S 240 --light-count 4,16,64 --layout atlas,cube_array \
    --atlas-tiles uniform,by_distance --technique six_pass,geometry_shader,vs_layer,nv_swizzle --filter pcf_disk20
}

# Every policy with a staleness sequence of 24 frames (the same frames and lights for all, so that their errors
# compare), at 400x300 so that the CPU's exact visibility of each frame stays within the budget; the policy table
# judges the target (a policy at <= 1/4 of the texels of every light, every face, full size, <= 0.5 points more
# misclassified).
step_policies() {
  many_lights_run policies POLICIES_BUDGET_S 300 --light-count 16,64 --camera 0,3,0,20,2,0 --layout cube_array \
    --technique six_pass --optimize none,view,clusters,view+clusters --update-budget none,24 --filter hard \
    --frame 400x300 --staleness-frames 24
  /usr/bin/python3 "$here/scripts/analysis/policy_table.py" "$out/policies/run" --out "$out/policies/policies.md" \
    --judge >/dev/null 2>&1
  local code=$?
  grep -E "^## |^Target" "$out/policies/policies.md" 2>/dev/null | tee -a "$summary"
  [ "$code" -eq 0 ] && note "**PASS** policies: the target met in every group with its baseline" ||
    { note "**FAIL** policies: the target missed (or no table: exit $code)"; failed=1; }
}

# What a walk gains: timed over frames 0-187, the camera's whole way back, so a frame's culling and lists are
# those of where the camera then stands.
step_walk() {
  many_lights_run walk WALK_BUDGET_S 180 --light-count 16 --camera 0,3,0,20,2,0,-16,0,0 --check-frame 188 \
    --layout cube_array --technique six_pass,geometry_shader --optimize none,view+clusters --filter pcf_disk20 \
    --frames 188 --warmup 0
}

# What re-planning an atlas along the walk costs and buys: the tiles sized again every frame (blocks whose size
# held kept in place), with and without an update budget, whose staleness sequence holds every lamp a re-plan
# moved to rendering again.
step_replan() {
  many_lights_run replan REPLAN_BUDGET_S 180 --light-count 24 --camera 0,3,0,20,2,0,-16,0,0 --check-frame 188 \
    --layout atlas --atlas-tiles by_distance --atlas-replan none,1 --update-budget none,24 --staleness-frames 24 \
    --frame 400x300 --technique six_pass --filter pcf_disk20 --frames 188 --warmup 0
}
