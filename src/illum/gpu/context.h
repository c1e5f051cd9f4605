// The Vulkan 1.3 instance, device and queue every GPU object is made from. Device choice
// prefers a discrete GPU, then integrated, then anything (lavapipe). Required features:
// dynamic rendering and synchronization2 (core 1.3); descriptor indexing is enabled where
// the device has it. Validation (VK_LAYER_KHRONOS_validation + a debug-utils messenger) is
// on in debug builds, in tests, and wherever ILLUM_VULKAN_VALIDATION=1; every message of
// warning or error severity is counted so tests can assert there were none.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/allocator.h"

namespace illum::gpu {

struct ContextOptions {
  // Default: on in debug builds, off in release; $ILLUM_VULKAN_VALIDATION (0/1) overrides.
  bool validation = default_validation();
  // Case-insensitive substring of the device name to pick ("" = best device by type).
  std::string device_filter;
  // Instance extensions a window system needs (from glfwGetRequiredInstanceExtensions);
  // when not empty, VK_KHR_swapchain is enabled on the device too.
  std::vector<std::string> instance_extensions;

  static bool default_validation();
};

// Begins `cmd` for one submission, records into it with `record` and ends it.
void record_one_time(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& record);

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  Allocator& allocator() { return *allocator_; }

  const std::string& device_name() const { return device_name_; }
  // The driver as VkPhysicalDeviceDriverProperties gives it: "NVIDIA 580.159.04",
  // "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)" (name, then info).
  const std::string& driver() const { return driver_; }
  bool is_software() const { return device_type_ == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  bool descriptor_indexing() const { return descriptor_indexing_; }
  bool depth_clamp() const { return depth_clamp_; }
  // gl_PrimitiveID in fragment shaders (the visibility buffer's triangle ids) needs the
  // geometryShader feature, enabled where the device has it.
  bool primitive_id() const { return primitive_id_; }
  // Occlusion queries count exact samples (counting frames of illum-bench raster).
  bool occlusion_query_precise() const { return occlusion_query_precise_; }
  // Pipeline statistics queries (counting frames: the triangles that reach rasterization).
  bool pipeline_statistics() const { return pipeline_statistics_; }
  // Fragment shaders can count the 2×2 quads they run in (subgroup quad operations and
  // storage writes in the fragment stage: shaders/quad_count.frag).
  bool quad_counting() const { return quad_counting_; }
  // VK_EXT_conditional_rendering (draws predicated on a GPU-written flag: occlusion culling),
  // enabled where the device has it.
  bool conditional_rendering() const { return begin_conditional_ != nullptr; }
  // Draws recorded until end_conditional() run only where the uint32 at `offset` of
  // `buffer` is not zero (needs conditional_rendering()).
  void begin_conditional(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset) const;
  void end_conditional(VkCommandBuffer cmd) const { end_conditional_(cmd); }
  bool timestamps() const { return timestamp_period_ns_ > 0.0f; }
  float timestamp_period_ns() const { return timestamp_period_ns_; }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }

  // Validation messages (warning or error severity) since creation.
  size_t validation_message_count() const;
  std::vector<std::string> validation_messages() const;

  // Records with `record` into a one-time command buffer, submits it and waits.
  void immediate(const std::function<void(VkCommandBuffer)>& record);
  // Submits `cmd` alone to the queue signalling `fence`, waits for the fence and resets it.
  void submit_and_wait(VkCommandBuffer cmd, VkFence fence) const;
  // Waits for `fence` (signalled by a submission) and resets it.
  void wait_and_reset(VkFence fence) const;
  void wait_idle() const;

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  void create_instance(const ContextOptions& options);
  void pick_device(const ContextOptions& options);
  void create_device(bool swapchain);
  void destroy();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool immediate_pool_ = VK_NULL_HANDLE;
  VkFence immediate_fence_ = VK_NULL_HANDLE;
  std::unique_ptr<Allocator> allocator_;
  std::string device_name_;
  std::string driver_;
  VkPhysicalDeviceType device_type_ = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  VkPhysicalDeviceLimits limits_{};
  bool descriptor_indexing_ = false;
  bool depth_clamp_ = false;
  PFN_vkCmdBeginConditionalRenderingEXT begin_conditional_ = nullptr;
  PFN_vkCmdEndConditionalRenderingEXT end_conditional_ = nullptr;
  bool primitive_id_ = false;
  bool occlusion_query_precise_ = false;
  bool pipeline_statistics_ = false;
  bool quad_counting_ = false;
  float timestamp_period_ns_ = 0.0f;
  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

}  // namespace illum::gpu
