#include "bench/cli/run_folder.h"

#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace omnishadow::bench {

namespace fs = std::filesystem;

namespace {

std::string default_out_dir() {
  std::time_t now = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "results/run-%Y%m%d-%H%M%S", std::gmtime(&now));
  return buf;
}

bool holds_run(const std::string& dir) {
  std::error_code ec;
  return fs::exists(fs::path(dir) / "results.json", ec);
}

}  // namespace

void prepare_out_dir(const std::string& dir) {
  if (holds_run(dir))
    throw std::invalid_argument("--out " + dir + " already holds a run (results.json); choose a new folder");
  create_writable_folder(dir, "--out");
}

RunFolder::RunFolder(const std::string& dir) {
  std::error_code ec;
  if (!dir.empty()) {
    created_ = !fs::exists(dir, ec);
    prepare_out_dir(dir);
    try {
      lock_.emplace((fs::path(dir) / kRunFolderLockFile).string());
    } catch (const std::exception& e) {
      throw std::runtime_error("--out " + dir + ": " + e.what());
    }
    path_ = dir;
    return;
  }
  const std::string base = default_out_dir();
  constexpr int kMostRunsASecond = 99;
  for (int k = 1; k <= kMostRunsASecond; ++k) {
    const std::string candidate = k == 1 ? base : base + "-" + std::to_string(k);
    if (holds_run(candidate)) continue;
    created_ = !fs::exists(candidate, ec);
    create_writable_folder(candidate, "--out");
    try {
      lock_.emplace((fs::path(candidate) / kRunFolderLockFile).string());
    } catch (const LockHeld&) {
      continue;  // a run of the same second is writing there
    }
    path_ = candidate;
    return;
  }
  throw std::runtime_error("--out not given and " + base + " to -" + std::to_string(kMostRunsASecond) +
                           " are all taken: give --out");
}

void RunFolder::release_if_unused() {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(path_, ec))
    if (entry.path().filename() != kRunFolderLockFile) return;
  if (ec) return;
  lock_.reset();
  fs::remove(fs::path(path_) / kRunFolderLockFile, ec);
  if (created_) fs::remove(path_, ec);
}

}  // namespace omnishadow::bench
