#pragma once
// Facts about the machine and build that belong in every results file.

#include <map>
#include <string>

namespace omnishadow::bench {

// cpu_model, cpu_count, LP_NUM_THREADS (or "unset: one raster thread per core"), GALLIUM_DRIVER,
// MESA_LOADER_DRIVER_OVERRIDE, kernel, commit, build_type.
std::map<std::string, std::string> system_info();
// The commit the binary was built from (12 digits, "-dirty" when tracked files differed from it, "unknown"
// outside a git checkout): defined by the file cmake/build_commit.cmake writes at every build.
std::string build_commit();
// The commit date (ISO 8601, git %cI) of that commit; empty outside a git checkout.
std::string build_commit_date();

}  // namespace omnishadow::bench
