#include "bench/cli/cli_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "bench/cli/matrix_options.h"

namespace omnishadow::bench {
namespace {

// The whole of `text` as a finite number; nullopt for anything else ("", "1x", "nan", "inf", "1e999").
std::optional<double> finite_number(const std::string& text) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

void add_frame_options(CLI::App& r, RunOptions& o) {
  r.add_option("--out", o.out_dir,
               "output folder (must not hold a run already); default results/run-<UTC time>[-N]");
  r.add_option("--frames", o.frames, "timed frames per repetition")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  r.add_option("--warmup", o.warmup_frames, "untimed warm-up frames per repetition")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  r.add_option(
       "--warmup-ms", o.warmup_ms,
       "untimed warm-up time per repetition as well as frames: the warm-up frames repeat until this long "
       "(default: 100 on a GPU, whose clock must ramp after each pause; 0 on a CPU driver)")
      ->check(finite_in(0.0, 600000.0));
  r.add_option(
       "--repetition-ms", o.repetition_ms,
       "a repetition's length in time as well as frames: each case gets as many more timed frames as "
       "this takes (default: 100 on a GPU, whose sub-millisecond frames vary a lot; 0 on a CPU driver)")
      ->check(finite_in(0.0, 600000.0));
  r.add_option("--inject-frame-ms", o.inject_frame_ms,
               "tests about time: every timed frame lasts this many ms (1% more per unit of "
               "--inject-fragment-work) on every clock the harness reads: wall, process CPU, GPU; the sizing "
               "and warm-up by time count it (0: measured)")
      ->check(finite_in(0.0, 600000.0));
  r.add_option(
       "--settle-s", o.settle_s,
       "before a backend's first timed repetition, render until the device clock is steady, at most this "
       "many seconds (0: don't)")
      ->capture_default_str()
      ->check(finite_in(0.0, 600.0));
  r.add_flag(
      "--lock-clocks", o.lock_clocks,
      "lock the GPU's graphics clock for the run (NVIDIA, through NVML, where this process may: usually "
      "root), restored when the run ends or is stopped; anywhere else a one-line refusal (exit 2)");
  r.add_option("--check-frame", o.check_frame, "frame index whose images are written and compared")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000000));
  r.add_option(
       "--staleness-frames", o.staleness_frames,
       "frames 0..N-1 rendered from a fresh start after a case's checks, each with its faces rendered "
       "and stale and its error against that frame's exact visibility (results.json staleness); "
       "default: " +
           std::to_string(RunOptions::kStalenessFrames) +
           " for cases with an --update-budget, none for the others; 0: none")
      ->check(CLI::Range(0, 10000));
  r.add_flag("--stability", o.stability,
             "also render the check frame + 1 and report how much of the shadow factor changed (flicker)");
}

void add_check_options(CLI::App& r, RunOptions& o) {
  r.add_option("--face-tolerance", o.face_tolerance, "allowed |difference| of cube texels, world units")
      ->capture_default_str()
      ->check(finite_in(0.0, 1e30));
  r.add_option("--lit-tolerance", o.lit_tolerance, "allowed |difference| of lit pixels, 8-bit levels")
      ->capture_default_str()
      ->check(finite_in(0.0, 255.0));
  r.add_option("--cross-lit-tolerance", o.cross_lit_tolerance,
               "across backends: allowed |difference| of lit pixels, 8-bit levels")
      ->capture_default_str()
      ->check(finite_in(0.0, 255.0));
  r.add_option("--cross-shadow-tolerance", o.cross_shadow_tolerance,
               "across backends: allowed |difference| of shadow factors")
      ->capture_default_str()
      ->check(finite_in(0.0, 1.0));
  r.add_option("--cross-max-percent", o.cross_max_percent,
               "across backends: % of values allowed beyond those tolerances")
      ->capture_default_str()
      ->check(finite_in(0.0, 100.0));
  r.add_option("--light-radius", o.truth.light_radius,
               "radius of the spherical light of the soft reference, world units (0: point light only)")
      ->capture_default_str()
      ->check(finite_in(0.0f, 1e6f));
  r.add_option("--light-samples", o.truth.samples_per_axis,
               "stratified samples per axis on that light (8 = 64 rays per pixel)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  r.add_option(
       "--sphere-stride", o.truth.sphere_stride,
       "cast the soft reference at every Nth pixel in x and y (0: every pixel up to 800x600 pixels, above "
       "that the stride that brings it under; mae_sphere/psnr_sphere are means over those pixels)")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  r.add_option(
       "--max-error", o.max_error_percent,
       "fail a case (failed_quality, error in the reason) whose shadow disagrees with exact visibility on "
       "more than this % of pixels")
      ->check(finite_in(0.0, 100.0));
}

