#include "backends/vulkan/vk_context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>

namespace omnishadow::vk {

const char* result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    default:
      return "VkResult error";
  }
}

void check(VkResult result, const char* call) {
  if (result == VK_SUCCESS) return;
  std::string name = call;
  name = name.substr(0, name.find('('));
  throw std::runtime_error(name + " failed: " + result_name(result) + " (" + std::to_string(result) + ")");
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                     void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
    static_cast<VkContext*>(user)->add_message(data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

std::string version_string(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    default:
      return "other";
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

VkInstance create_instance(bool validation, const VkDebugUtilsMessengerCreateInfoEXT* messenger_info) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "omnishadow";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  if (validation) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> available(count);
    vkEnumerateInstanceLayerProperties(&count, available.data());
    bool found = std::any_of(available.begin(), available.end(), [](const VkLayerProperties& l) {
      return std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0;
    });
    if (!found)
      throw std::runtime_error(
          "--api-checks needs VK_LAYER_KHRONOS_validation (Debian: vulkan-validationlayers)");
    layers.push_back("VK_LAYER_KHRONOS_validation");
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = validation ? messenger_info : nullptr;  // also reports problems in vkCreate/DestroyInstance
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw std::runtime_error(
        "no Vulkan 1.2 driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); "
        "Debian: mesa-vulkan-drivers gives lavapipe");
  OMNISHADOW_VK(r);
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t count = 0;
  OMNISHADOW_VK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  OMNISHADOW_VK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  return devices;
}

PhysicalDeviceSummary summarize(VkPhysicalDevice d, int index) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(d, &props);
  return {index, props.properties.deviceName, type_name(props.properties.deviceType),
          version_string(props.properties.apiVersion),
          std::string(driver.driverName) + " " + driver.driverInfo};
}

}  // namespace

std::vector<PhysicalDeviceSummary> VkContext::list_devices() {
  VkInstance instance = create_instance(false, nullptr);
  std::vector<PhysicalDeviceSummary> out;
  auto devices = physical_devices(instance);
  for (size_t i = 0; i < devices.size(); ++i) out.push_back(summarize(devices[i], static_cast<int>(i)));
  vkDestroyInstance(instance, nullptr);
  return out;
}

VkContext::VkContext(const std::string& selector, bool validation) : validation_(validation) {
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger_info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = on_validation_message;
  messenger_info.pUserData = this;
  instance_ = create_instance(validation, &messenger_info);
  try {
    if (validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw std::runtime_error("vkCreateDebugUtilsMessengerEXT is not available");
      OMNISHADOW_VK(create(instance_, &messenger_info, nullptr, &messenger_));
    }
    select_device(selector);
    read_properties();
    create_device();
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = queue_family_;
    OMNISHADOW_VK(vkCreateCommandPool(device_, &pool_info, nullptr, &pool_));
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    OMNISHADOW_VK(vkCreateFence(device_, &fence_info, nullptr, &fence_));
  } catch (...) {
    release();
    throw;
  }
}

// By index, or by a part of its name. No fallback.
void VkContext::select_device(const std::string& selector) {
  auto devices = physical_devices(instance_);
  std::string available;
  for (size_t i = 0; i < devices.size(); ++i)
    available += (i ? ", " : "") + std::to_string(i) + ": " + summarize(devices[i], static_cast<int>(i)).name;
  if (devices.empty())
    throw std::runtime_error("no Vulkan device (Debian: mesa-vulkan-drivers gives lavapipe)");
  bool numeric = !selector.empty() && std::all_of(selector.begin(), selector.end(), ::isdigit);
  if (selector.empty()) {
    physical_ = devices[0];
  } else if (numeric) {
    size_t index = std::stoul(selector);
    if (index >= devices.size())
      throw std::runtime_error("--vk-device " + selector + " is out of range (devices: " + available + ")");
    physical_ = devices[index];
  } else {
    for (size_t i = 0; i < devices.size() && !physical_; ++i)
      if (lower(summarize(devices[i], 0).name).find(lower(selector)) != std::string::npos)
        physical_ = devices[i];
    if (!physical_)
      throw std::runtime_error("--vk-device '" + selector +
                               "' matches no Vulkan device (devices: " + available + ")");
  }
}

