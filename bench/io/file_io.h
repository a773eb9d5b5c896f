#pragma once
// Files are written atomically (temp file in the same folder, then rename), so a kill at any moment leaves
// either the old file or the new one, never half a file.

#include <stdexcept>
#include <string>
#include <string_view>

namespace omnishadow::bench {

void write_file_atomic(const std::string& path, std::string_view bytes);  // throws std::runtime_error
std::string read_file(const std::string& path);                           // throws std::runtime_error
// Creates `dir` (and its parents) and proves it writable; throws std::runtime_error naming `what` (the option
// or argument that gave it: "--out", "merge OUT") and the folder in one line.
void create_writable_folder(const std::string& dir, const std::string& what);
// 64 hex digits of the file's SHA-256 (what `sha256sum` prints), or "" when it cannot be read: the identity
// of an image the results store keeps in place of its pixels.
std::string sha256_hex_of_file(const std::string& path);

// Thrown by FileLock when another process holds the lock (not when the file cannot be opened).
struct LockHeld : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An exclusive advisory lock (flock) on `path`, created if absent, held until the object is destroyed or the
// process ends (a killed run leaves no stale lock); the holder's pid is written into the file. A second
// holder is refused at once: throws LockHeld naming the pid that holds it (std::runtime_error for any other
// failure).
class FileLock {
 public:
  explicit FileLock(const std::string& path);
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  ~FileLock();

 private:
  int fd_ = -1;
};

}  // namespace omnishadow::bench
