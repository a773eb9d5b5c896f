#include "bench/cli/commands.h"

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <regex>
#include <set>

#include "backends/vulkan/vk_context.h"
#include "bench/cli/capture.h"
#include "bench/cli/case_isolation.h"
#include "bench/cli/run_folder.h"
#include "bench/io/file_io.h"
#include "bench/io/results_reader.h"
#include "bench/report/results_writer.h"
#include "bench/report/summary_table.h"
#include "bench/run/case_progress.h"
#include "bench/run/case_runner.h"
#include "bench/run/gbench_glue.h"
#include "bench/run/memory_budget.h"
#include "bench/run/system_info.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

// Set by SIGINT/SIGTERM: the run finishes the case in hand, saves what finished and exits 128 + signal.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void request_stop(int signal_number) { g_stop_signal = signal_number; }

// --benchmark_filter semantics of Google Benchmark 1.7: an extended regex searched in the name, negated by
// a leading '-'. Applied to the untimed part too, so that both parts run the same cases.
std::vector<CaseConfig> apply_benchmark_filter(const std::vector<CaseConfig>& cases,
                                               const std::vector<std::string>& benchmark_args) {
  std::string filter;
  for (const std::string& a : benchmark_args)
    if (a.rfind("--benchmark_filter=", 0) == 0) filter = a.substr(19);
  if (filter.empty() || filter == "all" || filter == ".") return cases;
  bool negate = filter[0] == '-';
  std::regex re;
  try {
    re = std::regex(negate ? filter.substr(1) : filter, std::regex::extended);
  } catch (const std::regex_error& e) {
    throw std::invalid_argument("--benchmark_filter: invalid regular expression '" + filter + "'");
  }
  std::vector<CaseConfig> out;
  for (const CaseConfig& c : cases)
    if (std::regex_search(c.id(), re) != negate) out.push_back(c);
  return out;
}

}  // namespace

