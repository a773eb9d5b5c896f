// The explicit table of backends. A run names its backend; nothing here falls back to another one.

#include <stdexcept>

#include "backends/backend.h"
#include "backends/common/cube_summary.h"
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

void Backend::load(const scene::Scene& scene) {
  make_current();
  config_.reset();
  checked_ = false;
  check_is_last_ = false;
  // The device's copy starts at rest, whatever frame the caller's scene is posed at, so that the first frame
  // rendered poses and uploads its moving casters like every later one (a check of any frame covers it).
  scene_ = scene;
  scene_->put_at_rest();
  upload_scene(*scene_);
  meshlets_.reset();
  if (has_mesh_shading() || emulates_mesh_shading())
    meshlets_ = gpu::build_meshlets(*scene_);  // needs the vertices released below
  scene_->focus_light = 0;
  if (!scene_->has_moving_objects()) {  // only the device's copy is needed after upload
    scene_->vertices.clear();
    scene_->vertices.shrink_to_fit();
  }
  all_objects_.clear();
  for (uint32_t i = 0; i < scene.objects.size(); ++i) all_objects_.push_back({i, 1, 0});
}

void Backend::configure(const CaseConfig& c) {
  if (!scene_) throw std::logic_error("configure() before load()");
  if (config_ && *config_ == c) return;
  make_current();
  Support s = supports(c);
  if (!s.ok) throw std::runtime_error("unsupported: " + s.reason);
  checked_ = false;
  check_is_last_ = false;
  configure_case(c);
}

// The scene's moving casters where `frame` has them, on the host and on the device, before anything of the
// frame is planned or drawn: a renderer's per-frame vertex upload, part of the frame's shadow pass.
void Backend::pose(int frame) {
  if (scene_->posed_frame == frame || !scene_->has_moving_objects()) return;
  scene_->pose(frame);
  upload_moving_objects();
}

FrameTiming Backend::render(int frame, FrameKind kind) {
  if (!config_) throw std::logic_error("render() before configure()");
  make_current();
  pose(frame);
  FrameTiming t = render_frame(frame, kind);
  if (kind == FrameKind::check) checked_ = true;
  check_is_last_ = kind == FrameKind::check;
  if (kind == FrameKind::check) reported_light_ = 0;
  return t;
}

FrameCounters Backend::count_work(int frame) {
  if (!config_) throw std::logic_error("count_work() before configure()");
  make_current();
  check_is_last_ = false;
  pose(frame);
  return count_frame_work(frame);
}

Images Backend::read_back(CubeReadBack cube, int light) {
  if (!config_) throw std::logic_error("read_back() before configure()");
  if (!checked_) throw std::logic_error("read_back() before a check frame (render(frame, FrameKind::check))");
  if (light < 0 || light >= config_->light_count)
    throw std::logic_error("read_back() of light " + std::to_string(light) + " of a case with " +
                           std::to_string(config_->light_count));
  make_current();
  if (light != reported_light_) {
    if (!check_is_last_)
      throw std::logic_error("read_back() of another light after a frame other than the check frame");
    report_light(light);
    reported_light_ = light;
  }
  Images img = read_back_images(cube, light);
  // A full read-back is summarised here, on the host, for every backend (no compute pass where the cube is in
  // host memory anyway); a sampled one brings the device's summary.
  if (img.has_full_cube()) cube::summarize_on_host(img);
  return img;
}

std::vector<std::string> Backend::drain_api_errors() {
  std::vector<std::string> out;
  out.swap(api_errors_);
  return out;
}

std::unique_ptr<Backend> create_backend(const std::string& name,
                                        const std::map<std::string, std::string>& options) {
  if (name == "gl") {
    std::string device = option(options, "gl_device", "0");
    int index = 0;
    try {
      index = std::stoi(device);
    } catch (const std::exception&) {
      throw std::runtime_error("--gl-device expects an EGL device index, got '" + device + "'");
    }
    return std::make_unique<gl::GlBackend>(option(options, "egl_platform", "surfaceless"), index,
                                           option(options, "api_checks", "0") == "1",
                                           option(options, "gl_profile", "auto"));
  }
  if (name == "vulkan")
    return std::make_unique<vk::VkBackend>(option(options, "vk_device", ""),
                                           option(options, "api_checks", "0") == "1");
  std::string valid;
  for (const auto& n : backend_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown backend '" + name + "' (valid: " + valid + ")");
}

}  // namespace omnishadow