// Properties, driver, memory, the graphics queue family and the features the techniques can use.
void VkContext::read_properties() {
  driver_ = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver_};
  vkGetPhysicalDeviceProperties2(physical_, &props2);
  properties_ = props2.properties;
  if (properties_.apiVersion < VK_API_VERSION_1_2)
    throw std::runtime_error(std::string(properties_.deviceName) + " supports Vulkan " +
                             version_string(properties_.apiVersion) + "; omnishadow needs 1.2");
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, families.data());
  bool found = false;
  for (uint32_t i = 0; i < family_count && !found; ++i)
    if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
      queue_family_ = i;
      timestamp_valid_bits_ = families[i].timestampValidBits;
      found = true;
    }
  if (!found) throw std::runtime_error(std::string(properties_.deviceName) + " has no graphics queue");

  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES, &f12};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f11};
  vkGetPhysicalDeviceFeatures2(physical_, &features);
  geometry_shader_ = features.features.geometryShader;
  clip_distance_ = features.features.shaderClipDistance;
  image_cube_array_ = features.features.imageCubeArray;
  pipeline_statistics_ = features.features.pipelineStatisticsQuery;
  storage_image_extended_formats_ = features.features.shaderStorageImageExtendedFormats;
  multiview_ = f11.multiview;
  layer_output_ = f12.shaderOutputLayer;
  viewport_output_ = f12.shaderOutputViewportIndex;
  multi_viewport_ = features.features.multiViewport;

  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> available(count);
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, available.data());
  auto has = [&](const char* name) {
    for (const VkExtensionProperties& e : available)
      if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
  };
  for (const char* ext : {VK_NV_VIEWPORT_SWIZZLE_EXTENSION_NAME, VK_NV_VIEWPORT_ARRAY_2_EXTENSION_NAME,
                          VK_NV_GEOMETRY_SHADER_PASSTHROUGH_EXTENSION_NAME})
    if (!has(ext)) missing_for_swizzle_ += (missing_for_swizzle_.empty() ? "" : ", ") + std::string(ext);
  if (!geometry_shader_)
    missing_for_swizzle_ += (missing_for_swizzle_.empty() ? "" : ", ") + std::string("geometryShader");
  if (!multi_viewport_)
    missing_for_swizzle_ += (missing_for_swizzle_.empty() ? "" : ", ") + std::string("multiViewport");
  if (missing_for_swizzle_.empty())
    extensions_.insert(extensions_.end(),
                       {VK_NV_VIEWPORT_SWIZZLE_EXTENSION_NAME, VK_NV_VIEWPORT_ARRAY_2_EXTENSION_NAME,
                        VK_NV_GEOMETRY_SHADER_PASSTHROUGH_EXTENSION_NAME});
  if (has(VK_EXT_MESH_SHADER_EXTENSION_NAME)) {
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &mesh};
    vkGetPhysicalDeviceFeatures2(physical_, &query);
    mesh_shader_ = mesh.taskShader && mesh.meshShader;
    if (mesh_shader_) extensions_.push_back(VK_EXT_MESH_SHADER_EXTENSION_NAME);
    VkPhysicalDeviceMeshShaderPropertiesEXT limits{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_PROPERTIES_EXT};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &limits};
    vkGetPhysicalDeviceProperties2(physical_, &properties);
    max_mesh_launch_ = std::min(limits.maxTaskWorkGroupCount[0], limits.maxTaskWorkGroupTotalCount);
  }
}

// Enables exactly what the techniques use, nothing else.
void VkContext::create_device() {
  VkPhysicalDeviceVulkan12Features e12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  e12.shaderOutputLayer = layer_output_;
  e12.shaderOutputViewportIndex = viewport_output_;
  VkPhysicalDeviceVulkan11Features e11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES, &e12};
  e11.multiview = multiview_;
  VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &e11};
  enable.features.geometryShader = geometry_shader_;
  enable.features.shaderClipDistance = clip_distance_;
  enable.features.imageCubeArray = image_cube_array_;
  enable.features.pipelineStatisticsQuery = pipeline_statistics_;
  enable.features.shaderStorageImageExtendedFormats = storage_image_extended_formats_;
  enable.features.multiViewport = multi_viewport_;  // nv_swizzle's six viewports, an atlas's six tiles
  VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
  mesh.taskShader = mesh.meshShader = VK_TRUE;
  if (mesh_shader_) {
    mesh.pNext = enable.pNext;
    enable.pNext = &mesh;
  }

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &enable};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.enabledExtensionCount = static_cast<uint32_t>(extensions_.size());
  device_info.ppEnabledExtensionNames = extensions_.data();
  OMNISHADOW_VK(vkCreateDevice(physical_, &device_info, nullptr, &device_));
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
}

VkContext::~VkContext() { release(); }

void VkContext::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (fence_) vkDestroyFence(device_, fence_, nullptr);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);  // the validation layer reports objects never destroyed here
    device_ = VK_NULL_HANDLE;
  }
  // Nobody drains messages after this point: say them, so a leak found at shutdown is not lost.
  for (const std::string& m : messages_)
    std::fprintf(stderr, "omnishadow: Vulkan validation: %s\n", m.c_str());
  messages_.clear();
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

uint32_t VkContext::memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  throw std::runtime_error("no Vulkan memory type with the required properties");
}

VkFormatProperties VkContext::format_properties(VkFormat format) const {
  VkFormatProperties p{};
  vkGetPhysicalDeviceFormatProperties(physical_, format, &p);
  return p;
}

void VkContext::submit(VkCommandBuffer cb) {
  VkSubmitInfo info{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  info.commandBufferCount = 1;
  info.pCommandBuffers = &cb;
  OMNISHADOW_VK(vkQueueSubmit(queue_, 1, &info, fence_));
}

void VkContext::wait() {
  OMNISHADOW_VK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
  OMNISHADOW_VK(vkResetFences(device_, 1, &fence_));
}

VkCommandBuffer VkContext::begin_one_time() {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkAllocateCommandBuffers(device_, &alloc, &cb));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  OMNISHADOW_VK(vkBeginCommandBuffer(cb, &begin));
  return cb;
}

void VkContext::end_one_time_and_wait(VkCommandBuffer cb) {
  OMNISHADOW_VK(vkEndCommandBuffer(cb));
  submit(cb);
  wait();
  vkFreeCommandBuffers(device_, pool_, 1, &cb);
}

std::vector<std::string> VkContext::drain_messages() {
  std::vector<std::string> out;
  out.swap(messages_);
  return out;
}

void VkContext::add_message(std::string message) {
  if (messages_.size() < 100) messages_.push_back(std::move(message));
}

}  // namespace omnishadow::vk