// Repetitions run in rounds (bench/run/repetition_policy.h); the fixed count stays Google Benchmark's flag
// --benchmark_repetitions=N, read in finish_run_options.
void add_repetition_options(CLI::App& r, RepetitionPolicy& p) {
  r.add_option(
       "--precision", p.precision_percent,
       "repeat each case (in rounds, interleaved with the others) until the 95% confidence interval of its "
       "median per-repetition frame time is within +-P% (at least 6 repetitions; at most "
       "--max-repetitions)")
      ->check(finite_in(0.01, 100.0));
  r.add_option_function<std::string>(
       "--precision-metric", [&p](const std::string& m) { p.metric = m; },
       "what --precision judges: wall (frame wall time), cpu (process CPU time per frame; compare --metric "
       "cpu) "
       "or gpu (timer-query time of the shadow and lighting passes per frame; compare --metric gpu; a "
       "repetition "
       "whose GPU timer failed its check adds no sample)")
      ->check(CLI::IsMember({"wall", "cpu", "gpu"}))
      ->default_str("wall");
  r.add_option("--max-repetitions", p.max_repetitions, "the cap on repetitions per case under --precision")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  r.add_option(
       "--sustain", p.sustain_seconds,
       "loop the matrix in rounds for this many seconds and report each case's worst repetition against "
       "its best (stability %; clocks recorded per repetition)")
      ->check(finite_in(1.0, 7.0 * 24 * 3600));
}

}  // namespace

// CLI::Range lets NaN through (every comparison with it is false) and "inf" is a number to it: a real-valued
// option must be a finite number within its range.
CLI::Validator finite_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::optional<double> v = finite_number(text);
        if (!v) return "'" + text + "' is not a finite number";
        if (*v < lo || *v > hi) {
          std::ostringstream range;
          range << "Value " << text << " not in range " << lo << " to " << hi;
          return range.str();
        }
        return "";
      },
      [&] {
        std::ostringstream d;
        d << "FLOAT in [" << lo << " - " << hi << "]";
        return d.str();
      }());
}

std::map<std::string, std::string> CommonOptions::backend_options() const {
  return {{"egl_platform", egl_platform},
          {"gl_device", gl_device},
          {"gl_profile", gl_profile},
          {"vk_device", vk_device},
          {"api_checks", api_checks ? "1" : "0"}};
}

void add_common_options(CLI::App& sub, CommonOptions& o) {
  sub.add_option("--scenes-dir", o.scenes_dir, "folder holding <scene>.json files")->capture_default_str();
  sub.add_option("--egl-platform", o.egl_platform, "surfaceless (Mesa) or device (EGL_EXT_platform_device)")
      ->capture_default_str()
      ->check(CLI::IsMember({"surfaceless", "device"}));
  sub.add_option("--gl-device", o.gl_device, "EGL device index with --egl-platform device")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            const bool digits =
                !text.empty() && text.size() <= 6 &&
                std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
            return digits ? "" : "expects an EGL device index (0, 1, ...), got '" + text + "'";
          },
          "INDEX"));
  sub.add_option("--gl-profile", o.gl_profile,
                 "GL context profile: auto (core, or compatibility where only that links nv_swizzle's "
                 "passthrough stage: NVIDIA), core, compatibility")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "core", "compatibility"}));
  sub.add_option("--vk-device", o.vk_device, "Vulkan device: index or part of its name (default: device 0)");
  sub.add_flag(
      "--api-checks", o.api_checks,
      "checking mode: GL debug context / Vulkan validation layer; any API error or validation message "
      "fails its case (slower: not for timing)");
}

// "X,Y,Z" or "X,Y,Z,A,B,C": world units, finite, below 1e30 like a scene file's numbers.
// Three or six numbers; nine where `nine` (the camera's sway).
std::vector<double> parse_placement(const std::string& text, const std::string& option, const char* expected,
                                    bool nine = false) {
  std::vector<double> v;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(',', start);
    std::string item = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::optional<double> x = finite_number(item);
    if (!x || std::fabs(*x) > 1e30)
      throw std::invalid_argument(option + ": '" + item + "' is not a finite number below 1e30 (expected " +
                                  expected + ")");
    v.push_back(*x);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  if (v.size() != 3 && v.size() != 6 && (v.size() != 9 || !nine))
    throw std::invalid_argument(option + ": expected " + expected + ", got " + std::to_string(v.size()) +
                                " numbers");
  return v;
}

