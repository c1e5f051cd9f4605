// GPU images (textures, render targets, cube maps) with sub-allocated memory. Each image
// remembers its current layout and last access so transition() can emit a correct
// synchronization2 barrier on the single graphics queue.
#pragma once

#include <vector>

#include <vulkan/vulkan.h>

#include "illum/core/image.h"
#include "illum/gpu/context.h"

namespace illum::gpu {

struct ImageDesc {
  uint32_t width = 1, height = 1;
  uint32_t layers = 1;  // 6 for a cube map, 6·n for a cube-map array
  uint32_t mips = 1;
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT;
  bool cube = false;
  bool cube_array = false;  // cube: view as samplerCubeArray (layers = 6·n)
  bool array = false;       // view as a 2D array even with one layer
};

bool is_depth_format(VkFormat format);
bool has_stencil(VkFormat format);
uint32_t format_bytes(VkFormat format);  // per texel, for the colour formats illum uses
// "rgba16f", "d32s8", ...: the formats illum renders to, short ("?" for others).
const char* format_name(VkFormat format);

// One synchronization2 image barrier over `range` (layout change plus execution and memory
// dependency). GpuImage::transition uses it with the tracked state; swapchain images, which
// GpuImage does not own, call it directly.
void image_barrier(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                   VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src_stage,
                   VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access);

class GpuImage {
 public:
  GpuImage() = default;
  GpuImage(Context& context, const ImageDesc& desc);
  ~GpuImage() { reset(); }
  GpuImage(GpuImage&& other) noexcept { *this = std::move(other); }
  GpuImage& operator=(GpuImage&& other) noexcept;
  GpuImage(const GpuImage&) = delete;
  GpuImage& operator=(const GpuImage&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }  // all layers (2D, 2D array or cube)
  // One layer, all aspects: the view to render into (cube faces, depth-stencil targets).
  VkImageView layer_view(uint32_t layer) const { return layer_views_.at(layer); }
  const ImageDesc& desc() const { return desc_; }
  // The memory type it was placed in (allocator.h: image_memory_type's choice).
  uint32_t memory_type() const { return allocation_.memory_type; }
  VkExtent2D extent() const { return {desc_.width, desc_.height}; }
  VkImageAspectFlags aspect() const;
  VkImageLayout layout() const { return layout_; }
  // The stages and accesses of the last recorded use (the source of the next barrier).
  VkPipelineStageFlags2 stage() const { return stage_; }
  VkAccessFlags2 access() const { return access_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

  // Barrier from the last recorded use to (layout, stage, access); all mips and layers.
  void transition(VkCommandBuffer cmd, VkImageLayout layout, VkPipelineStageFlags2 stage,
                  VkAccessFlags2 access);
  // Records that a barrier recorded elsewhere (the frame graph's) left the image in this
  // state, so later transition(), upload() and readback() start from it.
  void assume_state(VkImageLayout layout, VkPipelineStageFlags2 stage, VkAccessFlags2 access) {
    layout_ = layout;
    stage_ = stage;
    access_ = access;
  }

  // Fills mip 0 of layer `layer` from `image` (converted to the image's format), builds the
  // remaining mips by blits, and leaves the image SHADER_READ_ONLY.
  void upload(const Image& image, uint32_t layer = 0);
  // Copies mip level `mip` of `layer` back into an illum::Image (RGBA or R per the format;
  // depth gives one channel) of that level's size, max(1, side >> mip). Waits for the GPU.
  Image readback(uint32_t layer = 0, VkImageAspectFlags aspect = 0, uint32_t mip = 0);

  void reset();

 private:
  Context* context_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  std::vector<VkImageView> layer_views_;
  Allocation allocation_;
  ImageDesc desc_;
  VkImageLayout layout_ = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stage_ = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access_ = VK_ACCESS_2_NONE;
};

class Sampler {
 public:
  Sampler() = default;
  Sampler(Context& context, VkFilter filter, VkSamplerAddressMode address, bool mipmaps = false,
          bool compare = false);
  ~Sampler() { reset(); }
  Sampler(Sampler&& other) noexcept { *this = std::move(other); }
  Sampler& operator=(Sampler&& other) noexcept;
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;
  VkSampler handle() const { return sampler_; }
  void reset();

 private:
  Context* context_ = nullptr;
  VkSampler sampler_ = VK_NULL_HANDLE;
};

// The first depth-stencil format the device can render to (D32S8 or D24S8).
VkFormat pick_depth_stencil_format(const Context& context);

}  // namespace illum::gpu
