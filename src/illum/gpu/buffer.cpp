#include "illum/gpu/buffer.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "illum/gpu/vk_check.h"

namespace illum::gpu {

Buffer::Buffer(Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory)
    : context_(&context), size_(std::max<VkDeviceSize>(size, 4)) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size_;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ILLUM_VK(vkCreateBuffer(context.device(), &info, nullptr, &buffer_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(context.device(), buffer_, &req);
  VkMemoryPropertyFlags required = 0, preferred = 0;
  switch (memory) {
    case MemoryUsage::kDevice:
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
    case MemoryUsage::kUpload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
      break;
    case MemoryUsage::kReadback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
  }
  try {
    allocation_ = context.allocator().allocate(req, required, preferred);
    ILLUM_VK(vkBindBufferMemory(context.device(), buffer_, allocation_.memory, allocation_.offset));
  } catch (...) {
    reset();
    throw;
  }
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    allocation_ = std::exchange(other.allocation_, Allocation{});
  }
  return *this;
}

void Buffer::reset() {
  if (!context_) return;
  if (buffer_) vkDestroyBuffer(context_->device(), buffer_, nullptr);
  context_->allocator().free(allocation_);
  buffer_ = VK_NULL_HANDLE;
  context_ = nullptr;
  size_ = 0;
}

void Buffer::write(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  ILLUM_CHECK(allocation_.mapped && offset + bytes <= size_,
              "write to an unmapped or short buffer");
  std::memcpy(static_cast<char*>(allocation_.mapped) + offset, data, bytes);
  if (!context_->allocator().is_host_coherent(allocation_.memory_type)) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = allocation_.memory;
    range.offset = allocation_.offset;
    range.size = VK_WHOLE_SIZE;
    ILLUM_VK(vkFlushMappedMemoryRanges(context_->device(), 1, &range));
  }
}

void Buffer::read(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  ILLUM_CHECK(allocation_.mapped && offset + bytes <= size_,
              "read from an unmapped or short buffer");
  if (!context_->allocator().is_host_coherent(allocation_.memory_type)) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = allocation_.memory;
    range.offset = allocation_.offset;
    range.size = VK_WHOLE_SIZE;
    ILLUM_VK(vkInvalidateMappedMemoryRanges(context_->device(), 1, &range));
  }
  std::memcpy(data, static_cast<const char*>(allocation_.mapped) + offset, bytes);
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (allocation_.mapped) {
    write(data, bytes, offset);
    return;
  }
  Buffer staging(*context_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::kUpload);
  staging.write(data, bytes);
  context_->immediate([&](VkCommandBuffer cmd) {
    VkBufferCopy copy{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer_, 1, &copy);
  });
}

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

Buffer make_device_buffer(Context& context, const void* data, VkDeviceSize bytes,
                          VkBufferUsageFlags usage) {
  Buffer buffer(context, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::kDevice);
  buffer.upload(data, bytes);
  return buffer;
}

}  // namespace illum::gpu
