// Device-memory sub-allocation (VMA is not packaged). Per memory type, memory comes in
// blocks of kBlockSize, each managed by a sorted free list with first fit and merging of
// neighbours on free; requests larger than a quarter block, and images the driver prefers
// to have memory of their own (VkMemoryDedicatedRequirements: render targets, where that
// can keep them compressed), get a dedicated allocation.
// Host-visible blocks stay persistently mapped.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace illum::gpu {

struct Allocation {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // host pointer at `offset` for host-visible memory, else null
  uint32_t memory_type = 0;
  int block = -1;  // index of the owning block; −1 = dedicated
  bool valid() const { return memory != VK_NULL_HANDLE; }
};

struct AllocatorStats {
  size_t blocks = 0;
  size_t dedicated = 0;
  VkDeviceSize reserved_bytes = 0;  // device memory held
  VkDeviceSize used_bytes = 0;      // handed out to resources
};

// The memory type for an image (textures, render targets): a DEVICE_LOCAL one, never a
// silent fall-back to host memory, which would put every pass that touches the image on
// the bus. A software device (lavapipe: the "device" is the CPU, all its memory is host
// memory) is accepted explicitly with `software_device`: then any type fits, DEVICE_LOCAL
// preferred. Throws illum::Error naming `what` and `device` when no type fits.
uint32_t image_memory_type(const VkPhysicalDeviceMemoryProperties& properties, uint32_t type_bits,
                           bool software_device, const std::string& what,
                           const std::string& device);

class Allocator {
 public:
  static constexpr VkDeviceSize kBlockSize = VkDeviceSize(64) << 20;

  Allocator(VkPhysicalDevice physical, VkDevice device);
  ~Allocator();
  Allocator(const Allocator&) = delete;
  Allocator& operator=(const Allocator&) = delete;

  // `required` must hold, `preferred` is tried first (e.g. DEVICE_LOCAL). Throws
  // illum::Error when no memory type fits or the device is out of memory.
  Allocation allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required,
                      VkMemoryPropertyFlags preferred = 0);
  // Allocates from memory type `type` (image_memory_type's choice); memory of its own, bound
  // to `dedicated_image` alone, when that is given (the driver prefers it for the image).
  Allocation allocate_type(const VkMemoryRequirements& requirements, uint32_t type,
                           VkImage dedicated_image = VK_NULL_HANDLE);
  void free(Allocation& allocation);

  AllocatorStats stats() const;
  bool is_host_coherent(uint32_t memory_type) const;
  const VkPhysicalDeviceMemoryProperties& properties() const { return properties_; }

 private:
  struct Range {
    VkDeviceSize offset, size;
  };
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    uint32_t memory_type = 0;
    void* mapped = nullptr;
    std::map<VkDeviceSize, VkDeviceSize> free;  // offset → size, non-adjacent ranges
  };
  int find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;
  VkDeviceMemory allocate_memory(uint32_t type, VkDeviceSize size, void** mapped,
                                 VkImage dedicated_image);

  VkPhysicalDevice physical_;
  VkDevice device_;
  VkPhysicalDeviceMemoryProperties properties_{};
  VkDeviceSize granularity_ = 1;
  mutable std::mutex mutex_;
  std::vector<Block> blocks_;
  size_t dedicated_ = 0;
  VkDeviceSize dedicated_bytes_ = 0, used_bytes_ = 0;
};

}  // namespace illum::gpu
