#pragma once
// Runs the untimed part of every case: configure, render the check frame, read back, count work, write
// images and compare against the six_pass rendering of the same case. Timing is gbench_glue's job.

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/common/storage_filter_tables.h"
#include "bench/run/async_writer.h"
#include "bench/run/device_state.h"
#include "bench/run/timing_stats.h"
#include "bench/truth/accuracy.h"
#include "bench/truth/cube_truth.h"
#include "bench/truth/image_compare.h"
#include "bench/truth/lookup_check.h"
#include "bench/truth/map_truth.h"
#include "bench/truth/moments_check.h"

namespace omnishadow::bench {

// The default limit on a hard-filter case's misclassified pixels (--max-error not given). Correct cases
// measured here stay well below it (room 0.06-0.3%, heavy 1.3% at cube 512, the directional notes'
// scene 3.4%); a broken lookup (a flipped axis, no bias: 49% acne) is far above it.
inline constexpr double kDefaultHardMaxErrorPercent = 5.0;
// The default limit for the soft filters at the tutorials' kernel size (--pcf-scale 1): their penumbra is
// misclassified at the 0.5 threshold here and there (room 0.2-0.3%, heavy 2.9-5.1% at cube 256), while a
// kernel scaled by 10 (scripts/experiments/mutants.py) misclassifies 25-39% on heavy. A scale chosen with
// --pcf-scale has no default.
inline constexpr double kDefaultSoftMaxErrorPercent = 15.0;
// Which default a filter gets: hard for one depth comparison per lookup (hard, and hw_compare2x2, whose 2x2
// bilinear weighting of four 0/1 comparisons blurs only within one texel), soft for the PCF kernels.
inline bool has_hard_error_limit(Filter f) { return !traits(f).soft; }

struct RunOptions {
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
  int check_frame = 0;          // the frame whose images are written and compared
  double face_tolerance = 0.0;  // world units; single-pass faces are expected bit-identical to six_pass
  double lit_tolerance = 0.0;   // 8-bit levels per channel
  // Across backends (same case on another API) interpolation may differ in the last bits, which moves a PCF
  // sample across a texel edge now and then: a lit channel may differ by `cross_lit_tolerance` levels, a
  // shadow factor by `cross_shadow_tolerance` (0.1 = two of the disk's 20 samples), and up to
  // `cross_max_percent` of the values may exceed those before the check fails.
  double cross_lit_tolerance = 2.0;
  double cross_shadow_tolerance = 0.1;
  double cross_max_percent = 0.1;
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
  // A case whose shadow disagrees with exact visibility on more than this % of pixels is failed_quality, with
  // the measured error in its reason (the stability suite's "where a variant breaks"). Negative (not given):
  // hard-filter cases at kDefaultHardMaxErrorPercent, soft filters at the tutorials' scale at
  // kDefaultSoftMaxErrorPercent.
  double max_error_percent = -1.0;
  TruthOptions truth;                                  // the spherical light of the soft reference
  std::map<std::string, std::string> backend_options;  // egl_platform, gl_device, vk_device, api_checks
  // Crash isolation (bench/cli/case_isolation.h): the pipe on which this worker process names the case and
  // step it is in (-1: not a worker), and the test-only faults (bench/run/case_progress.h): regexes of case
  // ids, fired in the check frame or, with inject_in_timed, in the timed rounds.
  int progress_fd = -1;
  std::string inject_crash, inject_hang;
  bool inject_in_timed = false;
  // Tests of the sizing by time only (--inject-frame-ms): the warm-up by time and the repetitions' sizing
  // count every frame as this many milliseconds instead of its measured wall time, so a test gets exact frame
  // counts on any machine. 0: measured. The timings reported are measured either way.
  double inject_frame_ms = 0.0;
};

struct CheckResult;
// The timed and the check lighting variants are two compilations of one shader; a GPU compiler may contract
// or reorder their float operations. Each colour channel is fp32 until the final 8-bit rounding, and
// reassociating the ~64 operations that lead to it moves it by at most 64 * 2^-24 relative, under 1e-3 of a
// level: a value may then round the other way (1 level) only when it lies within 1e-3 of a rounding boundary,
// 0.2% of values at most for any distribution of colours. So: no value may differ by more than 1 level, and
// at most 0.2% by 1. Another filter, no bias or another light count moves whole regions by many levels and
// fails both (tests/image_test.cpp).
inline constexpr double kTimedLitMaxPercent = 0.2;
CheckResult timed_variant_check(const std::vector<uint8_t>& timed, const std::vector<uint8_t>& check_variant);

struct CheckResult {
  std::string
      name;  // timed_lit; cube_faces, shadow_factor, lit; cross_backend_lit, cross_backend_shadow_factor
  std::string against;  // id of the case compared with
  Difference difference;
  double tolerance = 0.0;    // per value
  double max_percent = 0.0;  // of values beyond the tolerance; 0 = none may differ
  double max_abs = -1.0;     // >= 0: and no value may differ by more than this (timed_lit: 1 level)
  bool passed = true;
  std::string diff_image;  // relative to out_dir, written on failure only
  // "values": compared value by value; "hash": the face hashes were equal, so were the values (cubes).
  std::string method = "values";
};

// A case's result code, the worst of its findings (dEQP's result codes are the model): users filter on these.
//   ok              every check passed
//   failed_quality  the shadow disagrees with exact visibility beyond --max-error (the measured error is a
//   figure) failed_check    a check failed: technique vs six_pass, timed vs check variant, across APIs,
//   non-finite values interrupted     the run was stopped (SIGINT/SIGTERM) before the case was timed
//   resource_error  the case does not fit in memory (predicted, or the allocation failed)
//   failed          an error: the API failed, the checking mode reported an API error, an exception
//   crashed         the process died (a signal: a driver's SIGSEGV or abort) or made no progress for
//                   --case-timeout-s while on this case; written by the supervisor
//                   (bench/cli/case_isolation.h), whose next worker process goes on from the next case
//   unsupported     the device or the technique cannot do the case; the matrix goes on
// Worse is later in that list.
enum class Status {
  ok,
  failed_quality,
  failed_check,
  interrupted,
  resource_error,
  failed,
  crashed,
  unsupported
};
std::string_view to_string(Status s);
// A case with this status makes `run --check` exit 1.
bool fails_run(Status s);

// One thing a check or a step found: what it does to the case, which check, a one-line message, and figures.
struct Finding {
  Status status = Status::failed;
  std::string
      check;  // timed_lit, cube_faces, cross_backend_lit, max_error, non_finite, memory, api, timing, ...
  std::string message;
  std::map<std::string, double> figures;
};

struct CaseResult {
  CaseConfig config;
  Status status = Status::ok;  // the worst finding's (ok without any)
  std::string reason;          // the findings' messages joined by "; " (one line); empty when ok
  std::vector<Finding> findings;
  // Adds a finding: the status becomes the worse of the two, the message joins the reason.
  void add(Finding finding);
  FrameCounters counters;
  std::vector<CheckResult> checks;
  std::map<std::string, std::string> images;  // role -> path relative to out_dir
  std::vector<FrameTiming> warmup;            // every warm-up frame of every repetition
  std::vector<FrameTiming> frames;            // every timed frame of every repetition
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
  std::optional<Accuracy> accuracy;        // against the ray-cast reference, for the check frame
  std::optional<FrameTiming> first_frame;  // the check frame rendered cold, right after configure
  float light_far = 0.0f;                  // far plane of the check frame's cube (fitted with fit_range)
  int empty_faces = 0;  // faces with no caster at the check frame (with face culling: cleared only)
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
  // The device's clocks, temperature, power and throttling before and after each repetition's frames
  // (bench/run/device_state.h), and where they came from.
  std::vector<DeviceState> device_states;
  std::string device_state_source;
  // The case's floor (FrameKind::floor): its shadow render passes with clears only and the frame shaded with
  // a constant; medians of kFloorFrames frames, shared by every case of the same backend, scene, sizes,
  // technique and storage. A pass's time over its floor is what the technique or filter costs beyond what any
  // variant pays.
  std::optional<FrameTiming> floor;
  std::optional<MomentsReport>
      moments;  // a moments storage read back in full: its moments against its depths
  std::optional<CubeTexelReport>
      cube_texels;  // the cube against exact first-hit distances (bench/truth/cube_truth.h)
  std::optional<MapTexelReport>
      map_texels;  // spot/directional maps against exact depths (bench/truth/map_truth.h)
  // The lighting pass's lookups replayed from the read-back cube (bench/truth/lookup_check.h); the reason it
  // was not replayed otherwise (a technique other than six_pass is held to six_pass's shadow factor bit for
  // bit).
  std::optional<LookupReport> lookups;
  std::string lookups_skipped;
  // Milliseconds of the untimed part per step (configure, check_frame, read_back, cube_and_map_truth,
  // accuracy, comparisons, images, ...); a truth or reference shared with earlier cases costs only the case
  // that computed it.
  std::map<std::string, double> untimed_ms;
};

inline constexpr int kFloorFrames = 5;

// The case every other case of its group is checked against (six_pass, no culling or caching), and the
// group's key.
CaseConfig reference_config(const CaseConfig& c);
std::string group_key(const CaseConfig& c);
// The cube's faces side by side in face order, one image (the cube_faces PNG and check).
std::vector<float> concat_faces(const Images& img);  // the full cube's faces, or the check grid's
int face_edge(const Images& img);                    // texels a face edge in concat_faces

// The key of a loaded scene: its name, and whether the rebase remedy moved it (truth caches are per key).
std::string scene_key(const std::string& name, bool rebase_origin, int tessellation = 1);
// The key of the scene a case renders (its name, load options and tessellation).
std::string scene_key(const CaseConfig& c);

class Harness {
 public:
  explicit Harness(RunOptions options);
  ~Harness();
  const RunOptions& options() const { return options_; }

