#include "bench/run/memory_budget.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "backends/common/atlas.h"
#include "backends/common/layouts.h"
#include "backends/common/light_clusters.h"
#include "backends/common/storage_filter_tables.h"

namespace omnishadow::bench {
namespace {

uint64_t depth_bytes(DepthFormat f) { return f == DepthFormat::d16 ? 2 : 4; }  // D24 is stored as X8_D24

// "MemAvailable:   123 kB" style lines of /proc files; 0 when absent.
uint64_t proc_kib(const char* file, const char* key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::istringstream s(line.substr(std::char_traits<char>::length(key)));
      uint64_t kib = 0;
      s >> kib;
      return kib * 1024;
    }
  return 0;
}

uint64_t read_number(const char* file) {
  std::ifstream in(file);
  std::string word;
  in >> word;
  if (word.empty() || word == "max") return 0;
  try {
    return std::stoull(word);
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace

std::string format_bytes(uint64_t bytes) {
  char buf[32];
  double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f GiB", b / (1024.0 * 1024 * 1024));
  else
    std::snprintf(buf, sizeof buf, "%.0f MiB", b / (1024.0 * 1024));
  return buf;
}

uint64_t shadow_texels(const CaseConfig& c, const scene::Scene* scene) {
  if (c.layout == Layout::atlas) {
    const atlas::Plan plan = scene ? atlas::plan_for(c, *scene) : atlas::uniform_plan(c);
    return uint64_t(plan.width) * uint64_t(plan.height);
  }
  const uint64_t edge = uint64_t(layer_size(c.layout, c.cube_size));
  return uint64_t(traits(c.layout).geometry.layers) * edge * edge * uint64_t(c.light_count);
}

uint64_t shadow_bytes_per_texel(const CaseConfig& c) {
  const uint64_t colour = uint64_t(colour_format_bytes(colour_format(c.storage, c.depth_format)));
  const uint64_t colour_cubes = traits(c.filter).prefilter == Prefilter::separable_blur ? 2 : 1;
  return depth_bytes(c.depth_format) + colour * colour_cubes;
}

uint64_t shadow_storage_bytes(const CaseConfig& c, const scene::Scene* scene) {
  return shadow_texels(c, scene) * shadow_bytes_per_texel(c);
}

MemoryNeed estimate_case_memory(const CaseConfig& c, CubeReadBack cube) {
  const uint64_t texels = shadow_texels(c);
  const uint64_t pixels = uint64_t(c.width) * uint64_t(c.height);
  MemoryNeed need;
  need.device_bytes = shadow_storage_bytes(c);
  // Check variant: RGBA8 lit, R32F shadow factor, RGBA32F position, D32F depth; timed variant: RGBA8 + D32F.
  need.device_bytes += pixels * (4 + 4 + 16 + 4) + pixels * (4 + 4);
  // Host: the read-back cube as floats, held twice (this case and the six_pass reference kept for checks),
  // plus the face strip written as an image (one more float copy and bytes), and the per-pixel buffers four
  // times over. A sampled read-back brings only the check grid (a cube read in full after all is a failing
  // case's path).
  const int grid = c.cube_size / cube_sample_stride(c.cube_size);
  // A full read-back copies the whole shadow image (every light's layers: Vulkan reads the image at once) and
  // keeps one light's.
  const uint64_t host_texels = cube == CubeReadBack::full ? texels : 6ull * uint64_t(grid) * uint64_t(grid);
  need.host_bytes = host_texels * 4 * 3 + host_texels + pixels * (4 + 4 + 4 + 16) * 4;
  if (c.optimizations.light_clusters) {  // the lists' buffer, and the builder's words and pairs on the host
    const uint64_t words = gpu::light_cluster_words(gpu::cluster_grid({}, c.width, c.height), c.light_count);
    need.device_bytes += words * 4;
    need.host_bytes += words * 4 * 3;
  }
  return need;
}

MemoryAvailable host_memory_available() {
  MemoryAvailable a;
  a.host_bytes = proc_kib("/proc/meminfo", "MemAvailable:");
  a.host_limit = "MemAvailable";
  // A container's cgroup (v2) may allow far less than the machine has free.
  uint64_t cg_max = read_number("/sys/fs/cgroup/memory.max");
  if (cg_max > 0) {
    uint64_t used = read_number("/sys/fs/cgroup/memory.current");
    uint64_t left = cg_max > used ? cg_max - used : 0;
    if (left < a.host_bytes) {
      a.host_bytes = left;
      a.host_limit = "cgroup memory.max";
    }
  }
  // ulimit -v: address space, which mappings count against whether touched or not.
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    uint64_t used = proc_kib("/proc/self/status", "VmSize:");
    uint64_t left = as.rlim_cur > used ? as.rlim_cur - used : 0;
    if (left < a.host_bytes) {
      a.host_bytes = left;
      a.host_limit = "RLIMIT_AS (ulimit -v)";
    }
  }
  return a;
}

std::string memory_shortfall(const MemoryNeed& need, const MemoryAvailable& host, const DeviceInfo& device) {
  MemoryAvailable available = host;
  uint64_t device_bytes = device.device_memory_bytes;
  std::string device_source = "the device has";
  if (host.device_budget > 0) {
    if (device.shares_host_memory && (available.host_bytes == 0 || host.device_budget < available.host_bytes))
      available.host_bytes = host.device_budget, available.host_limit = "--memory-budget";
    if (!device.shares_host_memory && (device_bytes == 0 || host.device_budget < device_bytes))
      device_bytes = host.device_budget, device_source = "--memory-budget allows";
  }
  return shortfall_against(need, available, device.shares_host_memory, device_bytes, device_source);
}

std::string shortfall_against(const MemoryNeed& need, const MemoryAvailable& host, bool shares_host_memory,
                              uint64_t device_bytes, const std::string& device_source) {
  // Leave a fifth of what is available to the driver's own allocations (staging, JIT code, command memory).
  auto usable = [](uint64_t bytes) { return bytes / 5 * 4; };
  if (host.host_bytes == 0) return "";  // nothing known (no /proc): let the allocations speak
  uint64_t host_need = need.host_bytes + (shares_host_memory ? need.device_bytes : 0);
  if (host_need > usable(host.host_bytes))
    return "out of memory (predicted): needs " + format_bytes(host_need) + " of host memory (" +
           format_bytes(need.device_bytes) + " of targets" +
           (shares_host_memory ? ", which this driver keeps in host memory" : "") + ", " +
           format_bytes(need.host_bytes) + " of read-back copies), " + format_bytes(host.host_bytes) +
           " available (" + host.host_limit + ")";
  if (!shares_host_memory && device_bytes > 0 && need.device_bytes > usable(device_bytes))
    return "out of memory (predicted): needs " + format_bytes(need.device_bytes) + " of device memory, " +
           device_source + " " + format_bytes(device_bytes);
  return "";
}

}  // namespace omnishadow::bench
