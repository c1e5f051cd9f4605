#include "illum/gpu/context.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include <fmt/ranges.h>

#include "illum/core/log.h"
#include "illum/gpu/vk_check.h"

namespace illum::gpu {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

}  // namespace

const char* to_string(VkResult result) {
  switch (result) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_INCOMPLETE:
      return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_SURFACE_LOST_KHR:
      return "VK_ERROR_SURFACE_LOST_KHR";
    case VK_ERROR_OUT_OF_DATE_KHR:
      return "VK_ERROR_OUT_OF_DATE_KHR";
    case VK_SUBOPTIMAL_KHR:
      return "VK_SUBOPTIMAL_KHR";
    case VK_ERROR_INVALID_SHADER_NV:
      return "VK_ERROR_INVALID_SHADER_NV";
    default:
      return "VkResult(other)";
  }
}

void throw_vk_error(const char* call, VkResult result) {
  throw Error(fmt::format("Vulkan call failed: {} returned {}", call, to_string(result)));
}

bool ContextOptions::default_validation() {
  if (const char* env = std::getenv("ILLUM_VULKAN_VALIDATION")) return std::strcmp(env, "0") != 0;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

Context::Context(const ContextOptions& options) {
  try {
    create_instance(options);
    pick_device(options);
    create_device(!options.instance_extensions.empty());
  } catch (...) {
    destroy();
    throw;
  }
}

Context::~Context() {
  destroy();
}

void Context::destroy() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    allocator_.reset();
    if (immediate_fence_) vkDestroyFence(device_, immediate_fence_, nullptr);
    if (immediate_pool_) vkDestroyCommandPool(device_, immediate_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
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

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debug_callback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  const std::string text = data && data->pMessage ? data->pMessage : "(no message)";
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    log::warn("Vulkan validation: {}", text);
    std::lock_guard lock(self->messages_mutex_);
    self->messages_.push_back(text);
  }
  return VK_FALSE;
}

void Context::create_instance(const ContextOptions& options) {
  uint32_t version = 0;
  if (vkEnumerateInstanceVersion(&version) != VK_SUCCESS || version < VK_API_VERSION_1_3)
    throw Error(
        "no Vulkan 1.3 loader found: install libvulkan1 and mesa-vulkan-drivers (lavapipe) or a "
        "GPU driver");

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  for (const std::string& e : options.instance_extensions) extensions.push_back(e.c_str());
  bool validation = false;
  if (options.validation) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> available(count);
    vkEnumerateInstanceLayerProperties(&count, available.data());
    validation = std::any_of(available.begin(), available.end(), [](const VkLayerProperties& l) {
      return std::strcmp(l.layerName, kValidationLayer) == 0;
    });
    if (validation) {
      layers.push_back(kValidationLayer);
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    } else {
      log::warn("Vulkan validation requested but {} is not installed (vulkan-validationlayers)",
                kValidationLayer);
    }
  }

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "illum";
  app.pEngineName = "illum";
  app.apiVersion = VK_API_VERSION_1_3;

  VkDebugUtilsMessengerCreateInfoEXT messenger{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &Context::debug_callback;
  messenger.pUserData = this;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  if (validation) info.pNext = &messenger;  // also covers vkCreate/DestroyInstance
  const VkResult r = vkCreateInstance(&info, nullptr, &instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw Error("no Vulkan device found: install mesa-vulkan-drivers (lavapipe) or a GPU driver");
  ILLUM_VK(r);
  if (validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create) ILLUM_VK(create(instance_, &messenger, nullptr, &messenger_));
  }
}

