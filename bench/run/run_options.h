#pragma once
// How a run measures: where it writes, how long it warms up and times, which images and read-backs it keeps,
// the devices' options, and the test-only faults.

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "bench/truth/case_checks.h"
#include "scenes/scene.h"

namespace omnishadow::bench {

// The options of a run, as `omnishadow run` takes them (bench/cli/cli_options.cpp): the checks' part in
// CheckOptions (bench/truth/case_checks.h), the rest here.
struct RunOptions : CheckOptions {
  std::string out_dir;     // results/<run>; images go under out_dir/images/<case id>/
  std::string scenes_dir;  // where `--scene room` finds room.json
  // --light / --camera: the point light and camera of every scene, as given (text kept for results.json).
  std::optional<scene::LightPlacement> light;
  std::optional<scene::CameraPlacement> camera;
  std::string light_text, camera_text;
  int warmup_frames = 2;  // rendered before timing, excluded from every figure
  // Warm-up by time as well (--warmup-ms): after the warm-up frames, more of them (the same frame indices
  // again, so the timed frames are the same frames whatever the count) until this much time has passed, so
  // that a GPU's clock has ramped up after the CPU-side pauses between repetitions. Negative: kGpuWarmupMs on
  // a GPU, 0 on a CPU driver (llvmpipe, lavapipe: no clock to ramp; the process keeps the CPUs busy).
  double warmup_ms = -1.0;
  static constexpr double kGpuWarmupMs = 100.0;
  // Before a backend's first timed repetition, render its first case until the device clock reads steady
  // (clock_steady: within 2% for a second of continuous rendering), at most this long; 0 skips it.
  double settle_s = 10.0;
  bool lock_clocks = false;  // --lock-clocks: NVML locked clocks for the run, a one-line refusal elsewhere
  int frames = 10;           // timed frames per repetition (Google Benchmark iterations), at least
  // A repetition's length in time as well (--repetition-ms): before the first round each case renders a few
  // frames and gets as many more timed frames per repetition as this takes
  // (CaseResult::frames_per_repetition). On a GPU a few sub-millisecond frames vary by 20-60% from one
  // repetition to the next at a steady clock (an H200: 33 of 120 default cases' first and last repetitions
  // more than 5% apart at 4 frames); Google Benchmark sizes its iterations by time for the same reason.
  // Negative: kGpuRepetitionMs on a GPU, 0 on a CPU driver (its frames are long already, and the count stays
  // the same from run to run, as instruction counts need).
  double repetition_ms = -1.0;
  static constexpr double kGpuRepetitionMs = 100.0;
  // Which image files a case writes (--images). failed (the default): the PNGs a person looks at, for every
  // case (lit, cube faces, shadow factor, error heatmap), and for a case that failed a check also every float
  // buffer (shadow factor, world position, coverage as PFM) beside its diff images; all: every file for every
  // case; none: no file (the checks still run).
  enum class ImagePolicy { none, failed, all };
  ImagePolicy images = ImagePolicy::failed;
  bool write_images() const { return images != ImagePolicy::none; }
  // Encode and write image files on a worker thread (bench/run/async_writer.h) while the next case renders;
  // the caller drains them (Harness::drain_writes) before anything is timed. Off: written before prepare()
  // returns.
  bool async_images = false;
  // How much of each cube comes back to the host (--cube-read-back). automatic: in full up to
  // kFullCubeReadBackMax a face edge or with --images all, above that only what the device computes (face
  // hashes, non-finite counts, the check grid: shaders/cube_summary.comp), the cube in full only where hashes
  // differ from six_pass's. full / sampled: always one or the other (sampled still reads in full where hashes
  // differ).
  enum class CubeReadBackPolicy { automatic, full, sampled };
  CubeReadBackPolicy cube_read_back = CubeReadBackPolicy::automatic;
  static constexpr int kFullCubeReadBackMax = 1024;  // 6 x 1024^2 floats: 24 MB
  bool accuracy = true;         // shadow error against exact visibility (ray-cast reference)
  bool memory_precheck = true;  // fail a case that cannot fit before it allocates (bench/run/memory_budget.h)
  uint64_t memory_budget =
      0;  // --memory-budget: plan as if the device had this many bytes (0: what it reports)
  // Also render check_frame + 1 and report how much of the shadow factor changed (flicker): with a light that
  // moves by tiny steps (scenes/extremes/stability_*), any change beyond the motion itself is instability.
  bool stability = false;
  // --staleness-frames: cases render frames 0..N-1 from a fresh start and report, per frame, the faces
  // rendered and stale and the error against that frame's exact visibility
  // (bench/run/staleness_sequence.cpp). Negative: kStalenessFrames for cases with an update budget, none for
  // the others; 0: none.
  int staleness_frames = -1;
  static constexpr int kStalenessFrames = 24;
  int staleness_frames_for(const CaseConfig& c) const {
    return staleness_frames >= 0 ? staleness_frames : c.update_budget_faces > 0 ? kStalenessFrames : 0;
  }
  std::map<std::string, std::string> backend_options;  // egl_platform, gl_device, vk_device, api_checks
  // Crash isolation (bench/cli/case_isolation.h): the pipe on which this worker process names the case and
  // step it is in (-1: not a worker), and the test-only faults (bench/run/case_progress.h): regexes of case
  // ids, fired in the check frame or, with inject_in_timed, in the timed rounds.
  int progress_fd = -1;
  std::string inject_crash, inject_hang;
  bool inject_in_timed = false;
  // A worker that runs a crashed case again: that case's attempt (its first case; 0: a first attempt), and
  // the attempts at a case the faults strike (0: every one; 1: the first only, a flaky driver).
  int worker_attempt = 0;
  int inject_attempts = 0;
  // Tests about time (--inject-frame-ms): the scripted clock (bench/run/scripted_clock.h) replaces every
  // timed and floor frame's times, so the sizing and warm-up by time and the timings reported are one on any
  // machine. 0: measured.
  double inject_frame_ms = 0.0;
};

}  // namespace omnishadow::bench
