#include "illum/gpu/gpu_image.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "illum/core/color.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/vk_check.h"

namespace illum::gpu {

const char* format_name(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R8G8B8A8_UNORM:
      return "rgba8";
    case VK_FORMAT_R8G8B8A8_SRGB:
      return "srgba8";
    case VK_FORMAT_R16G16B16A16_SFLOAT:
      return "rgba16f";
    case VK_FORMAT_R32_SFLOAT:
      return "r32f";
    case VK_FORMAT_R32G32_SFLOAT:
      return "rg32f";
    case VK_FORMAT_R32_UINT:
      return "r32ui";
    case VK_FORMAT_R32G32B32A32_UINT:
      return "rgba32ui";
    case VK_FORMAT_D32_SFLOAT:
      return "d32";
    case VK_FORMAT_D16_UNORM:
      return "d16";
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return "d32s8";
    case VK_FORMAT_D24_UNORM_S8_UINT:
      return "d24s8";
    default:
      return "?";
  }
}

bool is_depth_format(VkFormat f) {
  return f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D32_SFLOAT_S8_UINT ||
         f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D16_UNORM;
}

bool has_stencil(VkFormat f) {
  return f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_D24_UNORM_S8_UINT;
}

uint32_t format_bytes(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_D32_SFLOAT:
      return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
      return 16;
    case VK_FORMAT_D16_UNORM:
      return 2;
    case VK_FORMAT_R8_UINT:
    case VK_FORMAT_S8_UINT:
      return 1;
    default:
      throw InternalError("format_bytes: unsupported format");
  }
}

namespace {
int format_channels(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_S8_UINT:
      return 1;
    case VK_FORMAT_R32G32_SFLOAT:
      return 2;
    default:
      return 4;
  }
}
}  // namespace

uint32_t mip_chain_length(uint32_t width, uint32_t height, uint32_t depth) {
  uint32_t side = std::max({width, height, depth, 1u}), levels = 1;
  while (side > 1) {
    side /= 2;
    ++levels;
  }
  return levels;
}

GpuImage::GpuImage(Context& context, const ImageDesc& desc)
    : context_(&context), desc_(desc), mips_(desc.mips) {
  const bool volume = desc.depth > 1;
  ILLUM_CHECK(!volume || (desc.layers == 1 && !desc.cube && !desc.array),
              "a 3-D image has one layer and is neither a cube nor an array");
  ILLUM_CHECK(desc.mips >= 1 && desc.mips <= mip_chain_length(desc.width, desc.height, desc.depth),
              "{} mip levels for a {}x{}x{} image", desc.mips, desc.width, desc.height, desc.depth);
  layouts_.assign(static_cast<size_t>(desc.mips) * desc.layers, VK_IMAGE_LAYOUT_UNDEFINED);
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.flags = desc.cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
  info.imageType = volume ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  info.format = desc.format;
  info.extent = {desc.width, desc.height, desc.depth};
  info.mipLevels = desc.mips;
  info.arrayLayers = desc.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = desc.usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  ILLUM_VK(vkCreateImage(context.device(), &info, nullptr, &image_));
  try {
    VkImageMemoryRequirementsInfo2 which{VK_STRUCTURE_TYPE_IMAGE_MEMORY_REQUIREMENTS_INFO_2};
    which.image = image_;
    VkMemoryDedicatedRequirements dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_REQUIREMENTS};
    VkMemoryRequirements2 req2{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    req2.pNext = &dedicated;
    vkGetImageMemoryRequirements2(context.device(), &which, &req2);
    const VkMemoryRequirements& req = req2.memoryRequirements;
    const bool own = dedicated.prefersDedicatedAllocation || dedicated.requiresDedicatedAllocation;
    const uint32_t type = image_memory_type(
        context.allocator().properties(), req.memoryTypeBits, context.is_software(),
        fmt::format("image {}x{} {}", desc.width, desc.height, format_name(desc.format)),
        context.device_name());
    allocation_ = context.allocator().allocate_type(req, type, own ? image_ : VK_NULL_HANDLE);
    ILLUM_VK(vkBindImageMemory(context.device(), image_, allocation_.memory, allocation_.offset));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = image_;
    view.viewType =
        volume      ? VK_IMAGE_VIEW_TYPE_3D
        : desc.cube ? (desc.cube_array ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE)
        : desc.layers > 1 || desc.array ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                                        : VK_IMAGE_VIEW_TYPE_2D;
    view.format = desc.format;
    // Sampled views of depth-stencil images see depth only.
    view.subresourceRange = {
        is_depth_format(desc.format) ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : aspect(), 0,
        desc.mips, 0, desc.layers};
    ILLUM_VK(vkCreateImageView(context.device(), &view, nullptr, &view_));
    if (desc.mips > 1) {
      for (uint32_t m = 0; m < desc.mips; ++m) {
        VkImageViewCreateInfo level = view;
        level.subresourceRange.baseMipLevel = m;
        level.subresourceRange.levelCount = 1;
        VkImageView v = VK_NULL_HANDLE;
        ILLUM_VK(vkCreateImageView(context.device(), &level, nullptr, &v));
        mip_views_.push_back(v);
      }
    }
    // Depth-stencil images get per-layer views with both aspects for attachments; their
    // default view (sampling) sees depth only.
    if (desc.layers > 1 || has_stencil(desc.format)) {
      for (uint32_t l = 0; l < desc.layers; ++l) {
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.subresourceRange = {aspect(), 0, 1, l, 1};
        VkImageView v = VK_NULL_HANDLE;
        ILLUM_VK(vkCreateImageView(context.device(), &view, nullptr, &v));
        layer_views_.push_back(v);
      }
    } else {
      layer_views_.push_back(view_);
    }
  } catch (...) {
    reset();
    throw;
  }
}

