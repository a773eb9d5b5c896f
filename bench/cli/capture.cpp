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
#include <sstream>
#include <thread>

#include "bench/cli/commands.h"
#include "bench/io/file_io.h"
#include "bench/truth/findings.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kLayer = "VK_LAYER_LUNARG_gfxreconstruct";

bool selected(const std::string& mode, const std::string& status) {
  if (mode == "all") return true;
  if (mode == "crashed") return status == "crashed";
  if (mode == "failed") return status != "ok" && status != "unsupported" && status != "interrupted";
  return false;
}

}  // namespace

// Where the Vulkan loader finds explicit layers: every folder of VK_LAYER_PATH (colon-separated; it replaces
// the system's folders), else VK_ADD_LAYER_PATH's before the system's.
bool gfxreconstruct_layer_in(const char* layer_path, const char* add_layer_path) {
  std::vector<std::string> dirs;
  auto split = [&dirs](const char* list) {
    std::istringstream folders(list ? list : "");
    for (std::string folder; std::getline(folders, folder, ':');)
      if (!folder.empty()) dirs.push_back(folder);
  };
  if (layer_path && *layer_path) {
    split(layer_path);
  } else {
    split(add_layer_path);
    dirs.insert(dirs.end(), {"/usr/share/vulkan/explicit_layer.d", "/usr/local/share/vulkan/explicit_layer.d",
                             "/etc/vulkan/explicit_layer.d"});
  }
  std::error_code ec;
  for (const std::string& d : dirs)
    if (fs::exists(fs::path(d) / "VkLayer_gfxreconstruct.json", ec)) return true;
  return false;
}

