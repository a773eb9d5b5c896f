#include "bench/cli/cli_options.h"

// The run options a measurement leaves at their defaults: how a crashing driver is contained and captured,
// and the faults, copies and perturbations that test the harness itself (the isolation, the statistics, the
// checks).

#include <algorithm>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/cli/matrix_options.h"

namespace omnishadow::bench {
namespace {

// A case-id pattern: refused at once when it is no regular expression, not when the first case meets it.
CLI::Validator regex_check(const std::string& option) {
  return CLI::Validator(
      [option](std::string& text) -> std::string {
        try {
          std::regex pattern(text);
        } catch (const std::regex_error& e) {
          return "'" + text + "' is not a regular expression (" + e.what() + ")";
        }
        return "";
      },
      "REGEX");
}

}  // namespace

// A crashing or hanging driver costs one case (bench/cli/case_isolation.h), and the test-only faults that
// show it.
void add_isolation_options(CLI::App& r, RunCommand& run) {
  r.add_option_function<std::string>(
       "--isolation",
       [&run](const std::string& v) {
         if (v != "process" && v != "none")
           throw std::invalid_argument("--isolation: '" + v + "' is not process or none");
         run.isolate = v == "process";
       },
       "process: the matrix runs in a worker process; a case that kills it (a driver's SIGSEGV or abort) or "
       "hangs "
       "is recorded crashed and a fresh worker goes on from the next case. none: one process, the first "
       "crash "
       "ends the run")
      ->default_str("process");
  r.add_option(
       "--case-timeout-s", run.case_timeout_s,
       "a worker that makes no progress (no new case, step or timed repetition) for this long is killed and "
       "its case recorded crashed")
      ->capture_default_str()
      ->check(finite_in(1.0, 86400.0));
  r.add_option(
       "--crash-retries", run.crash_retries,
       "a case whose worker died by a signal runs again in a fresh worker up to N times: one that then "
       "finishes is kept, listed as flaky (`crashed_before` in results.json) and fails nothing; one that "
       "dies "
       "every time is crashed. A hang is not run again")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  r.add_option(
       "--capture", run.capture,
       "after the matrix, run the failed (or crashed, or all) cases again alone under a capture a driver "
       "team can replay: GFXReconstruct on Vulkan, RenderDoc on GL (its check frame)")
      ->check(CLI::IsMember({"failed", "crashed", "all", "none"}))
      ->capture_default_str();
  r.add_option(
       "--capture-tool", run.capture_tool,
       "auto: GFXReconstruct on Vulkan, RenderDoc on GL; renderdoc: RenderDoc on both (its check frame); "
       "gfxreconstruct: Vulkan only")
      ->check(CLI::IsMember({"auto", "gfxreconstruct", "renderdoc"}))
      ->capture_default_str();
  r.add_option(
       "--capture-max-mb", run.capture_max_mb,
       "a capture file that grows past this many MB is cut: its run is stopped, the file removed and the "
       "capture said `cut`")
      ->capture_default_str()
      ->check(finite_in(0.001, 1048576.0));
  r.add_option("--inject-crash", run.harness.inject_crash,
               "tests of the isolation only: SIGSEGV in the cases whose id matches this regex (--inject-in)")
      ->check(regex_check("--inject-crash"));
  r.add_option(
       "--inject-hang", run.harness.inject_hang,
       "tests of the isolation only: the cases whose id matches this regex never finish (--inject-in)")
      ->check(regex_check("--inject-hang"));
  r.add_option_function<std::string>(
       "--inject-in",
       [&run](const std::string& v) {
         if (v != "checks" && v != "timed")
           throw std::invalid_argument("--inject-in: '" + v + "' is not checks or timed");
         run.harness.inject_in_timed = v == "timed";
       },
       "where --inject-crash and --inject-hang strike: the check frame (checks) or a timed repetition "
       "(timed)")
      ->default_str("checks");
  r.add_option(
       "--inject-attempts", run.harness.inject_attempts,
       "tests of the isolation only: --inject-crash and --inject-hang strike a case's first N attempts "
       "(--crash-retries), 0 (default) every one")
      ->capture_default_str()
      ->check(CLI::Range(0, 6));
  // The supervisor's arguments to its workers (not for users: hidden from --help).
  r.add_option("--worker-skip", run.worker_skip)->group("");
  r.add_option("--worker-attempt", run.harness.worker_attempt)->group("");
  r.add_option("--worker-progress-fd", run.worker_progress_fd)->group("");
  r.add_option("--worker-results", run.worker_results)->group("");
}

// Sensitivity experiments and tests of the checks: options a measurement never uses.
void add_experiment_options(CLI::App& r, RunCommand& run) {
  r.add_option_function<std::string>(
       "--inject-fragment-work",
       [&run](const std::string& t) {
         run.matrix.injected_work = parse_list_with(t, "--inject-fragment-work", [](const std::string& item) {
           size_t used = 0;
           int v = -1;
           try {
             v = std::stoi(item, &used);
           } catch (const std::exception&) {
             used = 0;
           }
           if (used != item.size() || v < 0 || v > 1000000)
             throw std::invalid_argument("'" + item + "' is not a whole number from 0 to 1000000");
           return v;
         });
         std::vector<int> sorted = run.matrix.injected_work;
         std::sort(sorted.begin(), sorted.end());
         if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
           throw std::invalid_argument("--inject-fragment-work: a value is given twice");
       },
       "sensitivity experiments only: N extra dependent ALU steps per lighting fragment; a comma list makes "
       "it an "
       "axis (case ids end in /inj<N>)")
      ->default_str("0");
  r.add_option("--replicas", run.matrix.replicas,
               "sensitivity experiments only: measure K copies of every case in the same rounds (ids end in "
               "/rep<k>): "
               "a same-run A/A test of the timing noise")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  r.add_option(
       "--raster-perturb", run.matrix.raster_perturb_steps,
       "tests of the checks only: move every shadow- and map-pass vertex by up to STEPS of the device's "
       "sub-pixel steps in the target it is drawn into (a linear map of clip space; an atlas tile's steps "
       "are its own), as another conformant rasteriser may snap")
      ->capture_default_str()
      ->check(finite_in(0.0, 4.0));
  r.add_flag("--emulate-nv-swizzle", run.matrix.emulate_nv_swizzle,
             "tests only: nv_swizzle without its NV extensions (an ordinary GS applies each face's swizzle): "
             "proves its "
             "vertex stage, viewport mask, culling and reversed depth on any device; ids end in /emulated");
  r.add_flag(
      "--emulate-mesh-shader", run.matrix.emulate_mesh_shader,
      "tests only: mesh_shader without mesh shading (its task stage as a compute shader, its mesh stage "
      "as a vertex shader writing gl_Layer): proves its meshlets, routing, culling and layers on any "
      "device with vs_layer's feature; ids end in /emulated");
  r.add_option(
       "--lookup-perturb", run.matrix.lookup_perturb_texels,
       "tests of the checks only: move every cube lookup of the lighting pass by TEXELS along each of the "
       "face's two axes, as a sampler with coarser sub-texel precision may (the lookup check's bound)")
      ->capture_default_str()
      ->check(finite_in(0.0, 4.0));
}

}  // namespace omnishadow::bench
