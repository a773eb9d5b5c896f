// `omnishadow list`: the devices, scenes and axis values a run can name, and per backend what it can draw.

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "backends/common/storage_filter_tables.h"
#include "backends/vulkan/vk_context.h"
#include "bench/cli/commands.h"
#include "bench/run/case_runner.h"
#include "bench/run/memory_budget.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

void print_backends(Harness& harness, std::vector<std::string>& available) {
  std::cout << "backends:\n";
  for (const std::string& name : backend_names()) {
    try {
      const DeviceInfo& d = harness.backend(name).device();
      std::cout << "  " << name << ": " << d.renderer << " | " << d.version << " | " << d.platform
                << " | max cube " << d.max_cube_size << " | "
                << (d.shares_host_memory    ? std::string("host memory (CPU driver)")
                    : d.device_memory_bytes ? format_bytes(d.device_memory_bytes) + " device memory"
                                            : std::string("device memory unknown"))
                << "\n";
      available.push_back(name);
    } catch (const std::exception& e) {
      std::cout << "  " << name << ": unavailable: " << e.what() << "\n";
    }
  }
  try {
    std::cout << "vulkan devices (--vk-device):\n";
    for (const auto& d : vk::VkContext::list_devices())
      std::cout << "  " << d.index << ": " << d.name << " | " << d.type << " | Vulkan " << d.api_version
                << " | " << d.driver << "\n";
  } catch (const std::exception& e) {
    std::cout << "  none: " << e.what() << "\n";
  }
}

void print_scenes(Harness& harness, const std::string& scenes_dir) {
  std::cout << "scenes (" << scenes_dir << "):\n";
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(scenes_dir, ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    try {
      const scene::Scene& s = harness.scene(f.stem().string());
      std::cout << "  " << f.stem().string() << ": " << s.triangle_count() << " triangles, "
                << s.objects.size() << " objects, " << s.point_lights.size() << " point light"
                << (s.point_lights.size() == 1 ? "" : "s")
                << (s.map_lights.empty() ? ""
                                         : " + " + std::to_string(s.map_lights.size()) + " spot/directional")
                << ", frame " << s.camera.width << "x" << s.camera.height << "\n";
    } catch (const std::exception& e) {
      std::cout << "  " << f.stem().string() << ": invalid: " << e.what() << "\n";
    }
  }
}

// Per technique, the storages the backend draws it with and the filters that read each; a technique it cannot
// draw at all, with the reason. The pairs a filter cannot read (hw_compare2x2 on r32f_distance, a moments
// filter on another storage) are counted, not listed: `run` names the reason of any it is given.
void print_support(Backend& b, const std::string& name) {
  std::cout << "supported on " << name << " (technique: storage (filters), at the default cube and frame):\n";
  int refused = 0;
  for (Technique t : all_values<Technique>()) {
    std::string line, first_reason;
    for (Storage s : all_values<Storage>()) {
      std::string filters;
      for (Filter f : all_values<Filter>()) {
        CaseConfig c;
        c.backend = name;
        c.technique = t;
        c.storage = s;
        c.filter = f;
        const Support support = b.supports(c);
        if (support.ok) {
          filters += (filters.empty() ? "" : ", ") + std::string(to_string(f));
        } else {
          ++refused;
          if (first_reason.empty()) first_reason = support.reason;
        }
      }
      if (!filters.empty())
        line += (line.empty() ? "" : "; ") + std::string(to_string(s)) + " (" + filters + ")";
    }
    std::cout << "  " << to_string(t) << ": " << (line.empty() ? "unsupported: " + first_reason : line)
              << "\n";
  }
  std::cout << "  (" << refused << " other technique + storage + filter combinations are refused)\n";
}

}  // namespace

int list_command(const std::string& scenes_dir, const std::map<std::string, std::string>& backend_options) {
  RunOptions options;
  options.scenes_dir = scenes_dir;
  options.backend_options = backend_options;
  Harness harness(options);
  std::vector<std::string> available;
  print_backends(harness, available);
  print_scenes(harness, scenes_dir);
  std::cout << "techniques: " << valid_values<Technique>() << "\n";
  std::cout << "filters: " << valid_values<Filter>() << "\n";
  std::string moments;  // the filters that store and blur their own moments (storage_filter_tables.h)
  for (const FilterTraits& f : kFilterTable)
    if (f.own_storage) moments += (moments.empty() ? "" : ", ") + std::string(f.name);
  std::cout << "moments filters: " << moments << "\n";
  std::cout << "storages: " << valid_values<Storage>() << "\n";
  std::cout << "depth formats: " << valid_values<DepthFormat>() << "\n";
  std::cout << "layouts: " << valid_values<Layout>() << "\n";
  for (const std::string& name : available) print_support(harness.backend(name), name);
  return 0;
}

}  // namespace omnishadow::bench