void add_placement_options(CLI::App& r, RunOptions& o) {
  r.add_option_function<std::string>(
      "--light",
      [&o](const std::string& t) {
        std::vector<double> v = parse_placement(t, "--light", "X,Y,Z or X,Y,Z,AX,AY,AZ");
        scene::LightPlacement l;
        l.base = glm::dvec3(v[0], v[1], v[2]);
        if (v.size() == 6) l.amplitude = glm::vec3(v[3], v[4], v[5]);
        o.light = l;
        o.light_text = t;
      },
      "the point light at X,Y,Z (world units) in every scene of the run, standing still; with AX,AY,AZ it "
      "sways, "
      "position = X,Y,Z + A sin(0.5 t). A model's light planes are fitted to it, a scene file's stay "
      "(docs/guide.md "
      "\"Your own model\")");
  r.add_option_function<std::string>(
      "--camera",
      [&o](const std::string& t) {
        std::vector<double> v =
            parse_placement(t, "--camera", "X,Y,Z or X,Y,Z,TX,TY,TZ or X,Y,Z,TX,TY,TZ,AX,AY,AZ", true);
        scene::CameraPlacement c;
        c.position = glm::dvec3(v[0], v[1], v[2]);
        if (v.size() >= 6) c.target = glm::dvec3(v[3], v[4], v[5]);
        if (v.size() == 9) c.amplitude = glm::vec3(v[6], v[7], v[8]);
        o.camera = c;
        o.camera_text = t;
      },
      "the camera at X,Y,Z looking at TX,TY,TZ (default: the scene's target; a model's centre) in every "
      "scene, standing still; with AX,AY,AZ it sways, position and target + A sin(0.5 t)");
}

void add_run_options(CLI::App& r, RunCommand& run, RunFlags& flags) {
  add_matrix_options(r, run.matrix);
  add_isolation_options(r, run);
  add_placement_options(r, run.harness);
  add_frame_options(r, run.harness);
  add_check_options(r, run.harness);
  add_experiment_options(r, run);
  r.add_flag("--no-accuracy", flags.no_accuracy, "skip the shadow error against the ray-cast reference");
  r.add_flag("--no-timing", flags.no_timing,
             "the untimed part only: every check, the reference, read-backs and images; no case is timed (a "
             "check of a driver, or a sweep of the checks: results.json's cases carry no timing)");
  r.add_option(
       "--memory-budget", run.harness.memory_budget,
       "plan as if the device had BYTES (1G, 512M, ...; on CPU drivers: host memory): a case that would not "
       "fit fails as resource_error before it allocates")
      ->transform(CLI::AsSizeValue(false));
  r.add_flag("--no-memory-precheck", flags.no_memory_precheck,
             "allocate even when a case is predicted not to fit (tests the driver's own out-of-memory path)");
  r.add_option(
       "--images", flags.images,
       "image files: failed (every case's PNGs; float buffers and diffs of cases that failed a check), "
       "all (every file for every case), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"failed", "all", "none"}));
  r.add_flag("--no-images", flags.no_images, "the same as --images none");
  r.add_option(
       "--cube-read-back", flags.cube_read_back,
       "how much of each cube comes back to the host for the checks: auto (in full up to 1024 a face edge "
       "or with --images all; above, the GPU's face hashes and check grid, in full only where hashes differ "
       "from six_pass's), full, sampled")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "full", "sampled"}));
  r.add_flag("--check", run.check, "exit 1 if any case failed or failed a check");
  r.add_option(
      "--shard", flags.shard,
      "i/N: run the i-th of N deterministic slices of the matrix (0-based); auto: from the CI engine's "
      "variables (GitLab parallel, Slurm arrays, Kubernetes indexed jobs, OMNISHADOW_SHARD_INDEX/COUNT)");
  add_repetition_options(r, run.repetitions);
}

