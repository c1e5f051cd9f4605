// GPU images (textures, render targets, cube maps, 3-D volumes) with sub-allocated memory.
// Each image remembers the layout of every subresource (mip × layer) and its last access,
// so transition() can emit correct synchronization2 barriers on the single graphics queue
// even after passes left its mip levels in different layouts (a pyramid built level by
// level).
#pragma once

#include <vector>

#include <vulkan/vulkan.h>

#include "illum/core/image.h"
#include "illum/gpu/context.h"

namespace illum::gpu {

struct ImageDesc {
  uint32_t width = 1, height = 1;
  uint32_t depth = 1;   // > 1: a 3-D image (one layer), viewed and sampled as sampler3D
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
// The levels of a full mip chain down to 1 texel: 1 + floor(log2(max side)).
uint32_t mip_chain_length(uint32_t width, uint32_t height, uint32_t depth = 1);
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
  VkImageView view() const { return view_; }  // all mips and layers (2D, array, cube, 3-D)
  // One layer, all aspects: the view to render into (cube faces, depth-stencil targets).
  VkImageView layer_view(uint32_t layer) const { return layer_views_.at(layer); }
  // One mip level, all layers, the view type of view(): a level to write as a storage
  // image or to read alone while its neighbours are in other layouts.
  VkImageView mip_view(uint32_t mip) const { return mips_ > 1 ? mip_views_.at(mip) : view_; }
  const ImageDesc& desc() const { return desc_; }
  // The memory type it was placed in (allocator.h: image_memory_type's choice).
  uint32_t memory_type() const { return allocation_.memory_type; }
  VkExtent2D extent() const { return {desc_.width, desc_.height}; }
  VkImageAspectFlags aspect() const;
  // The layout shared by every subresource; VK_IMAGE_LAYOUT_MAX_ENUM when they differ.
  VkImageLayout layout() const;
  VkImageLayout layout(uint32_t mip, uint32_t layer) const {
    return layouts_.at(static_cast<size_t>(mip) * desc_.layers + layer);
  }
  // The stages and accesses of the last recorded use (the source of the next barrier).
  VkPipelineStageFlags2 stage() const { return stage_; }
  VkAccessFlags2 access() const { return access_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

  // Barriers from the last recorded use to (layout, stage, access); all mips and layers
  // (one barrier per run of subresources that share their old layout).
  void transition(VkCommandBuffer cmd, VkImageLayout layout, VkPipelineStageFlags2 stage,
                  VkAccessFlags2 access);
  // Records that a barrier recorded elsewhere (the frame graph's) left `range` (all of the
  // image without one) in this state, so later transition(), upload() and readback() start
  // from it. A partial range adds its stages and accesses to the image's last use: a later
  // whole-image barrier then waits for every part.
  void assume_state(VkImageLayout layout, VkPipelineStageFlags2 stage, VkAccessFlags2 access);
  void assume_state(const VkImageSubresourceRange& range, VkImageLayout layout,
                    VkPipelineStageFlags2 stage, VkAccessFlags2 access);

  // Fills mip 0 of layer `layer` from `image` (converted to the image's format), builds the
  // remaining mips by blits, and leaves the image SHADER_READ_ONLY.
  void upload(const Image& image, uint32_t layer = 0);
  // Copies mip level `mip` of `layer` (of a 3-D image: depth slice `layer` of that level)
  // back into an illum::Image (RGBA or R per the format; depth gives one channel) of that
  // level's size, max(1, side >> mip). Every subresource keeps its layout. Waits for the GPU.
  Image readback(uint32_t layer = 0, VkImageAspectFlags aspect = 0, uint32_t mip = 0);

  void reset();

 private:
  // Barriers taking every subresource from its layout to to[i].
  void transition_each(VkCommandBuffer cmd, const std::vector<VkImageLayout>& to,
                       VkPipelineStageFlags2 stage, VkAccessFlags2 access);

  Context* context_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  std::vector<VkImageView> layer_views_;
  std::vector<VkImageView> mip_views_;  // with more than one mip
  Allocation allocation_;
  ImageDesc desc_;
  uint32_t mips_ = 0;
  std::vector<VkImageLayout> layouts_;  // per subresource: mip * layers + layer
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
