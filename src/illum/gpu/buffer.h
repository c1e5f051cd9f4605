// GPU buffers with sub-allocated memory. kDevice buffers are filled through a staging copy
// (upload()); kUpload and kReadback buffers are persistently mapped.
#pragma once

#include <cstddef>
#include <span>

#include <vulkan/vulkan.h>

#include "illum/gpu/context.h"

namespace illum::gpu {

enum class MemoryUsage {
  kDevice,    // device-local, GPU only
  kUpload,    // host-visible, written by the CPU every frame (uniforms, staging)
  kReadback,  // host-visible, preferably cached, read by the CPU
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory);
  ~Buffer() { reset(); }
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
  void* mapped() const { return allocation_.mapped; }

  // Host-visible buffers only: copy in / out (flushing or invalidating non-coherent memory).
  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void read(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  // Any buffer with TRANSFER_DST: copies through a staging buffer and waits.
  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);

  void reset();

 private:
  Context* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  Allocation allocation_;
};

// One synchronization2 global memory barrier (buffers and other non-image resources).
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// A device-local buffer holding `bytes` (usage gets TRANSFER_DST added).
Buffer make_device_buffer(Context& context, const void* data, VkDeviceSize bytes,
                          VkBufferUsageFlags usage);

template <typename T>
Buffer make_device_buffer(Context& context, std::span<const T> data, VkBufferUsageFlags usage) {
  return make_device_buffer(context, data.data(), data.size_bytes(), usage);
}

}  // namespace illum::gpu
