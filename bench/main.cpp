// omnishadow: benchmark and profiling harness for omnidirectional (cube-map) shadow mapping.
// `omnishadow list` shows what this machine can run; `omnishadow run ...` runs a matrix. See README.md.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/commands.h"
#include "bench/compare.h"
#include "bench/merge.h"

using namespace omnishadow;
using namespace omnishadow::bench;

int main(int argc, char** argv) {
  // Google Benchmark's flags go to Google Benchmark; everything else is ours.
  std::vector<std::string> ours, benchmark_args;
  std::string command_line = argv[0];
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    command_line += " " + a;
    (a.rfind("--benchmark_", 0) == 0 ? benchmark_args : ours).push_back(a);
  }

  CLI::App app{"omnishadow: benchmark harness for point-light (cube-map) shadow mapping"};
  app.require_subcommand(1);
  std::string scenes_dir = OMNISHADOW_SCENES_DIR;
  std::string egl_platform = "surfaceless", gl_device = "0", vk_device;
  bool api_checks = false;
  auto add_common = [&](CLI::App* sub) {
    sub->add_option("--scenes-dir", scenes_dir, "folder holding <scene>.json files")->capture_default_str();
    sub->add_option("--egl-platform", egl_platform, "surfaceless (Mesa) or device (EGL_EXT_platform_device)")
        ->capture_default_str();
    sub->add_option("--gl-device", gl_device, "EGL device index with --egl-platform device")->capture_default_str();
    sub->add_option("--vk-device", vk_device, "Vulkan device: index or part of its name (default: device 0)");
    sub->add_flag("--api-checks", api_checks,
                  "checking mode: GL debug context / Vulkan validation layer; any API error or validation "
                  "message fails its case (slower: not for timing)");
  };

  CLI::App* list = app.add_subcommand("list", "backends, scenes, techniques, filters and what this machine supports");
  add_common(list);

  RunCommand run;
  std::string backends = "gl", scenes = "room,heavy", cubes = "512,1024", frames_sizes, techniques, filters,
              storages = "linear_depth", depth_formats = "d32f", optimize = "none", remedy = "none", pcf_scales = "1", shard_text;
  techniques = "six_pass,geometry_shader,geometry_shader_instanced,vs_layer,multiview";
  filters = "hard,pcf_grid64,pcf_disk20";
  CLI::App* r = app.add_subcommand("run", "run a benchmark matrix (Google Benchmark --benchmark_* flags apply)");
  add_common(r);
  r->add_option("--backend", backends, "comma list of backends: gl, vulkan")->capture_default_str();
  r->add_option("--scene", scenes, "comma list of scene names (scenes/<name>.json) or .json paths")
      ->capture_default_str();
  r->add_option("--cube", cubes, "comma list of cube face sizes in texels")->capture_default_str();
  r->add_option("--frame", frames_sizes, "comma list of WIDTHxHEIGHT (default: each scene's camera size)");
  r->add_option("--technique", techniques, "comma list: " + valid_values<Technique>())->capture_default_str();
  r->add_option("--filter", filters, "comma list: " + valid_values<Filter>())->capture_default_str();
  r->add_option("--storage", storages, "comma list: " + valid_values<Storage>())->capture_default_str();
  r->add_option("--depth-format", depth_formats, "comma list: " + valid_values<DepthFormat>())
      ->capture_default_str();
  r->add_option("--optimize", optimize,
                "comma list of optimisation sets, each none or a '+' join of cull (per-face culling, empty faces "
                "cleared only), fit (far plane fitted to the scene), cache (static cube not re-rendered): "
                "--optimize none,cull measures culling on and off")
      ->capture_default_str();
  r->add_option("--remedy", remedy,
                "comma list of numerical remedies, each none or a '+' join of rebase (scene loaded relative to its "
                "light in double precision), bias0, slope_bias (seed 003's max(0.05 (1 - n.l), 0.005)), "
                "normal_offset (lookup 1.5 texels along the normal), two_sided (casters without back-face culling)")
      ->capture_default_str();
  r->add_option("--pcf-scale", pcf_scales,
                "comma list of PCF radius scales (0 to 100; 1 = the seeds' kernels, 0 = one direction)")
      ->capture_default_str();
  r->add_option("--out", run.harness.out_dir, "output folder (must not hold a run already); default results/run-<time>");
  r->add_option("--frames", run.harness.frames, "timed frames per repetition")->capture_default_str()->check(
      CLI::Range(1, 1000000));
  r->add_option("--warmup", run.harness.warmup_frames, "untimed warm-up frames per repetition")->capture_default_str()->check(
      CLI::Range(0, 1000000));
  r->add_option("--check-frame", run.harness.check_frame, "frame index whose images are written and compared")
      ->capture_default_str()->check(CLI::Range(0, 100000000));
  r->add_option("--face-tolerance", run.harness.face_tolerance, "allowed |difference| of cube texels, world units")
      ->capture_default_str()->check(CLI::Range(0.0, 1e30));
  r->add_option("--lit-tolerance", run.harness.lit_tolerance, "allowed |difference| of lit pixels, 8-bit levels")
      ->capture_default_str()->check(CLI::Range(0.0, 255.0));
  r->add_option("--cross-lit-tolerance", run.harness.cross_lit_tolerance,
                "across backends: allowed |difference| of lit pixels, 8-bit levels")
      ->capture_default_str()->check(CLI::Range(0.0, 255.0));
  r->add_option("--cross-shadow-tolerance", run.harness.cross_shadow_tolerance,
                "across backends: allowed |difference| of shadow factors")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  r->add_option("--cross-max-percent", run.harness.cross_max_percent,
                "across backends: % of values allowed beyond those tolerances")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  r->add_option("--inject-fragment-work", run.injected_work,
                "sensitivity experiments only: N extra dependent ALU steps per lighting fragment (default 0)")
      ->capture_default_str()->check(CLI::Range(0, 1000000));
  bool no_accuracy = false;
  r->add_flag("--no-accuracy", no_accuracy, "skip the shadow error against the ray-cast reference");
  r->add_option("--light-radius", run.harness.truth.light_radius,
                "radius of the spherical light of the soft reference, world units (0: point light only)")
      ->capture_default_str()->check(CLI::Range(0.0f, 1e6f));
  r->add_option("--light-samples", run.harness.truth.samples_per_axis,
                "stratified samples per axis on that light (8 = 64 rays per pixel)")
      ->capture_default_str()->check(CLI::Range(1, 64));
  r->add_option("--max-error", run.harness.max_error_percent,
                "fail a case (failed_check, error in the reason) whose shadow disagrees with exact visibility on "
                "more than this % of pixels")
      ->check(CLI::Range(0.0, 100.0));
  r->add_flag("--stability", run.harness.stability,
              "also render the check frame + 1 and report how much of the shadow factor changed (flicker)");
  bool no_memory_precheck = false;
  r->add_flag("--no-memory-precheck", no_memory_precheck,
              "allocate even when a case is predicted not to fit (tests the driver's own out-of-memory path)");
  bool no_images = false;
  std::string images = "failed";
  r->add_option("--images", images,
                "image files: failed (every case's PNGs; float buffers and diffs of cases that failed a check), "
                "all (every file for every case), none")
      ->capture_default_str()->check(CLI::IsMember({"failed", "all", "none"}));
  r->add_flag("--no-images", no_images, "the same as --images none");
  r->add_flag("--check", run.check, "exit 1 if any case failed or failed a check");
  r->add_option("--shard", shard_text, "i/N: run the i-th of N deterministic slices of the matrix");

  CompareOptions compare;
  std::string base_run, new_run;
  CLI::App* cmp = app.add_subcommand("compare", "compare two runs: timing (U-test), work counters, images");
  cmp->add_option("base", base_run, "baseline run folder or results.json")->required();
  cmp->add_option("new", new_run, "new run folder or results.json")->required();
  cmp->add_option("--alpha", compare.alpha, "family-wise significance level (Holm-corrected)")
      ->capture_default_str()->check(CLI::Range(1e-9, 0.5));
  cmp->add_option("--min-effect", compare.min_effect, "smallest relative time change reported (0.05 = 5%)")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  cmp->add_option("--metric", compare.metric,
                  "time to test: wall (frame wall time) or cpu (process CPU time per frame, all threads: the work "
                  "itself on CPU drivers, less disturbed by other load)")
      ->capture_default_str()->check(CLI::IsMember({"wall", "cpu"}));
  cmp->add_option("--out", compare.out_dir, "folder for summary.md and diffs/ (default NEW/compare)");
  bool no_timing = false;
  cmp->add_flag("--no-timing", no_timing, "compare work counters and images only");
  bool timing_report_only = false;
  cmp->add_flag("--timing-report-only", timing_report_only,
                "report timing verdicts but fail (exit 1) on work and image changes only");
  cmp->add_flag("--allow-device-mismatch", compare.allow_device_mismatch,
                "compare runs from different devices anyway");

  std::string merge_out;
  std::vector<std::string> merge_inputs;
  CLI::App* mrg = app.add_subcommand("merge", "join the results of --shard runs into one run");
  mrg->add_option("out", merge_out, "folder for the merged results.json")->required();
  mrg->add_option("runs", merge_inputs, "run folders or results.json files")->required();

  std::string key_run;
  CLI::App* key = app.add_subcommand("device-key", "print the device key of each backend of a run (baselines/)");
  key->add_option("run", key_run, "run folder or results.json")->required();

  try {
    std::vector<std::string> reversed(ours.rbegin(), ours.rend());  // CLI11 parses a reversed vector
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error(e.what());
    return 2;
  }

  if (cmp->parsed() || mrg->parsed() || key->parsed()) {
    if (!benchmark_args.empty()) {
      print_error(benchmark_args.front() + " applies to 'run' only");
      return 2;
    }
    try {
      if (cmp->parsed()) {
        compare.timing = !no_timing;
        compare.timing_fails = !timing_report_only;
        return compare_command(base_run, new_run, compare);
      }
      if (mrg->parsed()) {
        merge_runs(merge_out, merge_inputs);
        std::cout << "merged " << merge_inputs.size() << " runs into " << merge_out << "/results.json\n";
        return 0;
      }
      for (const auto& [backend, device] : device_keys(load_run(key_run))) std::cout << device << "\n";
      return 0;
    } catch (const std::exception& e) {
      print_error(e.what());
      return 2;
    }
  }

  std::map<std::string, std::string> backend_options = {
      {"egl_platform", egl_platform},
      {"gl_device", gl_device},
      {"vk_device", vk_device},
      {"api_checks", api_checks ? "1" : "0"}};
  if (list->parsed()) {
    if (!benchmark_args.empty()) {
      print_error(benchmark_args.front() + " applies to 'run' only");
      return 2;
    }
    return list_command(scenes_dir, backend_options);
  }

  try {
    run.matrix.backends = split_list(backends);
    run.matrix.scenes = split_list(scenes);
    if (run.matrix.backends.empty()) throw std::invalid_argument("--backend: empty list");
    if (run.matrix.scenes.empty()) throw std::invalid_argument("--scene: empty list");
    run.matrix.cube_sizes = parse_int_list(cubes, "--cube");
    if (!frames_sizes.empty()) run.matrix.frame_sizes = parse_size_list(frames_sizes, "--frame");
    run.matrix.techniques = parse_enum_list<Technique>(techniques, "--technique");
    run.matrix.filters = parse_enum_list<Filter>(filters, "--filter");
    run.matrix.storages = parse_enum_list<Storage>(storages, "--storage");
    run.matrix.depth_formats = parse_enum_list<DepthFormat>(depth_formats, "--depth-format");
    run.matrix.optimizations =
        parse_list_with(optimize, "--optimize", [](const std::string& t) { return parse_optimizations(t); });
    run.matrix.remedies = parse_list_with(remedy, "--remedy", [](const std::string& t) { return parse_remedies(t); });
    run.matrix.pcf_scales = parse_list_with(pcf_scales, "--pcf-scale", [](const std::string& t) {
      size_t used = 0;
      float v = -1.0f;
      try {
        v = std::stof(t, &used);
      } catch (const std::exception&) {
      }
      if (used != t.size() || !(v >= 0.0f && v <= 100.0f))
        throw std::invalid_argument("'" + t + "' is not a scale in [0, 100]");
      return v;
    });
    if (!shard_text.empty()) {
      int consumed = 0;
      if (std::sscanf(shard_text.c_str(), "%d/%d%n", &run.shard_index, &run.shard_count, &consumed) != 2 ||
          consumed != static_cast<int>(shard_text.size()) || run.shard_count < 1 || run.shard_index < 0 ||
          run.shard_index >= run.shard_count)
        throw std::invalid_argument("--shard: expected i/N with 0 <= i < N, got '" + shard_text + "'");
    }
  } catch (const std::invalid_argument& e) {
    print_error(e.what());
    return 2;
  }
  for (const std::string& a : benchmark_args)
    if (a.rfind("--benchmark_out", 0) == 0) {
      print_error(a + ": omnishadow writes results.json itself; choose the folder with --out");
      return 2;
    }
  run.harness.images = no_images || images == "none" ? RunOptions::ImagePolicy::none
                       : images == "all"               ? RunOptions::ImagePolicy::all
                                                       : RunOptions::ImagePolicy::failed;
  run.harness.accuracy = !no_accuracy;
  run.harness.memory_precheck = !no_memory_precheck;
  run.harness.scenes_dir = scenes_dir;
  run.harness.backend_options = backend_options;
  run.benchmark_args = benchmark_args;
  run.command_line = command_line;
  return run_command(run);
}