GpuImage& GpuImage::operator=(GpuImage&& o) noexcept {
  if (this != &o) {
    reset();
    context_ = std::exchange(o.context_, nullptr);
    image_ = std::exchange(o.image_, VK_NULL_HANDLE);
    view_ = std::exchange(o.view_, VK_NULL_HANDLE);
    layer_views_ = std::move(o.layer_views_);
    o.layer_views_.clear();
    mip_views_ = std::move(o.mip_views_);
    o.mip_views_.clear();
    allocation_ = std::exchange(o.allocation_, Allocation{});
    desc_ = o.desc_;
    mips_ = std::exchange(o.mips_, 0);
    layouts_ = std::move(o.layouts_);
    o.layouts_.clear();
    stage_ = o.stage_;
    access_ = o.access_;
  }
  return *this;
}

void GpuImage::reset() {
  if (!context_) return;
  VkDevice d = context_->device();
  for (VkImageView v : layer_views_)
    if (v != view_) vkDestroyImageView(d, v, nullptr);
  layer_views_.clear();
  for (VkImageView v : mip_views_) vkDestroyImageView(d, v, nullptr);
  mip_views_.clear();
  if (view_) vkDestroyImageView(d, view_, nullptr);
  if (image_) vkDestroyImage(d, image_, nullptr);
  context_->allocator().free(allocation_);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  context_ = nullptr;
  layouts_.clear();
  mips_ = 0;
}

VkImageLayout GpuImage::layout() const {
  if (layouts_.empty()) return VK_IMAGE_LAYOUT_UNDEFINED;
  for (VkImageLayout l : layouts_)
    if (l != layouts_.front()) return VK_IMAGE_LAYOUT_MAX_ENUM;
  return layouts_.front();
}

