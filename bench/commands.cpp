#include "bench/commands.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <regex>

#include "backends/vulkan/vk_context.h"
#include "bench/case_runner.h"
#include "bench/file_io.h"
#include "bench/gbench_glue.h"
#include "bench/results_reader.h"
#include "bench/results_writer.h"
#include "bench/summary_table.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

// Set by SIGINT/SIGTERM: the run finishes the case in hand, saves what finished and exits 128 + signal.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void request_stop(int signal_number) { g_stop_signal = signal_number; }

std::string default_out_dir() {
  std::time_t now = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "results/run-%Y%m%d-%H%M%S", std::gmtime(&now));
  return buf;
}

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

int repetitions_of(const std::vector<std::string>& benchmark_args) {
  for (const std::string& a : benchmark_args)
    if (a.rfind("--benchmark_repetitions=", 0) == 0) return std::max(1, std::atoi(a.c_str() + 24));
  return 1;
}

// Refuses to clobber an earlier run; creates the folder and proves it is writable.
void prepare_out_dir(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw std::invalid_argument("--out " + dir + " exists and is not a folder");
  if (fs::exists(fs::path(dir) / "results.json", ec))
    throw std::invalid_argument("--out " + dir + " already holds a run (results.json); choose a new folder");
  fs::create_directories(dir, ec);
  if (ec) throw std::invalid_argument("--out " + dir + ": cannot create folder: " + ec.message());
  try {
    write_file_atomic((fs::path(dir) / ".write_test").string(), "ok");
    fs::remove(fs::path(dir) / ".write_test", ec);
  } catch (const std::exception&) {
    throw std::invalid_argument("--out " + dir + ": folder is not writable");
  }
}

}  // namespace

void print_error(const std::string& message) {
  std::string line = message.substr(0, message.find('\n'));
  std::fprintf(stderr, "omnishadow: error: %s\n", line.c_str());
}