void print_error(const std::string& message) {
  std::string line = message.substr(0, message.find('\n'));
  std::fprintf(stderr, "omnishadow: error: %s\n", line.c_str());
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The default matrix asks every backend for every technique; one that a backend cannot do at all (GL and
// multiview here) is left out of that backend's cases, with one line saying so, instead of a line per case.
std::vector<CaseConfig> drop_techniques_a_backend_cannot_do(const std::vector<CaseConfig>& cases,
                                                            Harness& harness) {
  std::map<std::pair<std::string, Technique>, Support> verdicts;
  std::vector<CaseConfig> kept;
  for (const CaseConfig& c : cases) {
    auto key = std::make_pair(c.backend, c.technique);
    if (!verdicts.count(key)) {
      CaseConfig probe;  // the technique alone: default storage, filter and sizes
      probe.backend = c.backend;
      probe.technique = c.technique;
      probe.cube_size = 64;
      Support s = harness.backend(c.backend).supports(probe);
      if (!s.ok)
        std::fprintf(stderr, "omnishadow: %s left out on %s (not asked for by name): %s\n",
                     std::string(to_string(c.technique)).c_str(), c.backend.c_str(), s.reason.c_str());
      verdicts[key] = s;
    }
    if (verdicts[key].ok) kept.push_back(c);
  }
  return kept;
}

// --cube not given: the GPU default, or MatrixSpec::kCpuDriverCubeSizes where every backend of the run
// renders on the CPU (said in one line).
std::vector<int> default_cube_sizes(const MatrixSpec& asked, Harness& harness) {
  auto on_cpu = [&](const std::string& name) { return harness.backend(name).device().shares_host_memory; };
  if (asked.cube_sizes == MatrixSpec::kCpuDriverCubeSizes ||
      !std::all_of(asked.backends.begin(), asked.backends.end(), on_cpu))
    return asked.cube_sizes;
  auto joined = [](const std::vector<int>& sizes) {
    std::string text;
    for (int size : sizes) text += (text.empty() ? "" : ",") + std::to_string(size);
    return text;
  };
  std::string renderers;
  for (const std::string& name : asked.backends)
    renderers += (renderers.empty() ? "" : ", ") + harness.backend(name).device().renderer;
  std::fprintf(stderr,
               "omnishadow: cube %s only: --cube not given and %s renders on the CPU (--cube %s for the GPU "
               "default)\n",
               joined(MatrixSpec::kCpuDriverCubeSizes).c_str(), renderers.c_str(),
               joined(asked.cube_sizes).c_str());
  return MatrixSpec::kCpuDriverCubeSizes;
}

// Everything that can be wrong with the request, found before anything runs: scenes load, backends come up,
// sizes fit the devices, the matrix is not empty. Throws std::invalid_argument (or the loaders' errors).
std::vector<CaseConfig> validate_request(const RunCommand& cmd, Harness& harness, RunInfo& info) {
  std::map<std::string, SceneFacts> scene_facts;
  MatrixSpec matrix = cmd.matrix;
  matrix.scenes.clear();
  for (const std::string& given : cmd.matrix.scenes) {
    const std::string name = harness.add_scene(given);
    if (!scene_facts.count(name)) {
      auto start = std::chrono::steady_clock::now();
      try {
        const scene::Scene& s = harness.scene(name);
        info.phases.scene_loads.push_back({name, s.source, s.triangle_count(), seconds_since(start)});
        scene_facts[name] = {s.camera.width, s.camera.height, int(s.point_lights.size())};
      } catch (const scene::SceneError& e) {
        if (cmd.matrix.scenes_given) throw;
        std::fprintf(stderr, "omnishadow: scene %s left out (not asked for by name): %s\n", name.c_str(),
                     e.what());
        continue;
      }
    }
    matrix.scenes.push_back(name);
  }
  if (matrix.scenes.empty()) throw std::invalid_argument("--scene: no scene of the default matrix loads");
  for (const std::string& name : cmd.matrix.backends) {
    Backend& b = harness.backend(name);
    info.devices[name] = b.device();
    for (int size : cmd.matrix.cube_sizes)
      if (size > b.device().max_cube_size)
        throw std::invalid_argument("--cube " + std::to_string(size) + " is above the largest cube map " +
                                    b.device().renderer + " supports (" +
                                    std::to_string(b.device().max_cube_size) + ")");
    int max_2d =
        std::stoi(b.device().extra.count("max_2d_size") ? b.device().extra.at("max_2d_size") : "16384");
    for (const auto& [w, h] : cmd.matrix.frame_sizes)
      if (w > max_2d || h > max_2d)
        throw std::invalid_argument("--frame " + std::to_string(w) + "x" + std::to_string(h) +
                                    " is above the largest render target " + b.device().renderer +
                                    " supports (" + std::to_string(max_2d) + ")");
  }
  if (!cmd.matrix.cube_sizes_given) matrix.cube_sizes = default_cube_sizes(cmd.matrix, harness);
  std::vector<CaseConfig> cases = expand(matrix, scene_facts);
  // Values written differently that name one case (`--optimize cull+fit,fit+cull`, a scene by name and by
  // path): refused before anything runs, as repeated values are.
  std::set<std::string> ids;
  for (const CaseConfig& c : cases)
    if (!ids.insert(c.id()).second)
      throw std::invalid_argument("two values of one axis name the same case " + c.id() +
                                  " (as --optimize cull+fit,fit+cull would): give each once");
  if (!cmd.matrix.techniques_given) cases = drop_techniques_a_backend_cannot_do(cases, harness);
  cases = shard(cases, cmd.shard_index, cmd.shard_count);
  cases = apply_benchmark_filter(cases, cmd.benchmark_args);
  if (cases.empty())
    throw std::invalid_argument("the matrix (after --shard and --benchmark_filter) is empty");
  prepare_out_dir(harness.options().out_dir);
  return cases;
}

// One run in progress: its results so far, saved atomically after every step so that nothing measured is
// lost.
struct RunState {
  RunInfo info;
  std::vector<CaseResult> results;
  size_t prepared = 0;  // results[0, prepared) hold finished cases; the rest are not written
  std::string results_path;
  std::vector<std::string> benchmark_argv;  // Google Benchmark's argv: it keeps pointers into it

  void save(const nlohmann::json& gbench, bool complete) {
    try {
      std::vector<CaseResult> finished(results.begin(), results.begin() + static_cast<ptrdiff_t>(prepared));
      write_results(results_path, info, finished, gbench, complete);
    } catch (const std::exception& e) {
      print_error(std::string("saving results: ") + e.what());
    }
  }
  bool stopped() {
    if (!g_stop_signal) return false;
    info.stopped_by = g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM";
    return true;
  }
};

// The untimed part: check frames, read-backs, checks, work counters and images, in matrix order.
void run_untimed(Harness& harness, const std::vector<CaseConfig>& cases, RunState& run) {
  auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < cases.size() && !run.stopped(); ++i) {
    CaseResult& r = run.results[i];
    r.config = cases[i];
    send_progress(harness.options().progress_fd,
                  "case " + cases[i].id() + "\t" + axes_to_json(cases[i]).dump());
    harness.prepare(r);
    run.prepared = i + 1;
    double elapsed = seconds_since(start);
    std::string error;
    if (r.accuracy) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " [misclassified %.3f%%, mae %.4f]", r.accuracy->misclassified_percent,
                    r.accuracy->mae_point);
      error = buf;
    }
    std::fprintf(stderr, "[check %zu/%zu] %s: %s%s%s%s  (elapsed %.0fs, eta %.0fs)\n", i + 1, cases.size(),
                 cases[i].id().c_str(), std::string(to_string(r.status)).c_str(), error.c_str(),
                 r.reason.empty() ? "" : " - ", r.reason.c_str(), elapsed,
                 elapsed / static_cast<double>(i + 1) * static_cast<double>(cases.size() - i - 1));
    run.save(nullptr, false);
  }
  // Every image file is written before anything is timed; a file that could not be written fails its case.
  for (const auto& [id, message] : harness.drain_writes())
    for (CaseResult& r : run.results)
      if (r.config.id() == id) r.add({Status::failed, "images", "writing images: " + message, {}});
  run.info.phases.untimed_seconds = seconds_since(start);
  run.save(nullptr, false);
}