  // Creates the backend on first use; throws std::runtime_error when the API cannot be brought up.
  Backend& backend(const std::string& name);
  // Uses `backend` for `name` instead of the registry's (tests substitute scripted backends).
  void add_backend(const std::string& name, std::unique_ptr<Backend> backend);
  // The state of `name`'s device now (clocks, temperature, power); its probe is chosen when the backend comes
  // up.
  DeviceState sample_device(const std::string& name);
  std::string device_state_source(const std::string& name);
  // Locks `name`'s device clock until the harness is destroyed (run --lock-clocks); "" or why it cannot.
  std::string lock_clocks(const std::string& name);
  // The name cases use for a scene given by name or path: a bundled name is itself; a file (a scene file or a
  // model) is named by its stem, with characters other than letters, digits, '.', '_' and '-' made '_', so
  // that ids read gl/bunny/c512/... Later calls with that name load the file. Throws std::invalid_argument
  // when two different files would share a name.
  std::string add_scene(const std::string& name_or_path);
  // Loads (and caches) a scene by name or path (with --light / --camera applied); throws scene::SceneError.
  const scene::Scene& scene(const std::string& name_or_path, bool rebase_origin = false,
                            int tessellation = 1);
  // The scene a case renders (its remedies decide how it is loaded).
  const scene::Scene& scene_of(const CaseConfig& c) {
    return scene(c.scene, c.remedies.rebase_origin, c.tessellation);
  }
  // Makes `config` the backend's current case (loading its scene first if needed).
  Backend& activate(const CaseConfig& config);
  // The untimed part of a case. Never throws: failures become the result's status and reason.
  void prepare(CaseResult& result);
  // With async_images: waits for every image file submitted so far; returns the failures as (case id,
  // message).
  std::vector<std::pair<std::string, std::string>> drain_writes();

