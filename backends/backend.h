#pragma once
// The one interface every graphics API implements. It is deliberately coarse: a technique is what we measure,
// so each backend implements it natively and the harness never sees API objects.

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/common/case_config.h"
#include "backends/common/meshlets.h"
#include "backends/common/techniques.h"
#include "backends/common/work_counters.h"
#include "scenes/scene.h"

namespace omnishadow {

struct DeviceInfo {
  std::string api;                   // "OpenGL 4.5 core", "Vulkan 1.3"
  std::string vendor;                // GL_VENDOR / vendorID
  std::string renderer;              // GL_RENDERER / deviceName
  std::string version;               // GL_VERSION / driverVersion
  std::string platform;              // EGL platform, ICD path, ...
  int max_cube_size = 0;             // GL_MAX_CUBE_MAP_TEXTURE_SIZE / maxImageDimensionCube
  uint64_t device_memory_bytes = 0;  // largest device-local heap / GL_NVX_gpu_memory_info; 0 = unknown
  bool shares_host_memory = false;   // CPU drivers (llvmpipe, lavapipe): targets live in host memory
  // The rasteriser's sub-pixel precision: vertices are snapped to 1 / 2^bits of a pixel (GL_SUBPIXEL_BITS,
  // VkPhysicalDeviceLimits::subPixelPrecisionBits; both APIs require at least 4). The texel truths' bounds
  // read it.
  int subpixel_bits = 4;
  // The sampler's sub-texel precision: a texel coordinate may be quantised to 1 / 2^bits of a texel before a
  // texel is chosen (VkPhysicalDeviceLimits::subTexelPrecisionBits, at least 4; GL states none, so 4 is
  // assumed there). The lookup check (bench/truth/lookup_check.h) reads it.
  int subtexel_bits = 4;
  std::map<std::string, std::string> extra;  // anything else worth recording (extensions that matter, ...)
};

struct FrameCounters {
  PassCounters shadow;
  PassCounters lighting;
};

// Times in milliseconds. cpu_submit: from the first command of the pass until the API returned (recording and
// submission); cpu_wall: from the first command until the pass completed (glFinish / fence). gpu: timer or
// timestamp queries, negative when the backend has none; the harness decides whether to trust it.
struct PassTiming {
  double cpu_submit_ms = 0.0;
  double cpu_wall_ms = 0.0;
  double gpu_ms = -1.0;
};

struct FrameTiming {
  PassTiming shadow;
  PassTiming lighting;
  double frame_wall_ms = 0.0;
  // CPU time the whole process spent on the frame (all threads: on CPU drivers such as llvmpipe and lavapipe
  // that is the rendering itself). Filled by the harness around render(); a measure of work that other load
  // on the machine disturbs far less than wall time does. Negative when not measured.
  double process_cpu_ms = -1.0;
};

// A frame's host timestamps as both backends take them (steady clock): [0] before the shadow pass's uniforms,
// [1] once it is submitted, [2] once it completed, [3] once the lighting pass is submitted, [4] once it
// completed; with each pass's GPU time (negative where the device has no timer).
using HostClock = std::chrono::steady_clock;
inline FrameTiming frame_timing(const std::array<HostClock::time_point, 5>& t, double shadow_gpu_ms,
                                double lighting_gpu_ms) {
  auto ms = [](HostClock::time_point a, HostClock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  FrameTiming f;
  f.shadow = {ms(t[0], t[1]), ms(t[0], t[2]), shadow_gpu_ms};
  f.lighting = {ms(t[2], t[3]), ms(t[2], t[4]), lighting_gpu_ms};
  f.frame_wall_ms = ms(t[0], t[4]);
  return f;
}

// A timed frame renders what a renderer would for the case: the shadow pass, then the lighting pass in its
// timed variant (one colour target, a shader specialised for the case: gpu::LightingVariant). A check frame
// renders the same shadow pass, then the lighting pass in the check variant (lit colour, shadow factor, world
// position) and, untimed after it, in the timed variant, so that read_back() holds both lit images of one
// frame. A floor frame does only what every variant must: the case's shadow render passes with their clears
// and no draw, then the lighting pass into the timed target with a constant shader (shaders/floor.frag); a
// pass's time as a multiple of its floor is what the technique or filter costs beyond that. A floor frame
// leaves the cube cleared.
enum class FrameKind { timed, check, floor };

// What the device tells of the cube without reading it back: per face, a 64-bit hash of the stored values
// (equal hashes: equal faces, but for a chance of about 2^-64) and how many are not finite. Hashes are of the
// values as stored, so they compare between cases of one backend (and storage), never across APIs.
struct CubeFaceSummary {
  uint64_t hash = 0;
  uint64_t non_finite = 0;
  bool operator==(const CubeFaceSummary&) const = default;
};
using CubeSummary = std::array<CubeFaceSummary, 6>;

// The check grid of a cube: every texel up to kCubeSampleGrid a face edge, above that every stride-th in s
// and t.
inline constexpr int kCubeSampleGrid = 128;
inline int cube_sample_stride(int cube_size) {
  return cube_size > kCubeSampleGrid ? cube_size / kCubeSampleGrid : 1;
}

// How much of the cube read_back() copies to the host. sampled: the summary and the check grid only (a 4096
// cube is 400 MB as floats; its grid 400 KB); full: every texel too, for images and for comparing faces whose
// hashes differ.
enum class CubeReadBack { sampled, full };

// Everything read back after a check frame. Images are stored as the API holds them: row 0 is the bottom row
// of the lit frame (GL window convention) and, for cube faces, row 0 is t = 0 of the face (cube-map
// addressing).
struct Images {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> lit_rgba8;  // the lit frame (check variant)
  std::vector<uint8_t>
      timed_lit_rgba8;  // the same frame lit by the timed variant: must equal lit_rgba8 bit for bit
  std::vector<float> shadow_factor;  // per pixel: 1 = fully shadowed, 0 = fully lit (the tutorial's `shadow`)
  std::vector<float> world_position;  // RGBA32F: xyz world position, w = 1 where geometry was drawn
  int cube_size = 0;
  float light_far = 0.0f;  // the far plane the cube was rendered with (the scene's, or fitted: fit_range)
  // Per face, the light distance in world units that the shadow pass stored (linear_depth values are
  // multiplied back by light_far; texels nothing was drawn to hold light_far, or FLT_MAX for r32f_distance).
  // Empty unless the read-back was CubeReadBack::full: the summary and sample below serve the checks
  // otherwise.
  std::array<std::vector<float>, 6> cube_distance;
  // Always: computed on the device (shaders/cube_summary.comp, over the stored values) for a sampled
  // read-back, on the host (cube::summarize_on_host, over the distances) for a full one. Hashes of the two
  // kinds never compare.
  CubeSummary cube_summary;
  bool cube_summary_on_device = false;
  // Light distances (as cube_distance) at the check grid's texels: (x * stride + stride / 2, y * stride +
  // stride / 2) for x, y < cube_size / stride, row-major per face. Always read back; tiny next to the cube.
  int cube_sample_stride = 1;
  std::array<std::vector<float>, 6> cube_sample;
  bool has_full_cube() const { return !cube_distance[0].empty(); }
  // The faces the frame drew (bit f = face f): view culling (--optimize view) leaves the others cleared or as
  // an earlier frame left them, read by no visible pixel; the checks read only these. Set by the harness.
  uint8_t view_faces = 0x3f;
  bool face_drawn(int f) const { return (view_faces >> f) & 1u; }
  // Moments storages, with a full read-back: per face the blurred moments the lighting pass sampled,
  // `moment_channels` floats a texel, texels as cube_distance's. Empty otherwise.
  int moment_channels = 0;
  std::array<std::vector<float>, 6> moments;
  // Spot/directional lights' 2D maps (none without such lights): per map, the stored window depth in [0, 1],
  // row-major, row 0 at NDC y = -1; 1 where nothing was drawn. The maps use the API's clip depth range (GL
  // -1..1, Vulkan 0..1), which the truth must know.
  int map_size = 0;
  bool map_depth_zero_to_one = false;
  std::vector<std::vector<float>> map_depth;
};

// The public calls check the order of use (load, configure, render, read_back) and keep the state every
// backend shares; each backend implements the protected steps with its API.
class Backend {
 public:
  virtual ~Backend() = default;
  const DeviceInfo& device() const { return info_; }             // filled by the backend's constructor
  virtual Support supports(const CaseConfig& config) const = 0;  // unsupported is a result, not an error
  void load(const scene::Scene& scene);  // upload geometry once per scene; forgets the case
  // Makes `config` the current case: targets, programs, queries. Throws std::logic_error before load(), and
  // std::runtime_error("unsupported: ...") for a case supports() refuses; nothing to do for the current case.
  void configure(const CaseConfig& config);
  FrameTiming render(int frame, FrameKind kind);  // blocks until the frame has completed
  FrameCounters count_work(int frame);            // renders `frame` once, timed kind, with statistics
  // Results of the last check frame for point light `light` (< CaseConfig::light_count): its shadow factor,
  // its map (cube_*, light_far) and the lit images every light shares. Another light than the last read back
  // needs the check frame to be the last frame rendered (its lighting pass is rendered again to report that
  // light's shadow factor).
  Images read_back(CubeReadBack cube = CubeReadBack::full, int light = 0);
  // API errors reported by the checking mode (GL KHR_debug, Vulkan validation) since the last call; empty
  // when the checking mode is off. Drained outside timed loops.
  virtual std::vector<std::string> drain_api_errors();
  // Drops the API's error flags that a capture tool's own calls left behind (RenderDoc's EndFrameCapture
  // reads a surfaceless GL context's default framebuffer): not the harness's errors. Only after such a call.
  virtual void discard_tool_errors() {}
  // Per point light, the frame index whose light position each face's content was rendered for (-1: nothing,
  // or cleared) after the last frame: what the update budget left stale (gpu::FaceContent). Empty where the
  // backend keeps no such record.
  virtual std::vector<std::array<int, 6>> face_frames() const { return {}; }

 protected:
  // The API's per-thread state made this backend's before each public call reaches it: GL calls go to the
  // thread's current context, and another backend in the process may have made its own current or left none.
  // Nothing to do for an API without such state (Vulkan).
  virtual void make_current() {}
  // Whether this device runs technique mesh_shader, or its test-only emulation (--emulate-mesh-shader):
  // load() then builds the scene's meshlets before it lets the scene's vertices go (they live on the device
  // after upload), for the mesh pass of a later case.
  virtual bool has_mesh_shading() const { return false; }
  virtual bool emulates_mesh_shading() const { return false; }
  virtual void upload_scene(
      const scene::Scene& scene) = 0;  // releases the case and the last scene's geometry
  // The moving objects' vertex ranges of scene_->vertices (just posed) to the device, before the next frame's
  // shadow pass reads them.
  virtual void upload_moving_objects() = 0;
  // configure()'s work once the case is known to be new and supported: release the last case's objects,
  // create this one's, and set config_ (left empty when it throws).
  virtual void configure_case(const CaseConfig& config) = 0;
  virtual FrameTiming render_frame(int frame, FrameKind kind) = 0;
  virtual FrameCounters count_frame_work(int frame) = 0;
  // sampled: cube_summary and cube_sample from the device; full: cube_distance (read_back() then summarises
  // it). Of point light `light`, whose shadow factor the check frame's lighting pass reported.
  virtual Images read_back_images(CubeReadBack cube, int light) = 0;
  // Renders the last check frame's lighting pass (check variant) again, reporting light `light`'s shadow
  // factor; the shadow maps are the check frame's.
  virtual void report_light(int light) = 0;
  void pose(int frame);  // scene_ posed at `frame`, its moving objects uploaded

  DeviceInfo info_;
  std::optional<scene::Scene>
      scene_;  // set by load(): objects, light path, camera (vertices live on the device)
  std::optional<gpu::MeshletData> meshlets_;  // set by load() where mesh shading runs or is emulated
  std::vector<ObjectDraw> all_objects_;       // every object once: the lighting pass's and the 2D maps' draws
  std::optional<CaseConfig> config_;          // the current case
  bool checked_ = false;                 // a check frame was rendered since configure (read_back needs one)
  bool check_is_last_ = false;           // and no other frame since
  int reported_light_ = 0;               // the point light whose shadow factor the check targets hold
  std::vector<std::string> api_errors_;  // the checking mode's messages, where the backend collects them here
};

// Creates a backend by name ("gl"). Options are backend-specific: "egl_platform" = surfaceless|device,
// "gl_profile" = auto|core|compatibility (GlBackend's constructor),
// "gl_device" = EGL device index, "vk_device" = Vulkan device index or part of its name, "api_checks" = "1"
// for the checking mode (GL debug context / Vulkan validation layer, errors captured).
// Throws std::runtime_error with a one-line reason when the API cannot be brought up on this machine.
std::unique_ptr<Backend> create_backend(const std::string& name,
                                        const std::map<std::string, std::string>& options);
std::vector<std::string> backend_names();

}  // namespace omnishadow
