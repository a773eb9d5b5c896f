#pragma once
// A case's result as plain data: the findings of its checks, its work counters, every timed frame and
// repetition, its floor and the device's state. Written by the runner and the timing, read by the report.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/common/atlas.h"
#include "bench/run/device_state.h"
#include "bench/run/timing_stats.h"
#include "bench/truth/findings.h"

namespace omnishadow::bench {

// One case of a run: what its checks found (CaseFindings), and what was timed, counted and sampled.
struct CaseResult : CaseFindings {
  FrameCounters counters;
  std::vector<FrameTiming> warmup;  // every warm-up frame of every repetition
  std::vector<FrameTiming> frames;  // every timed frame of every repetition
  GpuTimerCheck gpu_timer;
  int repetitions = 0;
  int frames_per_repetition =
      0;  // timed frames in each of its repetitions (RunOptions::repetition_ms); 0 untimed
  // Per repetition: the mean frame wall time and process CPU time of its timed frames (what Google Benchmark
  // reports per repetition and `compare` tests); the precision and stability figures are computed over these.
  std::vector<double> repetition_frame_ms, repetition_cpu_ms;
  // Per repetition whose GPU timer passed its check: the mean shadow + lighting GPU time of its timed frames.
  std::vector<double> repetition_gpu_ms;
  // Why its repetitions ended: "count" (the fixed count), "precision" (--precision met), "cap" (--precision
  // not met by --max-repetitions), "sustain" (--sustain's time), "stopped" (SIGINT/SIGTERM); empty if never
  // timed.
  std::string repetitions_ended_by;
  double precision_target_percent = 0.0;  // --precision, 0 without
  std::string precision_metric = "wall";  // --precision-metric: wall, cpu or gpu
  // The per-repetition figures --precision judges (wall time, process CPU time or GPU time).
  const std::vector<double>& precision_samples() const {
    return precision_metric == "cpu"   ? repetition_cpu_ms
           : precision_metric == "gpu" ? repetition_gpu_ms
                                       : repetition_frame_ms;
  }
  std::optional<FrameTiming> first_frame;  // the check frame rendered cold, right after configure
  float light_far = 0.0f;                  // far plane of the check frame's cube (fitted with fit_range)
  // Faces with no caster at the check frame, every light's (with face culling: cleared only).
  int empty_faces = 0;
  // NaN or Inf anywhere in the read-back buffers (cube, shadow factor, world position): any is a failed
  // check.
  uint64_t non_finite_cube = 0, non_finite_shadow = 0, non_finite_position = 0;
  // "full" or "sampled" (RunOptions::cube_read_back); "sampled+full" when face hashes differed from
  // six_pass's and the cube was read again in full to compare its values.
  std::string cube_read_back;
  std::optional<double>
      flicker_percent;  // --stability: pixels whose shadow factor changed by > 0.5 next frame
  std::optional<double>
      flicker_mean_abs;       // --stability: mean |change| of the shadow factor over covered pixels
  int object_face_pairs = 0;  // object x face draws the plan asks for (six_pass draws per frame)
  // --optimize view at the check frame: lights out of view (no pass) and faces of lights in view left out.
  int view_culled_lights = 0, view_culled_faces = 0;
  // What the counted frame (count_work's) rendered into the lights' maps: faces drawn, their texels, and its
  // shadow passes (six_pass: one a face drawn; a single pass: one a light drawn). -1: the backend keeps no
  // record of its faces (Backend::face_frames).
  int faces_rendered = -1, passes_rendered = -1;
  int64_t texels_rendered = -1;
  // The shadow storage as allocated for the case's scene (memory_budget.h shadow_texels); 0 before the plan.
  uint64_t shadow_texels = 0, shadow_storage_bytes = 0;
  // Layout atlas: its size as allocated and each light's face size at the check frame
  // (backends/common/atlas.h).
  std::optional<atlas::Plan> atlas;
  int atlas_planned_at = 0;            // with re-plans: the frame the check frame's tiles were planned for
  std::vector<double> atlas_coverage;  // by_coverage: each light's screen coverage at frame 0
  // The device's clocks, temperature, power and throttling before and after each repetition's frames
  // (bench/run/device_state.h), and where they came from.
  std::vector<DeviceState> device_states;
  std::string device_state_source;
  // The case's floor (FrameKind::floor): its shadow render passes with clears only and the frame shaded with
  // a constant; medians of kFloorFrames frames, shared by every case of the same backend, scene, sizes,
  // technique and storage. A pass's time over its floor is what the technique or filter costs beyond what any
  // variant pays.
  std::optional<FrameTiming> floor;
  // Milliseconds of the untimed part per step (configure, check_frame, read_back, cube_and_map_truth,
  // accuracy, comparisons, images, ...); a truth or reference shared with earlier cases costs only the case
  // that computed it.
  std::map<std::string, double> untimed_ms;
};

inline constexpr int kFloorFrames = 5;

}  // namespace omnishadow::bench
