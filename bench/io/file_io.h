#pragma once
// Files are written atomically (temp file in the same folder, then rename), so a kill at any moment leaves
// either the old file or the new one, never half a file.

#include <string>
#include <string_view>

namespace omnishadow::bench {

void write_file_atomic(const std::string& path, std::string_view bytes);  // throws std::runtime_error
std::string read_file(const std::string& path);                           // throws std::runtime_error

}  // namespace omnishadow::bench