void finish_run_options(RunCommand& run, const RunFlags& flags, const CommonOptions& common) {
  if (flags.shard == "auto") {
    ShardFromEnvironment s = shard_from_environment([](const char* name) { return std::getenv(name); });
    run.shard_index = s.index;
    run.shard_count = s.count;
    std::fprintf(stderr, "omnishadow: --shard auto: %s\n", s.source.c_str());
  } else if (!flags.shard.empty()) {
    int consumed = 0;
    if (std::sscanf(flags.shard.c_str(), "%d/%d%n", &run.shard_index, &run.shard_count, &consumed) != 2 ||
        consumed != static_cast<int>(flags.shard.size()) || run.shard_count < 1 || run.shard_index < 0 ||
        run.shard_index >= run.shard_count)
      throw std::invalid_argument("--shard: expected i/N with 0 <= i < N, got '" + flags.shard + "'");
  }
  for (const std::string& a : run.benchmark_args) {
    if (a.rfind("--benchmark_out", 0) == 0)
      throw std::invalid_argument(a +
                                  ": omnishadow writes results.json itself; choose the folder with --out");
    if (a.rfind("--benchmark_repetitions=", 0) == 0) {
      const std::string value = a.substr(24);
      size_t used = 0;
      int n = 0;
      try {
        n = std::stoi(value, &used);
      } catch (const std::exception&) {
      }
      if (used != value.size() || n < 1 || n > 100000)
        throw std::invalid_argument("--benchmark_repetitions: expected a count from 1 to 100000, got '" +
                                    value + "'");
      run.repetitions.repetitions = n;
    }
  }
  if (run.repetitions.precision_percent > 0.0 && run.repetitions.sustain_seconds > 0.0)
    throw std::invalid_argument(
        "--precision and --sustain: choose one (sustain loops for a time, precision until "
        "the interval is narrow enough)");
  run.repetitions.timed = !flags.no_timing;
  if (flags.no_timing && (run.repetitions.precision_percent > 0.0 || run.repetitions.sustain_seconds > 0.0))
    throw std::invalid_argument(
        std::string(run.repetitions.precision_percent > 0.0 ? "--precision" : "--sustain") +
        " and --no-timing: the one times repetitions, the other times none");
  using Policy = RunOptions::ImagePolicy;
  run.harness.images = flags.no_images || flags.images == "none" ? Policy::none
                       : flags.images == "all"                   ? Policy::all
                                                                 : Policy::failed;
  using ReadBack = RunOptions::CubeReadBackPolicy;
  run.harness.cube_read_back = flags.cube_read_back == "full"      ? ReadBack::full
                               : flags.cube_read_back == "sampled" ? ReadBack::sampled
                                                                   : ReadBack::automatic;
  run.harness.accuracy = !flags.no_accuracy;
  run.harness.memory_precheck = !flags.no_memory_precheck;
  run.harness.scenes_dir = common.scenes_dir;
  run.harness.backend_options = common.backend_options();
}

void add_compare_options(CLI::App& cmp, CompareOptions& compare, CompareFlags& flags) {
  cmp.add_option("base", flags.base_run, "baseline run folder or results.json")->required();
  cmp.add_option("new", flags.new_run, "new run folder or results.json")->required();
  cmp.add_option("--alpha", compare.alpha, "family-wise significance level (Holm-corrected)")
      ->capture_default_str()
      ->check(finite_in(1e-9, 0.5));
  cmp.add_option("--min-effect", compare.min_effect, "smallest relative time change reported (0.05 = 5%)")
      ->capture_default_str()
      ->check(finite_in(0.0, 10.0));
  cmp.add_option(
         "--metric", compare.metric,
         "time to test: wall (frame wall time), cpu (process CPU time per frame, all threads: the work "
         "itself on CPU drivers, less disturbed by other load) or gpu (shadow + lighting pass GPU time per "
         "frame from timer queries, repetitions whose timer passed its sanity check: what a GPU spends, "
         "without the CPU's submission noise)")
      ->capture_default_str()
      ->check(CLI::IsMember({"wall", "cpu", "gpu"}));
  cmp.add_option(
      "--gate", flags.gate,
      "take --metric, --alpha and --min-effect from this gate file (results/baselines/<key>/gate.json, "
      "written by scripts/experiments/sensitivity.py --write-gate); overrides those options");
  cmp.add_option("--out", compare.out_dir, "folder for summary.md and diffs/ (default NEW/compare)");
  cmp.add_flag("--no-timing", flags.no_timing, "compare work counters and images only");
  cmp.add_flag("--timing-report-only", flags.timing_report_only,
               "report timing verdicts but fail (exit 1) on work and image changes only");
  cmp.add_flag("--allow-device-mismatch", compare.allow_device_mismatch,
               "compare runs from different devices anyway");
}

std::string parse_error_message(const CLI::App& app, const CLI::ParseError& e,
                                const std::vector<std::string>& args) {
  const std::string what = e.what();
  if (what == "A subcommand is required") {
    std::string commands;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      commands += (commands.empty() ? "" : ", ") + sub->get_name();
    const auto word =
        std::find_if(args.begin(), args.end(), [](const std::string& a) { return a.rfind('-', 0) != 0; });
    if (word != args.end())
      return "unknown command '" + *word + "' (commands: " + commands + "; omnishadow --help)";
    return "no command given (commands: " + commands + "; omnishadow --help)";
  }
  // "--cube: At Most 1 required but received 2"
  const size_t at = what.find(": At Most 1 required but received ");
  if (at != std::string::npos)
    return what.substr(0, at) + " is given " + what.substr(at + 34) +
           " times: give it once (a list option takes one comma-separated list, as --cube 256,512)";
  return what;
}

}  // namespace omnishadow::bench
