// The frame graph's synchronization rules, apart from its bookkeeping (frame_graph.cpp):
// what layout, stages and accesses each use needs, and when a resource's state calls for a
// barrier before the next use.
#include "illum/core/error.h"
#include "illum/gpu/gpu_image.h"
#include "illum/realtime/frame_graph.h"

namespace illum::realtime {

namespace {

constexpr Uses kWriteUses =
    kStorageWrite | kColorAttachment | kDepthAttachment | kDepthReadOnly | kTransferDst;
constexpr VkAccessFlags2 kWriteAccess = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                        VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                        VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT;
constexpr VkPipelineStageFlags2 kFragmentTests =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;

}  // namespace

Access Access::mips(uint32_t base, uint32_t count) const {
  Access a = *this;
  a.base_mip = base;
  a.mip_count = count;
  return a;
}

Access Access::layers(uint32_t base, uint32_t count) const {
  Access a = *this;
  a.base_layer = base;
  a.layer_count = count;
  return a;
}

Access Access::if_produced() const {
  Access a = *this;
  a.optional = true;
  return a;
}

bool Access::same_range(const Access& o) const {
  return base_mip == o.base_mip && mip_count == o.mip_count && base_layer == o.base_layer &&
         layer_count == o.layer_count;
}

void merge_access(std::vector<Access>* accesses, const Access& access) {
  for (Access& a : *accesses)
    if (a.resource == access.resource && a.same_range(access)) {
      a.uses |= access.uses;
      a.shaders |= access.shaders;
      return;
    }
  accesses->push_back(access);
}

bool writes(Uses uses) {
  return (uses & kWriteUses) != 0;
}

bool is_depth_format(VkFormat f) {
  return gpu::is_depth_format(f);
}

UseState use_state(Uses uses, VkPipelineStageFlags2 shaders, bool image, bool depth) {
  UseState s;
  s.write = writes(uses);
  // The layout every image use asks for; two uses in one access must agree.
  auto want = [&](VkImageLayout layout) {
    if (!image) return;
    ILLUM_CHECK(s.layout == VK_IMAGE_LAYOUT_UNDEFINED || s.layout == layout,
                "one access asks for two image layouts ({} and {})", static_cast<int>(s.layout),
                static_cast<int>(layout));
    s.layout = layout;
  };
  if (uses & kDepthReadOnly) {
    want(VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL);
    s.stages |= kFragmentTests;
    s.access |= VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  }
  if (uses & kSampled) {
    // A sampled depth buffer stays in the read-only depth layout the light passes also
    // test it in (descriptors are written with that layout).
    if (!(uses & kDepthReadOnly))
      want(depth ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
                 : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    s.stages |= shaders;
    s.access |= VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
  }
  if (uses & (kStorageRead | kStorageWrite)) {
    want(VK_IMAGE_LAYOUT_GENERAL);
    s.stages |= shaders;
    if (uses & kStorageRead) s.access |= VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
    if (uses & kStorageWrite) s.access |= VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  }
  if (uses & kColorAttachment) {
    want(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    s.stages |= VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    s.access |= VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  }
  if (uses & kDepthAttachment) {
    want(VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    s.stages |= kFragmentTests;
    s.access |= VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  }
  if (uses & (kTransferSrc | kTransferDst)) {
    ILLUM_CHECK(!((uses & kTransferSrc) && (uses & kTransferDst) && image),
                "an image access cannot be both transfer source and destination");
    want(uses & kTransferSrc ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
                             : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    s.stages |= VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
    if (uses & kTransferSrc) s.access |= VK_ACCESS_2_TRANSFER_READ_BIT;
    if (uses & kTransferDst) s.access |= VK_ACCESS_2_TRANSFER_WRITE_BIT;
  }
  if (uses & kVertexInput) {
    ILLUM_CHECK(!image, "vertex input from an image");
    s.stages |= VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
    s.access |= VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT;
  }
  if (uses & kIndirectArgs) {
    ILLUM_CHECK(!image, "indirect arguments from an image");
    s.stages |= VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
    s.access |= VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
  }
  ILLUM_CHECK(uses != 0 && s.stages != VK_PIPELINE_STAGE_2_NONE, "an access without a use");
  return s;
}

std::optional<Barrier> barrier_for(ResourceState* state, const UseState& next, bool image) {
  const bool layout_change = image && state->layout != next.layout;
  const bool after_write = (state->access & kWriteAccess) != 0;
  const bool uncovered = (next.stages & ~state->stages) != 0 || (next.access & ~state->access) != 0;
  const bool untouched = state->stages == VK_PIPELINE_STAGE_2_NONE;
  if (!layout_change && !next.write && !after_write && !uncovered) {
    return std::nullopt;  // read after reads the last barrier covered
  }
  if (!layout_change && untouched) {
    // A buffer's first use: nothing before it to wait for.
    state->stages = next.stages;
    state->access = next.access;
    return std::nullopt;
  }
  // Otherwise a barrier; for a read by new stages its source is the stages the last one
  // covered, which chains it to the last write.
  Barrier b;
  b.old_layout = state->layout;
  b.new_layout = image ? next.layout : VK_IMAGE_LAYOUT_UNDEFINED;
  b.src_stages = state->stages;
  b.src_access = state->access & kWriteAccess;  // only writes need to be made available
  b.dst_stages = next.stages;
  b.dst_access = next.access;
  state->layout = b.new_layout;
  if (!layout_change && !after_write && !next.write) {
    // Visibility for more readers: the readers before stay covered.
    state->stages |= next.stages;
    state->access |= next.access;
  } else {
    state->stages = next.stages;
    state->access = next.access;
  }
  return b;
}

}  // namespace illum::realtime
