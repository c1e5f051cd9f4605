#include "illum/gpu/allocator.h"

#include <algorithm>

#include <fmt/format.h>

#include "illum/gpu/vk_check.h"

namespace illum::gpu {

namespace {
VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) {
  return (v + a - 1) / a * a;
}
}  // namespace

Allocator::Allocator(VkPhysicalDevice physical, VkDevice device)
    : physical_(physical), device_(device) {
  vkGetPhysicalDeviceMemoryProperties(physical_, &properties_);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(physical_, &props);
  // Aligning every sub-allocation to the buffer/image granularity keeps linear and
  // optimal resources from sharing a page without tracking resource kinds per range.
  granularity_ = std::max<VkDeviceSize>(1, props.limits.bufferImageGranularity);
}

Allocator::~Allocator() {
  for (Block& b : blocks_)
    if (b.memory) vkFreeMemory(device_, b.memory, nullptr);
}

int Allocator::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < properties_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (properties_.memoryTypes[i].propertyFlags & flags) == flags)
      return static_cast<int>(i);
  return -1;
}

bool Allocator::is_host_coherent(uint32_t memory_type) const {
  return properties_.memoryTypes[memory_type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
}

VkDeviceMemory Allocator::allocate_memory(uint32_t type, VkDeviceSize size, void** mapped,
                                          VkImage dedicated_image) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = size;
  info.memoryTypeIndex = type;
  VkMemoryDedicatedAllocateInfo dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO};
  dedicated.image = dedicated_image;
  if (dedicated_image != VK_NULL_HANDLE) info.pNext = &dedicated;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  const VkResult r = vkAllocateMemory(device_, &info, nullptr, &memory);
  if (r != VK_SUCCESS)
    throw Error(
        fmt::format("GPU memory allocation of {} MiB failed ({})", size >> 20, to_string(r)));
  *mapped = nullptr;
  if (properties_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
    ILLUM_VK(vkMapMemory(device_, memory, 0, VK_WHOLE_SIZE, 0, mapped));
  return memory;
}

uint32_t image_memory_type(const VkPhysicalDeviceMemoryProperties& properties, uint32_t type_bits,
                           bool software_device, const std::string& what,
                           const std::string& device) {
  int any = -1;
  for (uint32_t i = 0; i < properties.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    if (properties.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) return i;
    if (any < 0) any = static_cast<int>(i);
  }
  if (software_device && any >= 0) return static_cast<uint32_t>(any);
  throw Error(fmt::format(
      "{}: device '{}' offers no DEVICE_LOCAL memory for it (render targets and textures are "
      "not placed in host memory)",
      what, device));
}

Allocation Allocator::allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                               VkMemoryPropertyFlags preferred) {
  int type = find_memory_type(req.memoryTypeBits, required | preferred);
  if (type < 0) type = find_memory_type(req.memoryTypeBits, required);
  if (type < 0) throw Error("no GPU memory type fits the resource");
  return allocate_type(req, static_cast<uint32_t>(type));
}

Allocation Allocator::allocate_type(const VkMemoryRequirements& req, uint32_t type,
                                    VkImage dedicated_image) {
  std::lock_guard lock(mutex_);
  Allocation a;
  a.memory_type = static_cast<uint32_t>(type);
  a.size = req.size;
  if (req.size > kBlockSize / 4 || dedicated_image != VK_NULL_HANDLE) {
    a.memory = allocate_memory(a.memory_type, req.size, &a.mapped, dedicated_image);
    ++dedicated_;
    dedicated_bytes_ += req.size;
    used_bytes_ += req.size;
    return a;
  }
  const VkDeviceSize alignment = std::max(req.alignment, granularity_);
  const VkDeviceSize size = align_up(req.size, granularity_);
  auto try_block = [&](int index) -> bool {
    Block& b = blocks_[static_cast<size_t>(index)];
    if (b.memory_type != a.memory_type) return false;
    for (auto it = b.free.begin(); it != b.free.end(); ++it) {
      const VkDeviceSize start = align_up(it->first, alignment);
      const VkDeviceSize end = it->first + it->second;
      if (start + size > end) continue;
      const VkDeviceSize range_start = it->first;
      b.free.erase(it);
      if (start > range_start) b.free[range_start] = start - range_start;
      if (start + size < end) b.free[start + size] = end - (start + size);
      a.memory = b.memory;
      a.offset = start;
      a.size = size;
      a.block = index;
      a.mapped = b.mapped ? static_cast<char*>(b.mapped) + start : nullptr;
      used_bytes_ += size;
      return true;
    }
    return false;
  };
  for (size_t i = 0; i < blocks_.size(); ++i)
    if (blocks_[i].memory && try_block(static_cast<int>(i))) return a;
  Block block;
  block.memory_type = a.memory_type;
  block.memory = allocate_memory(a.memory_type, kBlockSize, &block.mapped, VK_NULL_HANDLE);
  block.free[0] = kBlockSize;
  // Reuse a released slot so block indices held by live allocations stay valid.
  auto slot =
      std::find_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return !b.memory; });
  int index;
  if (slot != blocks_.end()) {
    *slot = std::move(block);
    index = static_cast<int>(slot - blocks_.begin());
  } else {
    blocks_.push_back(std::move(block));
    index = static_cast<int>(blocks_.size() - 1);
  }
  ILLUM_CHECK(try_block(index), "a fresh block must fit {} bytes", size);
  return a;
}

void Allocator::free(Allocation& a) {
  if (!a.valid()) return;
  std::lock_guard lock(mutex_);
  used_bytes_ -= a.size;
  if (a.block < 0) {
    vkFreeMemory(device_, a.memory, nullptr);
    --dedicated_;
    dedicated_bytes_ -= a.size;
    a = Allocation{};
    return;
  }
  Block& b = blocks_[static_cast<size_t>(a.block)];
  VkDeviceSize offset = a.offset, size = a.size;
  auto next = b.free.lower_bound(offset);
  ILLUM_CHECK(next == b.free.end() || next->first >= offset + size, "double free of GPU memory");
  if (next != b.free.end() && next->first == offset + size) {  // merge with the following range
    size += next->second;
    next = b.free.erase(next);
  }
  if (next != b.free.begin()) {  // merge with the preceding range
    auto prev = std::prev(next);
    ILLUM_CHECK(prev->first + prev->second <= offset, "double free of GPU memory");
    if (prev->first + prev->second == offset) {
      offset = prev->first;
      size += prev->second;
      b.free.erase(prev);
    }
  }
  b.free[offset] = size;
  if (b.free.size() == 1 && b.free.begin()->second == kBlockSize) {  // empty: give it back
    vkFreeMemory(device_, b.memory, nullptr);
    b = Block{};
  }
  a = Allocation{};
}

AllocatorStats Allocator::stats() const {
  std::lock_guard lock(mutex_);
  AllocatorStats s;
  for (const Block& b : blocks_)
    if (b.memory) {
      ++s.blocks;
      s.reserved_bytes += kBlockSize;
    }
  s.dedicated = dedicated_;
  s.reserved_bytes += dedicated_bytes_;
  s.used_bytes = used_bytes_;
  return s;
}

}  // namespace illum::gpu
