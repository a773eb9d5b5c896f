#pragma once
// Runs the untimed part of every case: configure, render the check frame, read back, count work, write
// images and compare against the six_pass rendering of the same case. Timing is gbench_glue's job.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "bench/image_compare.h"
#include "bench/timing_stats.h"

namespace omnishadow::bench {

struct RunOptions {
  std::string out_dir;                // results/<run>; images go under out_dir/images/<case id>/
  std::string scenes_dir;             // where `--scene room` finds room.json
  int warmup_frames = 2;              // rendered before timing, excluded from every figure
  int frames = 10;                    // timed frames per repetition (Google Benchmark iterations)
  int check_frame = 0;                // the frame whose images are written and compared
  double face_tolerance = 0.0;        // world units; single-pass faces are expected bit-identical to six_pass
  double lit_tolerance = 0.0;         // 8-bit levels per channel
  bool write_images = true;
  std::map<std::string, std::string> backend_options;  // egl_platform, gl_device
};

struct CheckResult {
  std::string name;     // cube_faces, shadow_factor, lit
  std::string against;  // id of the case compared with
  Difference difference;
  double tolerance = 0.0;
  bool passed = true;
  std::string diff_image;  // relative to out_dir, written on failure only
};

enum class Status { ok, unsupported, failed, failed_check };
std::string_view to_string(Status s);

struct CaseResult {
  CaseConfig config;
  Status status = Status::ok;
  std::string reason;  // one line; empty when ok
  FrameCounters counters;
  std::vector<CheckResult> checks;
  std::map<std::string, std::string> images;  // role -> path relative to out_dir
  std::vector<FrameTiming> warmup;            // every warm-up frame of every repetition
  std::vector<FrameTiming> frames;            // every timed frame of every repetition
  GpuTimerCheck gpu_timer;
  int repetitions = 0;
};

class Harness {
 public:
  explicit Harness(RunOptions options);
  ~Harness();
  const RunOptions& options() const { return options_; }

  // Creates the backend on first use; throws std::runtime_error when the API cannot be brought up.
  Backend& backend(const std::string& name);
  // Uses `backend` for `name` instead of the registry's (tests substitute scripted backends).
  void add_backend(const std::string& name, std::unique_ptr<Backend> backend);
  // Loads (and caches) a scene by name or path; throws scene::SceneError.
  const scene::Scene& scene(const std::string& name_or_path);
  // Makes `config` the backend's current case (loading its scene first if needed).
  Backend& activate(const CaseConfig& config);
  // The untimed part of a case. Never throws: failures become the result's status and reason.
  void prepare(CaseResult& result);

 private:
  void check_against_six_pass(CaseResult& result, const Images& images);
  void write_images(CaseResult& result, const Images& images);
  std::string scene_path(const std::string& name_or_path) const;

  RunOptions options_;
  std::map<std::string, std::unique_ptr<Backend>> backends_;
  std::map<std::string, std::string> loaded_scene_;  // backend -> scene name it holds
  std::map<std::string, scene::Scene> scenes_;
  // The six_pass images of the latest case group (same case but technique), kept for the checks.
  std::string reference_key_;
  std::optional<Images> reference_;
};

}  // namespace omnishadow::bench
