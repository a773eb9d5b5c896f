#include "bench/run/system_info.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <thread>

namespace omnishadow::bench {
namespace {

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v ? v : fallback;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

}  // namespace

std::map<std::string, std::string> system_info() {
  std::map<std::string, std::string> info;
  info["cpu_model"] = cpu_model();
  info["cpu_count"] = std::to_string(std::thread::hardware_concurrency());
  // llvmpipe/lavapipe raster threads: recorded because they change every software-rendered figure.
  info["LP_NUM_THREADS"] = env_or("LP_NUM_THREADS", "unset (llvmpipe default: one raster thread per core)");
  info["GALLIUM_DRIVER"] = env_or("GALLIUM_DRIVER", "unset");
  info["MESA_LOADER_DRIVER_OVERRIDE"] = env_or("MESA_LOADER_DRIVER_OVERRIDE", "unset");
  utsname u{};
  if (uname(&u) == 0) info["kernel"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
  info["commit"] = build_commit();
#ifdef NDEBUG
  info["build_type"] = "optimized";
#else
  info["build_type"] = "debug (assertions on: do not compare timings with optimized builds)";
#endif
  return info;
}

}  // namespace omnishadow::bench
