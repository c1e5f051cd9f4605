#include "illum/gpu/descriptors.h"

#include <utility>

#include "illum/gpu/vk_check.h"

namespace illum::gpu {

DescriptorSetLayout::DescriptorSetLayout(Context& context,
                                         const std::vector<DescriptorBinding>& bindings)
    : context_(&context) {
  std::vector<VkDescriptorSetLayoutBinding> vk;
  std::vector<VkDescriptorBindingFlags> flags;
  bool any_flags = false;
  for (const DescriptorBinding& b : bindings) {
    vk.push_back({b.binding, b.type, b.count, b.stages, nullptr});
    VkDescriptorBindingFlags f = 0;
    if (b.variable) {
      ILLUM_CHECK(context.descriptor_indexing(),
                  "variable descriptor arrays need descriptor indexing");
      f = VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT |
          VK_DESCRIPTOR_BINDING_VARIABLE_DESCRIPTOR_COUNT_BIT;
      any_flags = true;
    }
    flags.push_back(f);
  }
  VkDescriptorSetLayoutBindingFlagsCreateInfo flag_info{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  flag_info.bindingCount = static_cast<uint32_t>(flags.size());
  flag_info.pBindingFlags = flags.data();
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.pNext = any_flags ? &flag_info : nullptr;
  info.bindingCount = static_cast<uint32_t>(vk.size());
  info.pBindings = vk.data();
  ILLUM_VK(vkCreateDescriptorSetLayout(context.device(), &info, nullptr, &layout_));
}

DescriptorSetLayout& DescriptorSetLayout::operator=(DescriptorSetLayout&& o) noexcept {
  if (this != &o) {
    reset();
    context_ = std::exchange(o.context_, nullptr);
    layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
  }
  return *this;
}

void DescriptorSetLayout::reset() {
  if (context_ && layout_) vkDestroyDescriptorSetLayout(context_->device(), layout_, nullptr);
  layout_ = VK_NULL_HANDLE;
  context_ = nullptr;
}

DescriptorAllocator::~DescriptorAllocator() {
  for (VkDescriptorPool p : pools_) vkDestroyDescriptorPool(context_->device(), p, nullptr);
}

VkDescriptorPool DescriptorAllocator::new_pool() {
  const VkDescriptorPoolSize sizes[] = {
      {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 256},
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 256},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4096},
      {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 256},
  };
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = 128;
  info.poolSizeCount = static_cast<uint32_t>(std::size(sizes));
  info.pPoolSizes = sizes;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  ILLUM_VK(vkCreateDescriptorPool(context_->device(), &info, nullptr, &pool));
  pools_.push_back(pool);
  return pool;
}

VkDescriptorSet DescriptorAllocator::allocate(const DescriptorSetLayout& layout,
                                              uint32_t variable_count) {
  VkDescriptorSetVariableDescriptorCountAllocateInfo variable{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_VARIABLE_DESCRIPTOR_COUNT_ALLOCATE_INFO};
  variable.descriptorSetCount = 1;
  variable.pDescriptorCounts = &variable_count;
  VkDescriptorSetLayout handle = layout.handle();
  VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  info.pNext = variable_count ? &variable : nullptr;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &handle;
  VkDescriptorSet set = VK_NULL_HANDLE;
  if (!pools_.empty()) {
    info.descriptorPool = pools_.back();
    const VkResult r = vkAllocateDescriptorSets(context_->device(), &info, &set);
    if (r == VK_SUCCESS) return set;
    if (r != VK_ERROR_OUT_OF_POOL_MEMORY && r != VK_ERROR_FRAGMENTED_POOL) ILLUM_VK(r);
  }
  info.descriptorPool = new_pool();
  ILLUM_VK(vkAllocateDescriptorSets(context_->device(), &info, &set));
  return set;
}

DescriptorWriter& DescriptorWriter::buffer(VkDescriptorSet set, uint32_t binding,
                                           VkDescriptorType type, VkBuffer buffer,
                                           VkDeviceSize range) {
  buffers_.push_back({buffer, 0, range});
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = &buffers_.back();
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::image(VkDescriptorSet set, uint32_t binding,
                                          VkDescriptorType type, VkImageView view,
                                          VkSampler sampler, VkImageLayout layout,
                                          uint32_t array_element) {
  images_.push_back({sampler, view, layout});
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.dstArrayElement = array_element;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pImageInfo = &images_.back();
  writes_.push_back(w);
  return *this;
}

void DescriptorWriter::commit(VkDevice device) {
  if (!writes_.empty())
    vkUpdateDescriptorSets(device, static_cast<uint32_t>(writes_.size()), writes_.data(), 0,
                           nullptr);
  writes_.clear();
  buffers_.clear();
  images_.clear();
}

}  // namespace illum::gpu