// Google Benchmark takes its own flags; ours are gone by now. Returns false (after the error line) on a flag
// it does not know. It keeps pointers into its argv (the executable's name in the JSON context): `gb_args`
// must outlive the run.
bool init_benchmark(const RunCommand& cmd, const RunInfo& info, std::vector<std::string>& gb_args) {
  gb_args = {"omnishadow"};
  // The repetitions are the policy's (rounds), not Google Benchmark's; its JSON is written from the rounds'
  // runs. The filter is applied to the case ids already (apply_benchmark_filter): Google Benchmark's names
  // add
  // "/iterations:N/manual_time", so a filter anchored at the id's end would match none of them there, and the
  // rounds would register the same cases for ever.
  for (const std::string& a : cmd.benchmark_args)
    if (a.rfind("--benchmark_repetitions=", 0) != 0 && a.rfind("--benchmark_filter=", 0) != 0)
      gb_args.push_back(a);
  std::vector<char*> gb_argv;
  for (std::string& a : gb_args) gb_argv.push_back(a.data());
  int gb_argc = static_cast<int>(gb_argv.size());
  benchmark::Initialize(&gb_argc, gb_argv.data());
  if (gb_argc > 1) {
    print_error(std::string("unknown Google Benchmark flag ") + gb_argv[1]);
    return false;
  }
  for (const auto& [name, d] : info.devices) {
    benchmark::AddCustomContext(name + "_renderer", d.renderer);
    benchmark::AddCustomContext(name + "_version", d.version);
    benchmark::AddCustomContext(name + "_platform", d.platform);
  }
  benchmark::AddCustomContext("omnishadow_commit", build_commit());
  const char* threads = std::getenv("LP_NUM_THREADS");
  benchmark::AddCustomContext("LP_NUM_THREADS", threads ? threads : "unset");
  return true;
}

