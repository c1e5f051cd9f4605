// Descriptor set layouts, one growable pool and a batched writer. With descriptor
// indexing, a binding may be a variable-size, partially bound array (bindless textures).
#pragma once

#include <deque>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/context.h"

namespace illum::gpu {

struct DescriptorBinding {
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  uint32_t count = 1;     // array size (upper bound when `variable`)
  bool variable = false;  // variable count + partially bound (last binding only)
  VkShaderStageFlags stages = VK_SHADER_STAGE_ALL;
};

class DescriptorSetLayout {
 public:
  DescriptorSetLayout() = default;
  DescriptorSetLayout(Context& context, const std::vector<DescriptorBinding>& bindings);
  ~DescriptorSetLayout() { reset(); }
  DescriptorSetLayout(DescriptorSetLayout&& o) noexcept { *this = std::move(o); }
  DescriptorSetLayout& operator=(DescriptorSetLayout&& o) noexcept;
  DescriptorSetLayout(const DescriptorSetLayout&) = delete;
  DescriptorSetLayout& operator=(const DescriptorSetLayout&) = delete;
  VkDescriptorSetLayout handle() const { return layout_; }
  void reset();

 private:
  Context* context_ = nullptr;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
};

// Allocates sets from a chain of pools; a new pool is added when one runs out.
class DescriptorAllocator {
 public:
  explicit DescriptorAllocator(Context& context) : context_(&context) {}
  ~DescriptorAllocator();
  DescriptorAllocator(const DescriptorAllocator&) = delete;
  DescriptorAllocator& operator=(const DescriptorAllocator&) = delete;
  VkDescriptorSet allocate(const DescriptorSetLayout& layout, uint32_t variable_count = 0);

 private:
  VkDescriptorPool new_pool();
  Context* context_;
  std::vector<VkDescriptorPool> pools_;
};

// Collects writes and applies them in one vkUpdateDescriptorSets call.
class DescriptorWriter {
 public:
  DescriptorWriter& buffer(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                           VkBuffer buffer, VkDeviceSize range = VK_WHOLE_SIZE);
  DescriptorWriter& image(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                          VkImageView view, VkSampler sampler, VkImageLayout layout,
                          uint32_t array_element = 0);
  void commit(VkDevice device);

 private:
  std::deque<VkDescriptorBufferInfo> buffers_;  // deque: stable addresses
  std::deque<VkDescriptorImageInfo> images_;
  std::vector<VkWriteDescriptorSet> writes_;
};

}  // namespace illum::gpu
