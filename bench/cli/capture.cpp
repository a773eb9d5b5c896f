#include "bench/cli/capture.h"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "bench/cli/commands.h"
#include "bench/io/file_io.h"
#include "bench/truth/findings.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kLayer = "VK_LAYER_LUNARG_gfxreconstruct";
constexpr const char* kGlReason =
    "apitrace's EGL wrapper cannot trace libepoxy's GL loading (libepoxy looks up glXGetCurrentContext, "
    "which the wrapper does not export, and aborts); no GL capture tool here";

bool selected(const std::string& mode, const std::string& status) {
  if (mode == "all") return true;
  if (mode == "crashed") return status == "crashed";
  if (mode == "failed") return status != "ok" && status != "unsupported" && status != "interrupted";
  return false;
}

// Where the Vulkan loader finds explicit layers (VK_LAYER_PATH first, then the system's folders).
bool layer_installed() {
  std::vector<std::string> dirs;
  if (const char* p = std::getenv("VK_LAYER_PATH")) dirs.push_back(p);
  dirs.insert(dirs.end(), {"/usr/share/vulkan/explicit_layer.d", "/usr/local/share/vulkan/explicit_layer.d",
                           "/etc/vulkan/explicit_layer.d"});
  std::error_code ec;
  for (const std::string& d : dirs)
    if (fs::exists(fs::path(d) / "VkLayer_gfxreconstruct.json", ec)) return true;
  return false;
}

// The tool's version as its replayer prints it ("0.9.18-unknown ..."), or "" when it is not installed.
std::string gfxreconstruct_version() {
  FILE* p = popen("gfxrecon-replay --version 2>/dev/null", "r");
  if (!p) return "";
  std::string text;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) text += buf;
  pclose(p);
  const size_t at = text.find("GFXReconstruct Version ");
  if (at == std::string::npos) return "";
  return text.substr(at + 23, text.find('\n', at) - at - 23);
}

// An extended regular expression matching exactly `id` (--benchmark_filter reads ERE).
std::string exact_filter(const std::string& id) {
  std::string out = "^";
  for (char c : id) {
    if (std::string(".[]{}()\\*+?^$|").find(c) != std::string::npos) out += '\\';
    out += c;
  }
  return out + "$";
}

std::string slug(const std::string& id) {
  std::string s = id;
  for (char& c : s)
    if (c == '/') c = '_';
  return s;
}

std::string format_mb(double mb) {
  char text[32];
  std::snprintf(text, sizeof text, "%g MB", mb);
  return text;
}