// summary.md, and the summary on stdout; an incomplete run says so first (`incomplete`: why, "" when whole).
void write_summary(RunState& run, const std::string& incomplete) {
  std::string summary = summary_markdown(run.results, run.info.phases, run.info.repetitions, incomplete);
  try {
    write_file_atomic((fs::path(run.info.options.out_dir) / "summary.md").string(), summary);
  } catch (const std::exception& e) {
    print_error(e.what());
  }
  const std::string out_dir = run.info.options.out_dir;
  std::cout << "\n"
            << summary << "\nresults: " << run.results_path << "\nreport: omnishadow report " << out_dir
            << ", then open " << (fs::path(out_dir) / "report.html").string() << " in a browser\n";
}

// results.json with Google Benchmark's figures, summary.md, and the summary on stdout.
void write_outputs(RunState& run, const std::string& raw_path, bool complete) {
  nlohmann::json gbench;
  try {
    gbench = parse_gbench_json(read_file(raw_path));
    fs::remove(raw_path);
  } catch (const std::exception& e) {
    print_error(std::string("reading Google Benchmark's output: ") + e.what());
  }
  run.save(gbench, complete);
  write_summary(run, complete ? "" : "stopped by " + run.info.stopped_by + " during the timed part");
}

// The cases this process runs (a worker after a crash skips those done), with the clocks locked where asked;
// nullopt, the error printed, when the request cannot run.
std::optional<std::vector<CaseConfig>> cases_to_run(const RunCommand& cmd, Harness& harness, RunState& run) {
  const RunOptions& options = harness.options();
  try {
    std::vector<CaseConfig> cases = validate_request(cmd, harness, run.info);
    // A worker after a crash: the cases before the crashed one, and that one, are done.
    send_progress(options.progress_fd, "cases " + std::to_string(cases.size()));
    if (cmd.worker_skip > 0)
      cases.erase(cases.begin(),
                  cases.begin() + std::min<ptrdiff_t>(cmd.worker_skip, ptrdiff_t(cases.size())));
    if (options.lock_clocks) {
      std::set<std::string> locked;
      for (const CaseConfig& c : cases)
        if (locked.insert(c.backend).second)
          if (std::string why = harness.lock_clocks(c.backend); !why.empty())
            throw std::runtime_error("--lock-clocks: " + c.backend + ": " + why);
    }
    return cases;
  } catch (const std::exception& e) {
    print_error(e.what());
    return std::nullopt;
  }
}

// A finished run's exit code: 1 with --check when a case failed or failed a check.
int run_exit_code(const RunCommand& cmd, const std::vector<CaseResult>& results) {
  if (cmd.check)
    for (const CaseResult& r : results)
      if (fails_run(r.status)) return 1;
  return 0;
}