VkImageAspectFlags GpuImage::aspect() const {
  if (!is_depth_format(desc_.format)) return VK_IMAGE_ASPECT_COLOR_BIT;
  return has_stencil(desc_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT
                                   : VK_IMAGE_ASPECT_DEPTH_BIT;
}

void image_barrier(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                   VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src_stage,
                   VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = range;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void GpuImage::transition(VkCommandBuffer cmd, VkImageLayout layout, VkPipelineStageFlags2 stage,
                          VkAccessFlags2 access) {
  transition_each(cmd, std::vector<VkImageLayout>(layouts_.size(), layout), stage, access);
}

void GpuImage::transition_each(VkCommandBuffer cmd, const std::vector<VkImageLayout>& to,
                               VkPipelineStageFlags2 stage, VkAccessFlags2 access) {
  const VkPipelineStageFlags2 src =
      stage_ == VK_PIPELINE_STAGE_2_NONE ? VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT : stage_;
  // Runs of layers of one level with the same (old, new) layouts, merged with the same run
  // of the level above: a uniform image takes one barrier.
  struct Run {
    VkImageSubresourceRange range;
    VkImageLayout from, to;
  };
  std::vector<Run> runs;
  const uint32_t layers = desc_.layers;
  for (uint32_t m = 0; m < mips_; ++m) {
    std::vector<Run> level;
    for (uint32_t l = 0; l < layers; ++l) {
      const size_t i = static_cast<size_t>(m) * layers + l;
      if (!level.empty() && level.back().from == layouts_[i] && level.back().to == to[i])
        ++level.back().range.layerCount;
      else
        level.push_back({{aspect(), m, 1, l, 1}, layouts_[i], to[i]});
    }
    for (const Run& r : level) {
      auto same = std::find_if(runs.begin(), runs.end(), [&](const Run& o) {
        return o.range.baseMipLevel + o.range.levelCount == m &&
               o.range.baseArrayLayer == r.range.baseArrayLayer &&
               o.range.layerCount == r.range.layerCount && o.from == r.from && o.to == r.to;
      });
      if (same != runs.end())
        ++same->range.levelCount;
      else
        runs.push_back(r);
    }
  }
  for (const Run& r : runs)
    image_barrier(cmd, image_, r.range, r.from, r.to, src, access_, stage, access);
  layouts_ = to;
  stage_ = stage;
  access_ = access;
}

void GpuImage::assume_state(VkImageLayout layout, VkPipelineStageFlags2 stage,
                            VkAccessFlags2 access) {
  std::fill(layouts_.begin(), layouts_.end(), layout);
  stage_ = stage;
  access_ = access;
}

void GpuImage::assume_state(const VkImageSubresourceRange& range, VkImageLayout layout,
                            VkPipelineStageFlags2 stage, VkAccessFlags2 access) {
  for (uint32_t m = range.baseMipLevel; m < range.baseMipLevel + range.levelCount; ++m)
    for (uint32_t l = range.baseArrayLayer; l < range.baseArrayLayer + range.layerCount; ++l)
      layouts_.at(static_cast<size_t>(m) * desc_.layers + l) = layout;
  const bool whole = range.levelCount == mips_ && range.layerCount == desc_.layers;
  stage_ = whole ? stage : stage_ | stage;
  access_ = whole ? access : access_ | access;
}

void GpuImage::upload(const Image& image, uint32_t layer) {
  ILLUM_CHECK(desc_.depth == 1, "GpuImage::upload fills 2-D images");
  ILLUM_CHECK(static_cast<uint32_t>(image.width()) == desc_.width &&
                  static_cast<uint32_t>(image.height()) == desc_.height,
              "upload size mismatch");
  const VkFormat f = desc_.format;
  const size_t texels = image.pixel_count();
  std::vector<uint8_t> bytes(texels * format_bytes(f));
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const size_t i = static_cast<size_t>(y) * image.width() + x;
      const float* p = image.pixel(x, y);
      float rgba[4] = {0, 0, 0, 1};
      const int c = image.channels();
      if (c == 1) {
        rgba[0] = rgba[1] = rgba[2] = p[0];
      } else {
        for (int k = 0; k < std::min(c, 4); ++k) rgba[k] = p[k];
      }
      switch (f) {
        case VK_FORMAT_R8G8B8A8_UNORM:
          for (int k = 0; k < 4; ++k)
            bytes[i * 4 + k] =
                static_cast<uint8_t>(std::clamp(rgba[k], 0.0f, 1.0f) * 255.0f + 0.5f);
          break;
        case VK_FORMAT_R8G8B8A8_SRGB:
          for (int k = 0; k < 4; ++k) {
            const float v = k < 3 ? srgb_encode(rgba[k]) : std::clamp(rgba[k], 0.0f, 1.0f);
            bytes[i * 4 + k] = static_cast<uint8_t>(v * 255.0f + 0.5f);
          }
          break;
        case VK_FORMAT_R32_SFLOAT:
          std::memcpy(&bytes[i * 4], rgba, 4);
          break;
        case VK_FORMAT_R32G32_SFLOAT:
          std::memcpy(&bytes[i * 8], rgba, 8);
          break;
        case VK_FORMAT_R32G32B32A32_SFLOAT:
          std::memcpy(&bytes[i * 16], rgba, 16);
          break;
        case VK_FORMAT_R16G16B16A16_SFLOAT: {
          const uint64_t packed = glm::packHalf4x16(glm::vec4(rgba[0], rgba[1], rgba[2], rgba[3]));
          std::memcpy(&bytes[i * 8], &packed, 8);
          break;
        }
        default:
          throw InternalError("GpuImage::upload: unsupported format");
      }
    }
  Buffer staging(*context_, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::kUpload);
  staging.write(bytes.data(), bytes.size());
  context_->immediate([&](VkCommandBuffer cmd) {
    transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
               VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1};
    copy.imageExtent = {desc_.width, desc_.height, 1};
    vkCmdCopyBufferToImage(cmd, staging.handle(), image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &copy);
    // Mips by successive linear blits: each level from the one above.
    int32_t w = static_cast<int32_t>(desc_.width), h = static_cast<int32_t>(desc_.height);
    for (uint32_t m = 1; m < desc_.mips; ++m) {
      image_barrier(cmd, image_, {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, 1, layer, 1},
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
      VkImageBlit blit{};
      blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, layer, 1};
      blit.srcOffsets[1] = {w, h, 1};
      w = std::max(1, w / 2);
      h = std::max(1, h / 2);
      blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, layer, 1};
      blit.dstOffsets[1] = {w, h, 1};
      vkCmdBlitImage(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image_,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
    }
    if (desc_.mips > 1) {  // bring the source levels back so the whole image shares a layout
      image_barrier(cmd, image_, {VK_IMAGE_ASPECT_COLOR_BIT, 0, desc_.mips - 1, layer, 1},
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    }
    transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  });
}

Image GpuImage::readback(uint32_t layer, VkImageAspectFlags aspect_mask, uint32_t mip) {
  const bool volume = desc_.depth > 1;
  ILLUM_CHECK(
      mip < desc_.mips && layer < (volume ? std::max(1u, desc_.depth >> mip) : desc_.layers),
      "readback of a level, layer or slice that does not exist");
  const uint32_t width = std::max(1u, desc_.width >> mip),
                 height = std::max(1u, desc_.height >> mip);
  if (aspect_mask == 0)
    aspect_mask =
        is_depth_format(desc_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  VkFormat f = desc_.format;
  if (aspect_mask == VK_IMAGE_ASPECT_STENCIL_BIT)
    f = VK_FORMAT_S8_UINT;
  else if (aspect_mask == VK_IMAGE_ASPECT_DEPTH_BIT && is_depth_format(f)) {
    ILLUM_CHECK(
        f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_D16_UNORM,
        "depth readback needs a d32 or d16 depth format");
    if (f != VK_FORMAT_D16_UNORM) f = VK_FORMAT_D32_SFLOAT;
  }
  const uint32_t texel = format_bytes(f);
  const VkDeviceSize bytes = VkDeviceSize(width) * height * texel;
  Buffer staging(*context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::kReadback);
  std::vector<VkImageLayout> previous = layouts_;
  for (VkImageLayout& l : previous)
    if (l == VK_IMAGE_LAYOUT_UNDEFINED) l = VK_IMAGE_LAYOUT_GENERAL;
  context_->immediate([&](VkCommandBuffer cmd) {
    transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
               VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {aspect_mask, mip, volume ? 0 : layer, 1};
    copy.imageOffset = {0, 0, volume ? static_cast<int32_t>(layer) : 0};
    copy.imageExtent = {width, height, 1};
    vkCmdCopyImageToBuffer(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1,
                           &copy);
    transition_each(cmd, previous, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::vector<uint8_t> raw(bytes);
  staging.read(raw.data(), bytes);
  const int channels = format_channels(f);
  Image out(static_cast<int>(width), static_cast<int>(height), channels);
  float* dst = out.data().data();
  const size_t n = out.pixel_count();
  for (size_t i = 0; i < n; ++i) {
    switch (f) {
      case VK_FORMAT_R8G8B8A8_UNORM:
      case VK_FORMAT_R8G8B8A8_SRGB:
        for (int k = 0; k < 4; ++k) dst[i * 4 + k] = raw[i * 4 + k] / 255.0f;
        break;
      case VK_FORMAT_R16G16B16A16_SFLOAT: {
        uint64_t packed;
        std::memcpy(&packed, &raw[i * 8], 8);
        const glm::vec4 v = glm::unpackHalf4x16(packed);
        for (int k = 0; k < 4; ++k) dst[i * 4 + k] = v[k];
        break;
      }
      case VK_FORMAT_S8_UINT:
        dst[i] = raw[i];
        break;
      case VK_FORMAT_D16_UNORM: {
        uint16_t d;
        std::memcpy(&d, &raw[i * 2], 2);
        dst[i] = d / 65535.0f;
        break;
      }
      default:
        std::memcpy(&dst[i * channels], &raw[i * texel], texel);
        break;
    }
  }
  return out;
}

Sampler::Sampler(Context& context, VkFilter filter, VkSamplerAddressMode address, bool mipmaps,
                 bool compare)
    : context_(&context) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = info.minFilter = filter;
  info.mipmapMode =
      filter == VK_FILTER_LINEAR ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = address;
  info.maxLod = mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
  info.compareEnable = compare ? VK_TRUE : VK_FALSE;
  info.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
  info.borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
  ILLUM_VK(vkCreateSampler(context.device(), &info, nullptr, &sampler_));
}

Sampler& Sampler::operator=(Sampler&& o) noexcept {
  if (this != &o) {
    reset();
    context_ = std::exchange(o.context_, nullptr);
    sampler_ = std::exchange(o.sampler_, VK_NULL_HANDLE);
  }
  return *this;
}

void Sampler::reset() {
  if (context_ && sampler_) vkDestroySampler(context_->device(), sampler_, nullptr);
  sampler_ = VK_NULL_HANDLE;
  context_ = nullptr;
}

VkFormat pick_depth_stencil_format(const Context& context) {
  for (VkFormat f : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(context.physical(), f, &props);
    if (props.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
  }
  throw Error("the Vulkan device has no depth-stencil attachment format");
}

}  // namespace illum::gpu