int run_command(const RunCommand& cmd) {
  RunOptions options;
  options.out_dir = cmd.out_dir.empty() ? default_out_dir() : cmd.out_dir;
  options.scenes_dir = cmd.scenes_dir;
  options.warmup_frames = cmd.warmup_frames;
  options.frames = cmd.frames;
  options.check_frame = cmd.check_frame;
  options.face_tolerance = cmd.face_tolerance;
  options.lit_tolerance = cmd.lit_tolerance;
  options.cross_lit_tolerance = cmd.cross_lit_tolerance;
  options.cross_shadow_tolerance = cmd.cross_shadow_tolerance;
  options.cross_max_percent = cmd.cross_max_percent;
  options.write_images = cmd.write_images;
  options.accuracy = cmd.accuracy;
  options.memory_precheck = cmd.memory_precheck;
  options.stability = cmd.stability;
  options.max_error_percent = cmd.max_error_percent;
  options.truth.light_radius = cmd.light_radius;
  options.truth.samples_per_axis = cmd.light_samples_per_axis;
  options.backend_options = cmd.backend_options;
  Harness harness(options);
  RunInfo info;
  info.command_line = cmd.command_line;
  info.options = options;

  // Everything that can be wrong with the request is found before anything runs.
  std::vector<CaseConfig> cases;
  try {
    std::map<std::string, std::pair<int, int>> scene_sizes;
    for (const std::string& name : cmd.matrix.scenes) {
      const scene::Scene& s = harness.scene(name);
      scene_sizes[name] = {s.camera.width, s.camera.height};
    }
    for (const std::string& name : cmd.matrix.backends) {
      Backend& b = harness.backend(name);
      info.devices[name] = b.device();
      for (int size : cmd.matrix.cube_sizes)
        if (size > b.device().max_cube_size)
          throw std::invalid_argument("--cube " + std::to_string(size) + " is above the largest cube map " +
                                      b.device().renderer + " supports (" +
                                      std::to_string(b.device().max_cube_size) + ")");
      int max_2d = std::stoi(b.device().extra.count("max_2d_size") ? b.device().extra.at("max_2d_size") : "16384");
      for (const auto& [w, h] : cmd.matrix.frame_sizes)
        if (w > max_2d || h > max_2d)
          throw std::invalid_argument("--frame " + std::to_string(w) + "x" + std::to_string(h) +
                                      " is above the largest render target " + b.device().renderer + " supports (" +
                                      std::to_string(max_2d) + ")");
    }
    cases = expand(cmd.matrix, scene_sizes);
    cases = shard(cases, cmd.shard_index, cmd.shard_count);
    cases = apply_benchmark_filter(cases, cmd.benchmark_args);
    for (CaseConfig& c : cases) c.injected_work = cmd.injected_work;
    if (cases.empty()) throw std::invalid_argument("the matrix (after --shard and --benchmark_filter) is empty");
    prepare_out_dir(options.out_dir);
  } catch (const std::exception& e) {
    print_error(e.what());
    return 2;
  }

  std::vector<CaseResult> results(cases.size());
  size_t prepared = 0;  // results[0, prepared) hold finished cases; the rest are not written
  const std::string results_path = (fs::path(options.out_dir) / "results.json").string();
  auto save = [&](const nlohmann::json& gbench, bool complete) {
    try {
      std::vector<CaseResult> finished(results.begin(), results.begin() + static_cast<ptrdiff_t>(prepared));
      write_results(results_path, info, finished, gbench, complete);
    } catch (const std::exception& e) {
      print_error(std::string("saving results: ") + e.what());
    }
  };

  g_stop_signal = 0;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  auto stopped = [&] {
    if (!g_stop_signal) return false;
    info.stopped_by = g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM";
    return true;
  };

  // Untimed part: images, checks and work counters, in matrix order.
  auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < cases.size() && !stopped(); ++i) {
    results[i].config = cases[i];
    harness.prepare(results[i]);
    prepared = i + 1;
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::string error;
    if (results[i].accuracy) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " [misclassified %.3f%%, mae %.4f]", results[i].accuracy->misclassified_percent,
                    results[i].accuracy->mae_point);
      error = buf;
    }
    std::fprintf(stderr, "[check %zu/%zu] %s: %s%s%s%s  (elapsed %.0fs, eta %.0fs)\n", i + 1, cases.size(),
                 cases[i].id().c_str(), std::string(to_string(results[i].status)).c_str(), error.c_str(),
                 results[i].reason.empty() ? "" : " - ", results[i].reason.c_str(), elapsed,
                 elapsed / static_cast<double>(i + 1) * static_cast<double>(cases.size() - i - 1));
    save(nullptr, false);
  }

  if (stopped()) {
    results.resize(prepared);
    save(nullptr, false);
    std::fprintf(stderr, "omnishadow: stopped by %s after %zu of %zu cases; %s holds them\n",
                 info.stopped_by.c_str(), prepared, cases.size(), results_path.c_str());
    return 128 + static_cast<int>(g_stop_signal);
  }

  // Timed part, through Google Benchmark.
  const std::string raw_path = (fs::path(options.out_dir) / ".gbench_raw.json").string();
  std::vector<std::string> gb_args = {"omnishadow"};
  gb_args.insert(gb_args.end(), cmd.benchmark_args.begin(), cmd.benchmark_args.end());
  gb_args.push_back("--benchmark_out=" + raw_path);
  gb_args.push_back("--benchmark_out_format=json");
  std::vector<char*> gb_argv;
  for (std::string& a : gb_args) gb_argv.push_back(a.data());
  int gb_argc = static_cast<int>(gb_argv.size());
  benchmark::Initialize(&gb_argc, gb_argv.data());
  if (gb_argc > 1) {
    print_error(std::string("unknown Google Benchmark flag ") + gb_argv[1]);
    return 2;
  }
  auto device_context = [&](const std::string& key, const std::string& value) {
    benchmark::AddCustomContext(key, value);
  };
  for (const auto& [name, d] : info.devices) {
    device_context(name + "_renderer", d.renderer);
    device_context(name + "_version", d.version);
    device_context(name + "_platform", d.platform);
  }
  device_context("omnishadow_commit", OMNISHADOW_COMMIT);
  const char* threads = std::getenv("LP_NUM_THREADS");
  device_context("LP_NUM_THREADS", threads ? threads : "unset");

  run_timed(harness, results, repetitions_of(cmd.benchmark_args), [&] { save(nullptr, false); }, stopped);

  nlohmann::json gbench;
  try {
    gbench = parse_gbench_json(read_file(raw_path));
    fs::remove(raw_path);
  } catch (const std::exception& e) {
    print_error(std::string("reading Google Benchmark's output: ") + e.what());
  }
  const bool interrupted = stopped();
  save(gbench, !interrupted);
  std::string summary = summary_markdown(results);
  try {
    write_file_atomic((fs::path(options.out_dir) / "summary.md").string(), summary);
  } catch (const std::exception& e) {
    print_error(e.what());
  }
  std::cout << "\n" << summary << "\nresults: " << results_path << "\n";
  if (interrupted) {
    std::fprintf(stderr, "omnishadow: stopped by %s; cases not timed are marked interrupted in %s\n",
                 info.stopped_by.c_str(), results_path.c_str());
    return 128 + static_cast<int>(g_stop_signal);
  }

  if (cmd.check)
    for (const CaseResult& r : results)
      if (r.status == Status::failed || r.status == Status::failed_check) return 1;
  return 0;
}

