#include "tests/cli_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>

#include "bench/io/file_io.h"

namespace omnishadow::cli_test {
namespace {

// Skips only for the reason `list` gives ("gl: unavailable: ..."); a `list` that fails is a failure of the
// program, never a reason to skip (on the H100 it once exited 134 and every CLI test skipped itself).
// `omnishadow list` brings up both backends (a second or two under the sanitizers): once per process.
const Outcome& backends_listing() {
  static const Outcome listing = run("list");
  return listing;
}

}  // namespace

fs::path scratch(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("omnishadow_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

Outcome run(const std::string& args, const std::string& wrapper) {
  fs::path base = scratch("io");
  fs::create_directories(base);
  std::string cmd = (wrapper.empty() ? "" : wrapper + " ") + std::string(OMNISHADOW_BINARY) + " " + args +
                    " >" + (base / "out").string() + " 2>" + (base / "err").string();
  int status = std::system(cmd.c_str());
  Outcome o{WIFEXITED(status) ? WEXITSTATUS(status) : -1,
            omnishadow::bench::read_file((base / "out").string()),
            omnishadow::bench::read_file((base / "err").string())};
  return o;
}

bool gl_available(std::string& why) {
  const Outcome& o = backends_listing();
  EXPECT_EQ(o.exit_code, 0) << "omnishadow list failed:\n" << o.err;
  if (const size_t at = o.out.find("gl: unavailable"); at != std::string::npos) {
    why = "OpenGL backend unavailable here: " + o.out.substr(at, 200);
    return false;
  }
  return true;
}

bool vulkan_available(std::string& why) {
  const Outcome& o = backends_listing();
  if (const size_t at = o.out.find("vulkan: unavailable"); at != std::string::npos) {
    why = "Vulkan backend unavailable here: " + o.out.substr(at, 200);
    return false;
  }
  return true;
}

std::string available_backends() {
  std::string why;
  return vulkan_available(why) ? "gl,vulkan" : "gl";
}

nlohmann::json results_of(const fs::path& run_folder) {
  return nlohmann::json::parse(omnishadow::bench::read_file((run_folder / "results.json").string()));
}

std::string error_lines(const std::string& err) {
  std::istringstream in(err);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("omnishadow: error: ", 0) == 0) out += line + "\n";
  return out;
}

}  // namespace omnishadow::cli_test