 private:
  bool admit(CaseResult& result, Backend& b);
  void count_work(CaseResult& result, Backend& b, float light_far);
  void check_accuracy(CaseResult& result, const Images& images);
  void measure_floor(CaseResult& result, Backend& b);
  void check_cube(CaseResult& result, const Images& images);
  void check_moment_cube(CaseResult& result,
                         const Images& images);  // moments storages (bench/truth/moments_check.h)
  void check_maps(CaseResult& result, const Images& images);
  void check_lookups_of(CaseResult& result, const Images& images);  // bench/truth/lookup_check.h
  void check_timed_variant(CaseResult& result, const Images& images);
  void check_against_six_pass(CaseResult& result, Images& images);  // may read the cube again in full
  CubeReadBack cube_read_back_for(const CaseConfig& config) const;
  void read_full_cube(const CaseConfig& config, Images& images);
  void count_non_finite(CaseResult& result, const Images& images);
  void measure_flicker(CaseResult& result, Backend& b, const Images& images);
  void check_against_other_backend(CaseResult& result, const Images& images);
  void record_check(CaseResult& result, CheckResult check, const std::vector<float>& a,
                    const std::vector<float>& b, const std::vector<float>& grey, int width, int height,
                    double scale, bool flip);
  void write_images(CaseResult& result, const Images& images);
  void write_later(const CaseResult& result, std::function<void()> write);  // now, or on the writer
  DeviceStateProbe& probe(const std::string& backend_name);
  const reference::RayCaster& caster_of(const CaseConfig& config);
  std::string scene_path(const std::string& name_or_path) const;
  const Truth& truth_for(const CaseConfig& config, const Images& images);

  RunOptions options_;
  std::map<std::string, std::unique_ptr<Backend>> backends_;
  std::vector<std::string> creation_order_;                          // of backends_: destroyed in reverse
  std::map<std::string, std::unique_ptr<DeviceStateProbe>> probes_;  // by backend
  std::map<std::string, std::string> loaded_scene_;                  // backend -> scene name it holds
  std::map<std::string, scene::Scene> scenes_;
  std::map<std::string, std::string> scene_files_;  // add_scene's names -> the files they stand for
  // The six_pass images of the latest case group (same case but technique), kept for the checks.
  std::string reference_key_;
  std::optional<Images> reference_;
  // The first backend's lit frame and shadow factor per case (id without the backend), for the cross-API
  // check.
  struct CrossReference {
    std::string case_id;
    std::vector<uint8_t> lit;
    std::vector<float> shadow_factor;
  };
  std::map<std::string, CrossReference> cross_;
  std::map<std::string, std::unique_ptr<reference::RayCaster>> casters_;  // by scene
  std::unique_ptr<AsyncWriter> writer_;                                   // with async_images
  std::map<std::string, FrameTiming> floors_;
  std::map<std::string, MapTruth> map_truths_;  // by scene, frame, map size and depth range
  std::map<std::string, CubeTruth>
      cube_truths_;  // by scene, light position, near, far and cube size  // by the axes a floor depends on
  std::map<std::string, Truth> truths_;  // by scene, frame and positions fingerprint: shared by all its cases
  // Per scene, frame and image size: the first truth cast (its key in truths_) and the world positions it was
  // cast from, the prior every later truth of that scene takes its same-surface pixels from
  // (bench/truth/accuracy.h).
  std::map<std::string, std::pair<std::string, std::vector<float>>> truth_priors_;
};

}  // namespace omnishadow::bench