int list_command(const std::string& scenes_dir, const std::map<std::string, std::string>& backend_options) {
  std::cout << "backends:\n";
  RunOptions options;
  options.scenes_dir = scenes_dir;
  options.backend_options = backend_options;
  Harness harness(options);
  std::vector<std::string> available;
  for (const std::string& name : backend_names()) {
    try {
      const DeviceInfo& d = harness.backend(name).device();
      std::cout << "  " << name << ": " << d.renderer << " | " << d.version << " | " << d.platform
                << " | max cube " << d.max_cube_size << "\n";
      available.push_back(name);
    } catch (const std::exception& e) {
      std::cout << "  " << name << ": unavailable: " << e.what() << "\n";
    }
  }
  try {
    std::cout << "vulkan devices (--vk-device):\n";
    for (const auto& d : vk::VkContext::list_devices())
      std::cout << "  " << d.index << ": " << d.name << " | " << d.type << " | Vulkan " << d.api_version << " | "
                << d.driver << "\n";
  } catch (const std::exception& e) {
    std::cout << "  none: " << e.what() << "\n";
  }
  std::cout << "scenes (" << scenes_dir << "):\n";
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(scenes_dir, ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    try {
      const scene::Scene& s = harness.scene(f.stem().string());
      std::cout << "  " << f.stem().string() << ": " << s.triangle_count() << " triangles, " << s.objects.size()
                << " objects, frame " << s.camera.width << "x" << s.camera.height << "\n";
    } catch (const std::exception& e) {
      std::cout << "  " << f.stem().string() << ": invalid: " << e.what() << "\n";
    }
  }
  std::cout << "techniques: " << valid_values<Technique>() << "\n";
  std::cout << "filters: " << valid_values<Filter>() << "\n";
  std::cout << "storages: " << valid_values<Storage>() << "\n";
  std::cout << "depth formats: " << valid_values<DepthFormat>() << "\n";
  for (const std::string& name : available) {
    std::cout << "unsupported on " << name << ":";
    Backend& b = harness.backend(name);
    int count = 0;
    for (Technique t : all_values<Technique>())
      for (Storage s : all_values<Storage>())
        for (Filter f : all_values<Filter>()) {
          CaseConfig c;
          c.backend = name;
          c.technique = t;
          c.storage = s;
          c.filter = f;
          Support support = b.supports(c);
          if (!support.ok) {
            std::cout << "\n  " << to_string(t) << " + " << to_string(s) << " + " << to_string(f) << ": "
                      << support.reason;
            ++count;
          }
        }
    std::cout << (count ? "\n" : " nothing\n");
  }
  return 0;
}

}  // namespace omnishadow::bench