// Runs the capture; "" when it exited 0 or 1 (a case that fails its checks still renders), else why not.
// `cut`: set when the file grew past max_mb and the run was killed for it.
std::string run_capture(const std::vector<std::string>& args, const std::string& file, const std::string& log,
                        double timeout_s, double max_mb, bool& cut) {
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    // The capture run's own output goes to its log, not among the run's lines.
    if (FILE* f = std::fopen(log.c_str(), "w")) {
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
    }
    setenv("VK_INSTANCE_LAYERS", kLayer, 1);
    setenv("GFXRECON_CAPTURE_FILE", file.c_str(), 1);
    setenv("GFXRECON_CAPTURE_FILE_TIMESTAMP", "false", 1);
    setenv("GFXRECON_LOG_LEVEL", "warning", 1);
    std::vector<std::string> all = {"omnishadow"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  if (pid < 0) return "cannot start the capture run";
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  cut = false;
  std::error_code ec;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    const uintmax_t bytes = fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
    if (double(bytes) > max_mb * 1024.0 * 1024.0) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      cut = true;
      return "the capture grew past --capture-max-mb " + format_mb(max_mb) + " and its run was stopped";
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return "the capture run took over " + std::to_string(int(timeout_s)) +
             " s (--case-timeout-s) and was killed";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // Finished between two looks at its size, and over the bound all the same.
  const uintmax_t bytes = fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
  if (double(bytes) > max_mb * 1024.0 * 1024.0) {
    cut = true;
    return "the capture grew past --capture-max-mb " + format_mb(max_mb);
  }
  if (WIFSIGNALED(status)) return "the capture run died by signal " + std::to_string(WTERMSIG(status));
  if (WEXITSTATUS(status) > 1) return "the capture run exited " + std::to_string(WEXITSTATUS(status));
  return "";
}

json capture_one(const CaptureSettings& s, const std::string& id, const std::string& version) {
  json entry = {{"case", id}};
  if (id.rfind("vulkan/", 0) != 0) {
    entry.update({{"status", "unsupported"}, {"reason", kGlReason}});
    return entry;
  }
  if (version.empty() || !layer_installed()) {
    entry.update(
        {{"status", "unsupported"},
         {"reason", "GFXReconstruct is not installed (Debian package gfxreconstruct): no capture layer"}});
    return entry;
  }
  const fs::path dir = fs::path(s.out_dir) / "captures";
  const fs::path file = dir / (slug(id) + ".gfxr");
  const fs::path run_dir = dir / (slug(id) + ".run");
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string log = (dir / (slug(id) + ".log")).string();
  bool cut = false;
  const std::string why = run_capture(capture_run_args(s.args, id, run_dir.string()), file.string(), log,
                                      s.timeout_s, s.max_mb, cut);
  const uintmax_t bytes = fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
  entry.update({{"tool", "gfxreconstruct"}, {"version", version}});
  if (cut) {  // nothing over the bound is kept: an incomplete capture would not replay anyway
    fs::remove(file, ec);
    entry.update({{"status", "cut"},
                  {"reason", why + ": not kept (" + format_mb(double(bytes) / 1048576.0) + " when cut)"}});
    return entry;
  }
  if (!why.empty() || bytes == 0) {
    entry.update({{"status", "failed"},
                  {"reason", (why.empty() ? "the capture layer wrote nothing" : why) +
                                 " (its output: " + fs::relative(log, s.out_dir, ec).string() + ")"}});
    return entry;
  }
  entry.update({{"status", "captured"},
                {"file", fs::relative(file, s.out_dir, ec).string()},
                {"bytes", bytes},
                {"replay", "gfxrecon-replay " + file.string()}});
  return entry;
}

}  // namespace

std::vector<std::string> capture_run_args(const std::vector<std::string>& args, const std::string& id,
                                          const std::string& out_dir) {
  static const std::vector<std::string> with_value = {"--out",   "--capture",        "--isolation",
                                                      "--shard", "--case-timeout-s", "--capture-max-mb"};
  std::vector<std::string> out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    bool drop = a.rfind("--benchmark_filter=", 0) == 0 || a.rfind("--benchmark_repetitions=", 0) == 0;
    for (const std::string& o : with_value) {
      if (a == o) {
        drop = true;
        ++i;  // and its value
      } else if (a.rfind(o + "=", 0) == 0) {
        drop = true;
      }
    }
    if (!drop) out.push_back(a);
  }
  out.insert(out.end(), {"--benchmark_filter=" + exact_filter(id), "--benchmark_repetitions=1", "--isolation",
                         "none", "--out", out_dir});
  return out;
}

void capture_cases(const CaptureSettings& s) {
  if (s.mode == "none") return;
  const std::string results = (fs::path(s.out_dir) / "results.json").string();
  json doc = json::parse(read_file(results), nullptr, false);
  if (doc.is_discarded() || !doc.contains("omnishadow")) {
    print_error("--capture: " + results + " cannot be read: nothing captured");
    return;
  }
  const std::string version = gfxreconstruct_version();
  json captures = json::array();
  for (const json& c : doc["omnishadow"]["cases"]) {
    const std::string id = c.value("id", ""), status = c.value("status", "");
    if (!selected(s.mode, status)) continue;
    json entry = capture_one(s, id, version);
    std::cout << "capture " << id << ": " << entry["status"].get<std::string>()
              << (entry.contains("file") ? " " + entry["file"].get<std::string>()
                                         : ": " + entry.value("reason", std::string()))
              << "\n";
    captures.push_back(entry);
  }
  doc["omnishadow"]["captures"] = captures;
  write_file_atomic(results, doc.dump(1) + "\n");
  write_file_atomic((fs::path(s.out_dir) / "captures.json").string(),
                    json{{"captures", captures}}.dump(1) + "\n");
}

}  // namespace omnishadow::bench
