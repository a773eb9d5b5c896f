#pragma once
// A headless Vulkan 1.2+ device: instance (with the validation layer in the checking mode), the chosen
// physical device, one graphics queue, a command pool and a fence. No surface, no window system.

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace omnishadow::vk {

// Throws std::runtime_error("vkCreateDevice failed: VK_ERROR_OUT_OF_DEVICE_MEMORY").
void check(VkResult result, const char* call);
#define OMNISHADOW_VK(call) ::omnishadow::vk::check((call), #call)
const char* result_name(VkResult result);

struct PhysicalDeviceSummary {
  int index;
  std::string name;
  std::string type;  // cpu, integrated, discrete, virtual, other
  std::string api_version;
  std::string driver;
};

class VkContext {
 public:
  // selector: "" or an index ("0") or a case-insensitive part of the device name ("llvmpipe"). Never falls
  // back to another device: no match is an error listing the devices. validation:
  // VK_LAYER_KHRONOS_validation.
  VkContext(const std::string& selector, bool validation);
  ~VkContext();
  VkContext(const VkContext&) = delete;
  VkContext& operator=(const VkContext&) = delete;

  static std::vector<PhysicalDeviceSummary> list_devices();

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return pool_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceDriverProperties& driver() const { return driver_; }
  uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }

  bool has_geometry_shader() const { return geometry_shader_; }
  bool has_clip_distance() const { return clip_distance_; }  // dual_paraboloid clips the other hemisphere
  bool has_image_cube_array() const { return image_cube_array_; }  // layout cube_array's views
  bool has_multiview() const { return multiview_; }
  bool has_layer_output() const { return layer_output_; }  // shaderOutputLayer (1.2) for vs_layer
  // multiViewport, and shaderOutputViewportIndex (1.2): layout atlas routes a single pass's faces by
  // viewport.
  bool has_multi_viewport() const { return multi_viewport_; }
  bool has_viewport_output() const { return viewport_output_; }
  bool has_pipeline_statistics() const { return pipeline_statistics_; }
  bool has_storage_image_extended_formats() const { return storage_image_extended_formats_; }
  // nv_swizzle: what the device lacks of VK_NV_viewport_swizzle, VK_NV_viewport_array2,
  // VK_NV_geometry_shader_passthrough, geometryShader and multiViewport; empty: it has them all (enabled).
  const std::string& missing_for_swizzle() const { return missing_for_swizzle_; }
  // mesh_shader: VK_EXT_mesh_shader with its taskShader and meshShader features (enabled when present).
  bool has_mesh_shader() const { return mesh_shader_; }
  // The task workgroups one vkCmdDrawMeshTasksEXT(x, 1, 1) launches: maxTaskWorkGroupCount[0] within
  // maxTaskWorkGroupTotalCount (0 without mesh shading).
  uint32_t max_mesh_launch() const { return max_mesh_launch_; }
  bool validation() const { return validation_; }

  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted) const;
  VkFormatProperties format_properties(VkFormat format) const;

  // Records with `record`, submits, waits. For set-up and read-back, never inside timed frames.
  template <typename Record>
  void submit_and_wait(Record record) {
    VkCommandBuffer cb = begin_one_time();
    record(cb);
    end_one_time_and_wait(cb);
  }
  // Submits `cb` and waits on the context's fence; returns after the GPU finished.
  void submit(VkCommandBuffer cb);
  void wait();

  // Validation messages (errors and warnings) since the last call.
  std::vector<std::string> drain_messages();
  void add_message(std::string message);

 private:
  void release();  // destroys whatever was created; safe on a half-built context
  void select_device(const std::string& selector);
  void read_properties();
  void create_device();
  VkCommandBuffer begin_one_time();
  void end_one_time_and_wait(VkCommandBuffer cb);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceDriverProperties driver_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  uint32_t timestamp_valid_bits_ = 0;
  bool geometry_shader_ = false;
  bool clip_distance_ = false;
  bool image_cube_array_ = false;
  bool multiview_ = false;
  bool layer_output_ = false;
  bool viewport_output_ = false;
  bool pipeline_statistics_ = false;
  bool storage_image_extended_formats_ = false;  // rg32f / rg16f storage images (the moments blur)
  bool multi_viewport_ = false;
  std::string missing_for_swizzle_;
  bool mesh_shader_ = false;
  uint32_t max_mesh_launch_ = 0;
  std::vector<const char*> extensions_;  // the device extensions enabled
  bool validation_ = false;
  std::vector<std::string> messages_;
};

}  // namespace omnishadow::vk
