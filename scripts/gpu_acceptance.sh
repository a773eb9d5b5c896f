#!/usr/bin/env bash
# The checks only a real GPU can run (no false alarms, single-pass paths, timings a renderer can trust),
# one step per call so that each fits a device call (10 minutes). Writes OUT/<step>/ and appends one section per step
# to OUT/summary.md: exit codes, untimed and timed seconds, statuses, clocks, the figures the closing notes ask for.
# Usage: scripts/gpu_acceptance.sh OUT STEP [STEP...]
#   exits      `list`, `run --backend gl,vulkan` and `--backend vulkan,gl` must exit 0
#   clocks     the default run (both APIs) and the GL default matrix twice: PASS when no case's clock moved inside a
#              timed repetition and every case's first and last repetitions agree within 5% in GPU time (wall time
#              reported beside it); and the default run's
#              untimed part (checks, reference, read-backs, images) at most 0.5x its timed part
#   checks     no false alarm on correct code: the small-cube matrix that failed 124 of 156 cases at 3387fa1, the
#              grazing scene in every storage and depth format, the moments filters at 32 and 16 bits, the face_array
#              tetrahedral and dual_paraboloid layouts, and ctest (as the suite step runs it);
#              PASS or FAIL per part
#   multiview  GL and Vulkan multiview against six_pass with --check
#   singlepass nv_swizzle and mesh_shader against six_pass and geometry_shader with --check, GL and
#              Vulkan, room and heavy, cubes 512 and 1024, linear_depth and r32f_distance, culling off and on, and
#              nv_swizzle on the hall's 4 lamps (r32f_distance past far; the atlas) within a minute: PASS
#              when no check fails and, on an NVIDIA GPU (whose drivers expose every extension they need), none is
#              unsupported; the shadow pass's GPU time per technique beside six_pass's
#   matrix     the untimed/timed matrix: room, heavy and a 4.2 M-triangle scene x cubes 512-4096, GL
#              (the untimed part at most a quarter of the run); clock samples recorded
#   layouts    the equal-memory layout table (scripts/analysis/layout_table.py) on the GPU: cube, face_array, tetrahedral, room
#              and heavy, cubes 512 and 1024, GL and Vulkan, with --check; and dual_paraboloid beside the cube at
#              tessellations 1, 4 and 16 on room and mixed
#   lights     many point lights: hall at 1, 4, 16 and 64 lights in cube_array, face_array and cube (a cube and a
#              sampler per light, at most 16), grouped per face
#              (six_pass), per light (geometry_shader, vs_layer, multiview, mesh_shader where the GPU has them) and
#              every light in one pass (vs_layer, geometry_shader, mesh_shader --light-grouping all_lights), GL and
#              Vulkan,
#              cube 256, with --check: PASS when no check fails (quality is a figure: --max-error 100); the
#              many-light table (scripts/analysis/many_lights_table.py); the run is cut at 7 minutes (LIGHTS_BUDGET_S)
#   atlas      layout atlas on the GPU: hall at 4, 16 and 64 lights, atlas (tiles uniform and by distance) beside
#              cube_array, six_pass, geometry_shader, vs_layer and nv_swizzle (faces routed by viewport; nv_swizzle
#              natively where the NV extensions are, else unsupported), pcf_disk20, cube 256,
#              GL and Vulkan, with --check: PASS when no check fails; the many-light table; cut at 4 minutes
#              (ATLAS_BUDGET_S)
#   policies   what each frame needs with many lights: hall at 16 and 64 lights seen from mid-hall, culling to the
#              view and clustered light lists each on and off (--optimize none,view,clusters,view+clusters), each
#              without and with an update budget of 24 faces a frame, six_pass, cube_array, hard, cube 256, 400x300,
#              GL and Vulkan, with --check and a 24-frame staleness sequence for every case: PASS when no check
#              fails and the policy table's target holds (a policy at <= 1/4 of the texels of every light, every
#              face, full size, for <= 0.5 points more misclassified pixels); cut at 5 minutes (POLICIES_BUDGET_S)
#   walk       the same view walking 16 units back down the hall (--camera's sway): hall at 16 lights, culling to
#              the view and clustered lists off and on, six_pass and geometry_shader, pcf_disk20, cube 256, GL and
#              Vulkan, checked where the walk ends (frame 188) and timed over the 188 frames of the walk: PASS when
#              no check fails; the many-light table; cut at 3 minutes (WALK_BUDGET_S)
#   replan     the walk with an atlas re-planned every frame: hall at 24 lights, tiles by distance, re-plans off
#              and on, without and with an update budget of 24 faces, six_pass, pcf_disk20,
#              cube 256, 400x300 (the CPU's exact visibility of each sequence frame within the budget), GL and
#              Vulkan, checked where the walk ends (frame 188) and over a 24-frame staleness sequence, timed over
#              the walk: PASS when no check fails; the many-light table; cut at 3 minutes
#              (REPLAN_BUDGET_S)
#   capture    a failed case captured with --capture failed on both APIs and the Vulkan capture replayed by
#              gfxrecon-replay on this driver: PASS when it replays (exit 0); the GL case's RenderDoc capture
#              replayed by scripts/replay_renderdoc.py where RenderDoc's Python module is there (else said): PASS
#              when its image equals the capture run's lit image; both traces timed by scripts/replay_trace.py
#   suite      ctest as scripts/test.sh runs it (labels extended and memory left out), cut at SUITE_BUDGET_S (300):
#              PASS when none failed (the skipped listed); about 2 minutes on an H100 with 16 cores at 320 tests
#              (547 now); cut, it says how many passed and failed before the cut and lists the rest (not_run.txt)
#   tutorial   scripts/experiments/tutorial_ab.py: the timed passes against the tutorial's own rendering at the same
#              depth format, wall and GPU time: PASS where the harness is within 1.1x
#   precision  a 2% slowdown found at <= 1% false alarms in GPU time on the GPU-sized CI-style matrix, injected work
#              calibrated on the GPU: fixed and adaptive (--precision) designs across runs (scripts/experiments/
#              sensitivity.py, as CI compares builds) and inside one run (sensitivity_same_run.py), as many trials as fit
#              200 s each (PRECISION_BUDGET_S); every stopping rule replayed on the fixed design's samples
#              (repetition_replay.py); PASS/FAIL per design. PRECISION_MATRIX_SIZE=cpu runs it at the CPU size (a
#              smoke test of the step on a CPU driver, whose verdict says nothing of a GPU)
# ACCEPTANCE_BACKENDS (gl,vulkan) narrows the singlepass and many-light runs to one API: a run cut at its budget
# keeps the cases so far, and the matrix runs every GL case before the first Vulkan one, so a short device call
# runs each API as its own step (OUT/gl, OUT/vulkan) with half the budget. SINGLEPASS_BUDGET_S (480) cuts singlepass.
# Exit 1 when a command it ran failed (a failed check included). On the NVIDIA machine: bash .gpu/device.sh bash scripts/gpu_acceptance.sh "$OUT" exits multiview
set -uo pipefail
steps="exits checks clocks multiview singlepass matrix tutorial precision layouts lights atlas policies walk replan suite capture"
[ $# -gt 1 ] || { echo "usage: scripts/gpu_acceptance.sh OUT STEP [STEP...] ($steps)" >&2; exit 2; }
out="$1"; shift
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
mkdir -p "$out"
summary="$out/summary.md"
# The steps, a file for each kind (scripts/acceptance/): common.sh first, for what they share.
for part in common checks timing many_lights capture; do source "$here/scripts/acceptance/$part.sh"; done

# Every step named is known before the first one runs (a device call is too dear to spend on a typo's forerunners).
for step in "$@"; do
  case " $steps " in
    *" $step "*) ;;
    *) echo "gpu_acceptance: unknown step '$step' ($steps)" >&2; exit 2 ;;
  esac
done
for step in "$@"; do rm -rf "${out:?}/$step"; mkdir -p "$out/$step"; "step_$step"; done
exit "$failed"