void Context::pick_device(const ContextOptions& options) {
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance_, &count, devices.data());
  int best_rank = 1 << 30;
  std::vector<std::string> seen;
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(d, &props);
    seen.emplace_back(props.deviceName);
    if (props.apiVersion < VK_API_VERSION_1_3) continue;
    if (!options.device_filter.empty() &&
        lower(props.deviceName).find(lower(options.device_filter)) == std::string::npos)
      continue;
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.pNext = &f13;
    vkGetPhysicalDeviceFeatures2(d, &f);
    if (!f13.dynamicRendering || !f13.synchronization2) continue;
    uint32_t qcount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qcount, nullptr);
    std::vector<VkQueueFamilyProperties> queues(qcount);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qcount, queues.data());
    int family = -1;
    for (uint32_t q = 0; q < qcount; ++q)
      if ((queues[q].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
          (queues[q].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
        family = static_cast<int>(q);
        break;
      }
    if (family < 0) continue;
    const int rank = type_rank(props.deviceType);
    if (rank >= best_rank) continue;
    best_rank = rank;
    physical_ = d;
    queue_family_ = static_cast<uint32_t>(family);
    device_name_ = props.deviceName;
    device_type_ = props.deviceType;
    limits_ = props.limits;
    timestamp_period_ns_ = (props.limits.timestampComputeAndGraphics &&
                            queues[static_cast<size_t>(family)].timestampValidBits > 0)
                               ? props.limits.timestampPeriod
                               : 0.0f;
  }
  if (!physical_) {
    if (!options.device_filter.empty())
      throw Error(fmt::format(
          "no Vulkan 1.3 device matches '{}' (found: {})", options.device_filter,
          seen.empty() ? std::string("none") : fmt::format("{}", fmt::join(seen, ", "))));
    throw Error("no Vulkan device found: install mesa-vulkan-drivers (lavapipe) or a GPU driver");
  }
}

void Context::begin_conditional(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset) const {
  VkConditionalRenderingBeginInfoEXT info{VK_STRUCTURE_TYPE_CONDITIONAL_RENDERING_BEGIN_INFO_EXT};
  info.buffer = buffer;
  info.offset = offset;
  begin_conditional_(cmd, &info);
}

