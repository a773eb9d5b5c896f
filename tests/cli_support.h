#pragma once
// The CLI tests' shared means: the omnishadow binary run with arguments (its exit code, stdout and stderr), a
// scratch folder per test, whether each backend is up here, and the fixture that skips (naming why) where GL
// is not.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace omnishadow::cli_test {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code;
  std::string out;
  std::string err;
};

// A fresh folder under this process's scratch root (removed first).
fs::path scratch(const std::string& name);
// OMNISHADOW_BINARY with `args` through the shell, after `wrapper` where given (a command that runs it, as
// `timeout ...`); its outputs read back whole.
Outcome run(const std::string& args, const std::string& wrapper = "");
// Whether `omnishadow list` brought the backend up; `why` is list's reason where it did not (a list that
// fails is a test failure, never a reason to skip).
bool gl_available(std::string& why);
bool vulkan_available(std::string& why);
// "gl,vulkan" where Vulkan came up here, else "gl" (CliRun has made sure of GL): both APIs wherever they run.
std::string available_backends();
// A run folder's results.json, parsed.
nlohmann::json results_of(const fs::path& run_folder);
// Everything on stderr but the progress lines: what a user reads when the run refuses to start.
std::string error_lines(const std::string& err);

class CliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!gl_available(why)) GTEST_SKIP() << why;
  }
};

}  // namespace omnishadow::cli_test
