// The explicit table of backends. A run names its backend; nothing here falls back to another one.

#include <stdexcept>

#include "backends/backend.h"
#include "backends/gl/gl_backend.h"
#include "backends/vulkan/vk_backend.h"

namespace omnishadow {
namespace {

std::string option(const std::map<std::string, std::string>& options, const std::string& key,
                   const std::string& fallback) {
  auto it = options.find(key);
  return it == options.end() ? fallback : it->second;
}

}  // namespace

std::vector<std::string> backend_names() { return {"gl", "vulkan"}; }

void Backend::configure(const CaseConfig& c) {
  if (!scene_) throw std::logic_error("configure() before load()");
  if (config_ && *config_ == c) return;
  Support s = supports(c);
  if (!s.ok) throw std::runtime_error("unsupported: " + s.reason);
  configure_case(c);
}

std::unique_ptr<Backend> create_backend(const std::string& name, const std::map<std::string, std::string>& options) {
  if (name == "gl") {
    std::string device = option(options, "gl_device", "0");
    int index = 0;
    try {
      index = std::stoi(device);
    } catch (const std::exception&) {
      throw std::runtime_error("--gl-device expects an EGL device index, got '" + device + "'");
    }
    return std::make_unique<gl::GlBackend>(option(options, "egl_platform", "surfaceless"), index,
                                           option(options, "api_checks", "0") == "1");
  }
  if (name == "vulkan")
    return std::make_unique<vk::VkBackend>(option(options, "vk_device", ""), option(options, "api_checks", "0") == "1");
  std::string valid;
  for (const auto& n : backend_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown backend '" + name + "' (valid: " + valid + ")");
}

}  // namespace omnishadow