void Context::create_device(bool swapchain) {
  VkPhysicalDeviceSubgroupProperties subgroup{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  driver.pNext = &subgroup;
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &driver;
  vkGetPhysicalDeviceProperties2(physical_, &props);
  driver_ = fmt::format("{} {}", driver.driverName, driver.driverInfo);
  VkPhysicalDeviceVulkan13Features have13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  have12.pNext = &have13;
  VkPhysicalDeviceConditionalRenderingFeaturesEXT have_conditional{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_CONDITIONAL_RENDERING_FEATURES_EXT};
  uint32_t extension_count = 0;
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &extension_count, nullptr);
  std::vector<VkExtensionProperties> device_extensions(extension_count);
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &extension_count,
                                       device_extensions.data());
  const bool has_conditional_extension =
      std::any_of(device_extensions.begin(), device_extensions.end(), [](const auto& e) {
        return std::strcmp(e.extensionName, VK_EXT_CONDITIONAL_RENDERING_EXTENSION_NAME) == 0;
      });
  if (has_conditional_extension) have13.pNext = &have_conditional;
  VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  have.pNext = &have12;
  vkGetPhysicalDeviceFeatures2(physical_, &have);

  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  f13.dynamicRendering = VK_TRUE;
  f13.synchronization2 = VK_TRUE;
  f13.maintenance4 = have13.maintenance4;  // glslc's vulkan1.3 target emits LocalSizeId
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.pNext = &f13;
  f12.hostQueryReset = have12.hostQueryReset;
  f12.scalarBlockLayout = have12.scalarBlockLayout;
  descriptor_indexing_ = have12.runtimeDescriptorArray && have12.descriptorBindingPartiallyBound &&
                         have12.shaderSampledImageArrayNonUniformIndexing &&
                         have12.descriptorBindingVariableDescriptorCount;
  if (descriptor_indexing_) {
    f12.descriptorIndexing = have12.descriptorIndexing;
    f12.runtimeDescriptorArray = VK_TRUE;
    f12.descriptorBindingPartiallyBound = VK_TRUE;
    f12.shaderSampledImageArrayNonUniformIndexing = VK_TRUE;
    f12.descriptorBindingVariableDescriptorCount = VK_TRUE;
  }
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &f12;
  features.features.depthClamp = have.features.depthClamp;
  depth_clamp_ = have.features.depthClamp == VK_TRUE;
  features.features.samplerAnisotropy = have.features.samplerAnisotropy;
  features.features.geometryShader = have.features.geometryShader;
  primitive_id_ = have.features.geometryShader == VK_TRUE;
  features.features.occlusionQueryPrecise = have.features.occlusionQueryPrecise;
  features.features.pipelineStatisticsQuery = have.features.pipelineStatisticsQuery;
  pipeline_statistics_ = have.features.pipelineStatisticsQuery == VK_TRUE;
  occlusion_query_precise_ = have.features.occlusionQueryPrecise == VK_TRUE;
  features.features.fragmentStoresAndAtomics = have.features.fragmentStoresAndAtomics;
  quad_counting_ = have.features.fragmentStoresAndAtomics == VK_TRUE &&
                   (subgroup.supportedStages & VK_SHADER_STAGE_FRAGMENT_BIT) != 0 &&
                   (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_QUAD_BIT) != 0;
  if (!have.features.imageCubeArray)
    throw Error(fmt::format(
        "Vulkan device '{}' lacks imageCubeArray (needed for point-light shadows)", device_name_));
  features.features.imageCubeArray = VK_TRUE;
  features.features.shaderSampledImageArrayDynamicIndexing =
      have.features.shaderSampledImageArrayDynamicIndexing;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  std::vector<const char*> extensions;
  if (swapchain) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  // Occlusion culling predicates each cluster's draw on a GPU-written flag (SceneDrawer).
  VkPhysicalDeviceConditionalRenderingFeaturesEXT conditional{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_CONDITIONAL_RENDERING_FEATURES_EXT};
  if (has_conditional_extension && have_conditional.conditionalRendering) {
    extensions.push_back(VK_EXT_CONDITIONAL_RENDERING_EXTENSION_NAME);
    conditional.conditionalRendering = VK_TRUE;
    f13.pNext = &conditional;
  }
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  ILLUM_VK(vkCreateDevice(physical_, &info, nullptr, &device_));
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  if (conditional.conditionalRendering) {
    begin_conditional_ = reinterpret_cast<PFN_vkCmdBeginConditionalRenderingEXT>(
        vkGetDeviceProcAddr(device_, "vkCmdBeginConditionalRenderingEXT"));
    end_conditional_ = reinterpret_cast<PFN_vkCmdEndConditionalRenderingEXT>(
        vkGetDeviceProcAddr(device_, "vkCmdEndConditionalRenderingEXT"));
    if (!begin_conditional_ || !end_conditional_) begin_conditional_ = nullptr;
  }
  allocator_ = std::make_unique<Allocator>(physical_, device_);

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags =
      VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool.queueFamilyIndex = queue_family_;
  ILLUM_VK(vkCreateCommandPool(device_, &pool, nullptr, &immediate_pool_));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  ILLUM_VK(vkCreateFence(device_, &fence, nullptr, &immediate_fence_));
  log::debug("Vulkan device: {} (descriptor indexing {})", device_name_,
             descriptor_indexing_ ? "on" : "off");
}

size_t Context::validation_message_count() const {
  std::lock_guard lock(messages_mutex_);
  return messages_.size();
}

std::vector<std::string> Context::validation_messages() const {
  std::lock_guard lock(messages_mutex_);
  return messages_;
}

void Context::immediate(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = immediate_pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  ILLUM_VK(vkAllocateCommandBuffers(device_, &alloc, &cmd));
  struct Free {
    VkDevice d;
    VkCommandPool p;
    VkCommandBuffer c;
    ~Free() { vkFreeCommandBuffers(d, p, 1, &c); }
  } guard{device_, immediate_pool_, cmd};
  record_one_time(cmd, record);
  submit_and_wait(cmd, immediate_fence_);
}

void record_one_time(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  ILLUM_VK(vkBeginCommandBuffer(cmd, &begin));
  record(cmd);
  ILLUM_VK(vkEndCommandBuffer(cmd));
}

void Context::submit_and_wait(VkCommandBuffer cmd, VkFence fence) const {
  VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cb.commandBuffer = cmd;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cb;
  ILLUM_VK(vkQueueSubmit2(queue_, 1, &submit, fence));
  wait_and_reset(fence);
}

void Context::wait_and_reset(VkFence fence) const {
  ILLUM_VK(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX));
  ILLUM_VK(vkResetFences(device_, 1, &fence));
}

void Context::wait_idle() const {
  vkDeviceWaitIdle(device_);
}

}  // namespace illum::gpu
