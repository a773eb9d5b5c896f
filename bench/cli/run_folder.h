#pragma once
// The folder a run writes into (--out), held by the run for its whole life: a second run given the same
// folder is refused at once, not when results.json appears; a run without --out takes the first free
// results/run-<UTC time>[-N]; a run refused before it wrote anything leaves no empty folder behind.
#include <optional>
#include <string>

#include "bench/io/file_io.h"

namespace omnishadow::bench {

// The lock file in a run's folder while it runs (FileLock): it names the pid of the run that holds it.
inline constexpr const char* kRunFolderLockFile = ".omnishadow.lock";

// Refuses a folder that holds a run (results.json) already; creates it and proves it writable. Throws
// std::invalid_argument / std::runtime_error: one line naming --out and the folder.
void prepare_out_dir(const std::string& dir);

class RunFolder {
 public:
  // Claims `dir`; an empty `dir`: results/run-<UTC time>, or -2, -3, ... after it where a run started in
  // the same second (a script's GL and Vulkan halves started together) holds or has filled that name.
  // Throws (one line naming --out) when it cannot be had.
  explicit RunFolder(const std::string& dir);
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;

  const std::string& path() const { return path_; }
  // At the run's end: where nothing but the lock file is in the folder (a bad option or scene found after
  // the claim), the lock file goes, and the folder too where this run made it. A folder with any other file
  // in it is kept whole.
  void release_if_unused();

 private:
  std::string path_;
  std::optional<FileLock> lock_;
  bool created_ = false;
};

}  // namespace omnishadow::bench