namespace {

bool layer_installed() {
  return gfxreconstruct_layer_in(std::getenv("VK_LAYER_PATH"), std::getenv("VK_ADD_LAYER_PATH"));
}

// The tool's version as its replayer prints it ("0.9.18-unknown ..."), or "" when it is not installed.
// The line after `marker` in what `command` prints ("" when it is not installed).
std::string version_after(const char* command, const std::string& marker) {
  FILE* p = popen(command, "r");
  if (!p) return "";
  std::string text;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) text += buf;
  pclose(p);
  const size_t at = text.find(marker);
  if (at == std::string::npos) return "";
  const size_t from = at + marker.size();
  return text.substr(from, text.find('\n', from) - from);
}
std::string gfxreconstruct_version() {
  return version_after("gfxrecon-replay --version 2>/dev/null", "GFXReconstruct Version ");
}
std::string renderdoc_version() {
  const std::string line = version_after("renderdoccmd version 2>/dev/null", "renderdoccmd x64 v");
  return line.substr(0, line.find(' '));  // "1.24 built from ..."
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

// How a case is captured: the program that runs the capture run (the harness itself, or a launcher in front
// of it), the environment it adds, and where the capture lands.
struct CaptureLaunch {
  std::vector<std::string> argv;  // argv[0] run as is when it holds a '/', else found on PATH
  std::vector<std::pair<std::string, std::string>> env;
  std::string file;  // the capture the run writes (watched for --capture-max-mb)
};

// Runs the capture; "" when it exited 0 or 1 (a case that fails its checks still renders), else why not.
// `cut`: set when the file grew past max_mb (its run killed if still going).
std::string run_capture(const CaptureLaunch& launch, const std::string& log, double timeout_s, double max_mb,
                        bool& cut) {
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    // The capture run's own output goes to its log, not among the run's lines.
    if (FILE* f = std::fopen(log.c_str(), "w")) {
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
    }
    for (const auto& [name, value] : launch.env) setenv(name.c_str(), value.c_str(), 1);
    std::vector<std::string> all = launch.argv;
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  if (pid < 0) return "cannot start the capture run";
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  cut = false;
  std::error_code ec;
  const double max_bytes = max_mb * 1024.0 * 1024.0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (double(fs::exists(launch.file, ec) ? fs::file_size(launch.file, ec) : 0) > max_bytes) {
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
  if (double(fs::exists(launch.file, ec) ? fs::file_size(launch.file, ec) : 0) > max_bytes) {
    cut = true;
    return "the capture grew past --capture-max-mb " + format_mb(max_mb);
  }
  if (WIFSIGNALED(status)) return "the capture run died by signal " + std::to_string(WTERMSIG(status));
  if (WEXITSTATUS(status) == 127) return "the capture run could not start " + launch.argv[0];
  if (WEXITSTATUS(status) > 1) return "the capture run exited " + std::to_string(WEXITSTATUS(status));
  return "";
}

// The tools' versions, looked up once per run ("" where absent).
struct ToolVersions {
  std::string gfxreconstruct, renderdoc;
};

// Why `renderdoc` (else GFXReconstruct) cannot capture a case of this API here, or "".
std::string missing_tool(bool renderdoc, bool gl, const ToolVersions& tools) {
  if (renderdoc && tools.renderdoc.empty())
    return "RenderDoc is not installed (Debian packages renderdoccmd and librenderdoc): it captures the "
           "check "
           "frame through its in-application API" +
           std::string(gl ? " (apitrace's EGL wrapper cannot trace libepoxy's GL loading)" : "");
  if (!renderdoc && gl) return "GFXReconstruct captures Vulkan only (--capture-tool renderdoc captures GL)";
  if (!renderdoc && (tools.gfxreconstruct.empty() || !layer_installed()))
    return "GFXReconstruct is not installed (Debian package gfxreconstruct): no capture layer";
  return "";
}

json capture_one(const CaptureSettings& s, const std::string& id, const ToolVersions& tools) {
  json entry = {{"case", id}};
  const bool gl = id.rfind("gl/", 0) == 0;
  const bool renderdoc = s.tool == "renderdoc" || (s.tool == "auto" && gl);
  if (const std::string why = missing_tool(renderdoc, gl, tools); !why.empty()) {
    entry.update({{"status", "unsupported"}, {"reason", why}});
    return entry;
  }
  const fs::path dir = fs::path(s.out_dir) / "captures";
  const fs::path file = dir / (slug(id) + (renderdoc ? ".rdc" : ".gfxr"));
  const fs::path run_dir = dir / (slug(id) + ".run");
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string log = (dir / (slug(id) + ".log")).string();
  const std::string self = fs::read_symlink("/proc/self/exe", ec).string();
  CaptureLaunch launch;
  if (renderdoc) {  // RenderDoc names an in-application capture <template>_capture.rdc
    // RenderDoc starts the program in the executable's folder unless told: the run's own working folder keeps
    // every relative path of its arguments (--out, --scene files) meaning what it meant.
    launch.argv = {"renderdoccmd",
                   "capture",
                   "-w",
                   "-d",
                   fs::current_path(ec).string(),
                   "-c",
                   fs::absolute(dir / slug(id), ec).string(),
                   self};
    launch.file = (dir / (slug(id) + "_capture.rdc")).string();
  } else {
    launch.argv = {self};
    launch.env = {{"VK_INSTANCE_LAYERS", kLayer},
                  {"GFXRECON_CAPTURE_FILE", file.string()},
                  {"GFXRECON_CAPTURE_FILE_TIMESTAMP", "false"},
                  {"GFXRECON_LOG_LEVEL", "warning"}};
    launch.file = file.string();
  }
  for (const std::string& a : capture_run_args(s.args, id, run_dir.string())) launch.argv.push_back(a);
  bool cut = false;
  const std::string why = run_capture(launch, log, s.timeout_s, s.max_mb, cut);
  if (launch.file != file.string() && fs::exists(launch.file, ec)) fs::rename(launch.file, file, ec);
  const uintmax_t bytes = fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
  entry.update({{"tool", renderdoc ? "renderdoc" : "gfxreconstruct"},
                {"version", renderdoc ? tools.renderdoc : tools.gfxreconstruct}});
  if (cut) {  // nothing over the bound is kept: an incomplete capture would not replay anyway
    fs::remove(file, ec);
    entry.update({{"status", "cut"},
                  {"reason", why + ": not kept (" + format_mb(double(bytes) / 1048576.0) + " when cut)"}});
    return entry;
  }
  if (!why.empty() || bytes == 0) {
    entry.update({{"status", "failed"},
                  {"reason", (why.empty() ? "the capture tool wrote nothing" : why) +
                                 " (its output: " + fs::relative(log, s.out_dir, ec).string() + ")"}});
    return entry;
  }
  entry.update({{"status", "captured"},
                {"file", fs::relative(file, s.out_dir, ec).string()},
                {"bytes", bytes},
                {"replay", renderdoc ? "EGL_PLATFORM=surfaceless python3 scripts/replay_renderdoc.py " +
                                           file.string() + " --out replayed.png"
                                     : "gfxrecon-replay " + file.string()}});
  return entry;
}

}  // namespace

std::vector<std::string> capture_run_args(const std::vector<std::string>& args, const std::string& id,
                                          const std::string& out_dir) {
  static const std::vector<std::string> with_value = {
      "--out",          "--capture", "--isolation", "--shard", "--case-timeout-s", "--capture-max-mb",
      "--capture-tool", "--backend"};
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
  out.insert(out.end(), {"--backend", id.substr(0, id.find('/')), "--benchmark_filter=" + exact_filter(id),
                         "--benchmark_repetitions=1", "--isolation", "none", "--out", out_dir});
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
  const ToolVersions tools{gfxreconstruct_version(), renderdoc_version()};
  json captures = json::array();
  for (const json& c : doc["omnishadow"]["cases"]) {
    const std::string id = c.value("id", ""), status = c.value("status", "");
    if (!selected(s.mode, status)) continue;
    json entry = capture_one(s, id, tools);
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