// The matrix in this process: a run without isolation, or a worker's share of one.
int run_matrix_here(const RunCommand& cmd, RunOptions options) {
  options.progress_fd = cmd.worker_progress_fd;
  if (cmd.worker_skip >= 0) report_fatal_signals();  // a driver's crash names its library in the log
  options.async_images = true;                       // drained at the end of the untimed part
  Harness harness(options);
  RunState run;
  run.info.command_line = cmd.command_line;
  run.info.options = options;
  run.info.repetitions = cmd.repetitions;
  run.info.shard_index = cmd.shard_index;
  run.info.shard_count = cmd.shard_count;
  run.results_path =
      cmd.worker_results.empty() ? (fs::path(options.out_dir) / "results.json").string() : cmd.worker_results;
  std::optional<std::vector<CaseConfig>> planned = cases_to_run(cmd, harness, run);
  if (!planned) return 2;
  std::vector<CaseConfig>& cases = *planned;
  run.results.resize(cases.size());
  g_stop_signal = 0;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);

  run_untimed(harness, cases, run);
  if (run.stopped()) {
    run.results.resize(run.prepared);
    for (CaseResult& r : run.results)  // checked, never timed: not ok, whatever the checks said
      if (is_timed(r.status))
        r.add({Status::interrupted,
               "timing",
               "interrupted: the run was stopped before this case was timed",
               {}});
    run.save(nullptr, false);
    write_summary(run, "stopped by " + run.info.stopped_by + " during the untimed checks, after " +
                           std::to_string(run.prepared) + " of " + std::to_string(cases.size()) +
                           " cases; none was timed");
    std::fprintf(stderr, "omnishadow: stopped by %s after %zu of %zu cases; %s holds them\n",
                 run.info.stopped_by.c_str(), run.prepared, cases.size(), run.results_path.c_str());
    return 128 + static_cast<int>(g_stop_signal);
  }

  if (!run.info.repetitions.timed) {  // --no-timing: the checks' verdicts are the run's
    run.save(nullptr, true);
    write_summary(run, "");
    return run_exit_code(cmd, run.results);
  }
  const std::string raw_path = (fs::path(options.out_dir) / ".gbench_raw.json").string();
  if (!init_benchmark(cmd, run.info, run.benchmark_argv)) return 2;
  auto timed_start = std::chrono::steady_clock::now();
  try {
    run.info.repetitions.compared_cases = compared_cases(run.results);
    run_timed(
        harness, run.results, run.info.repetitions, raw_path, [&] { run.save(nullptr, false); },
        [&] { return run.stopped(); });
  } catch (const std::exception& e) {
    print_error(std::string("writing Google Benchmark's output: ") + e.what());
  }
  run.info.phases.timed_seconds = seconds_since(timed_start);

  const bool interrupted = run.stopped();
  write_outputs(run, raw_path, !interrupted);
  if (interrupted) {
    std::fprintf(stderr, "omnishadow: stopped by %s; cases not timed are marked interrupted in %s\n",
                 run.info.stopped_by.c_str(), run.results_path.c_str());
    return 128 + static_cast<int>(g_stop_signal);
  }
  return run_exit_code(cmd, run.results);
}

}  // namespace

int run_command(const RunCommand& cmd) {
  RunOptions options = cmd.harness;
  // Workers write under their supervisor's claim, into the folder it names.
  std::optional<RunFolder> folder;
  if (cmd.worker_skip < 0) {
    try {
      folder.emplace(options.out_dir);
    } catch (const std::exception& e) {
      print_error(e.what());
      return 2;
    }
    options.out_dir = folder->path();
  }
  int code = 0;
  if (cmd.isolate && cmd.worker_skip < 0) {  // this process supervises; workers run the matrix
    IsolationSettings isolation{cmd.args, options.out_dir, cmd.case_timeout_s, cmd.crash_retries, cmd.check};
    if (cmd.harness.out_dir.empty()) isolation.args.insert(isolation.args.end(), {"--out", options.out_dir});
    try {
      code = supervise_run(isolation);
    } catch (const std::exception& e) {
      print_error(e.what());
      code = 1;
    }
  } else {
    code = run_matrix_here(cmd, options);
  }
  // The whole run's results are written: the selected cases again, each under a capture
  // (bench/cli/capture.h).
  if (cmd.worker_skip < 0 && cmd.capture != "none" && (code == 0 || code == 1))
    capture_cases(
        {cmd.capture, cmd.capture_tool, cmd.args, options.out_dir, cmd.case_timeout_s, cmd.capture_max_mb});
  if (folder) folder->release_if_unused();
  return code;
}

std::string project_path(const std::string& relative) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "omnishadow" / relative;
    if (fs::exists(installed, ec)) return installed.string();
  }
  return (fs::path(OMNISHADOW_SOURCE_DIR) / relative).string();
}

}  // namespace omnishadow::bench
