#include "illum/realtime/occlusion_culling.h"

#include <algorithm>
#include <cstring>

#include "illum/core/log.h"
#include "illum/realtime/frame_resources.h"

namespace illum::realtime {

namespace {

// shaders/occlusion.glsl's push constants.
struct CullPush {
  glm::mat4 clip{1.0f};
  glm::uvec4 config{0u};
  glm::uvec4 extent{0u};
};

constexpr VkPipelineStageFlags2 kPredicate = VK_PIPELINE_STAGE_2_CONDITIONAL_RENDERING_BIT_EXT;
constexpr VkAccessFlags2 kPredicateRead = VK_ACCESS_2_CONDITIONAL_RENDERING_READ_BIT_EXT;
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkAccessFlags2 kStorage =
    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr VkPipelineStageFlags2 kTransfer = VK_PIPELINE_STAGE_2_TRANSFER_BIT;

// HZB levels (shaders/occlusion.glsl): level 0 half the target's size, each next one half
// of it, rounded up, down to 1 × 1.
glm::uvec2 hzb_level_size(VkExtent2D extent, uint32_t level) {
  glm::uvec2 s((extent.width + 1) / 2, (extent.height + 1) / 2);
  for (uint32_t k = 0; k < level; ++k) s = (s + 1u) / 2u;
  return s;
}

uint32_t hzb_levels(VkExtent2D extent) {
  uint32_t levels = 1;
  while (hzb_level_size(extent, levels - 1) != glm::uvec2(1)) ++levels;
  return levels;
}

uint32_t hzb_floats(VkExtent2D extent) {
  uint32_t total = 0;
  for (uint32_t level = 0; level < hzb_levels(extent); ++level) {
    const glm::uvec2 s = hzb_level_size(extent, level);
    total += s.x * s.y;
  }
  return total;
}

}  // namespace

OcclusionCuller::OcclusionCuller(gpu::Context& context, const GpuScene& scene,
                                 FrameResources& resources)
    : context_(context), scene_(scene), resources_(resources), descriptors_(context) {
  if (!context.conditional_rendering()) return;
  const std::vector<Cluster>& clusters = scene.clusters();
  std::vector<glm::vec4> bounds(2 * std::max<size_t>(clusters.size(), 1), glm::vec4(0.0f));
  for (size_t c = 0; c < clusters.size(); ++c) {
    const uint32_t triangles = clusters[c].index_count / 3;
    float bits = 0.0f;
    std::memcpy(&bits, &triangles, sizeof(bits));
    bounds[2 * c] = glm::vec4(clusters[c].bounds.min, bits);
    bounds[2 * c + 1] = glm::vec4(clusters[c].bounds.max, 0.0f);
  }
  cluster_bounds_ =
      gpu::make_device_buffer(context, bounds.data(), bounds.size() * sizeof(glm::vec4),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  sampler_ = gpu::Sampler(context, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  using B = gpu::DescriptorBinding;
  const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  set_layout_ = gpu::DescriptorSetLayout(
      context, {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{1, ssbo}, B{2, ssbo}, B{3, ssbo},
                B{4, ssbo}, B{5, ssbo}, B{6, ssbo}, B{7, ssbo}});
  layout_ = gpu::PipelineLayout(context, {set_layout_.handle()}, sizeof(CullPush));
  build_ = gpu::Pipeline(context, layout_.handle(), "hzb_build.comp");
  test_ = gpu::Pipeline(context, layout_.handle(), "occlusion_cull.comp");
}

void OcclusionCuller::set_enabled(bool on, bool shadows) {
  enabled_ = on && context_.conditional_rendering();
  shadows_ = shadows;
  if (on && !enabled_ && !warned_) {
    warned_ = true;
    log::warn("occlusion culling off: device '{}' lacks VK_EXT_conditional_rendering",
              context_.device_name());
  }
}

OcclusionCuller::View& OcclusionCuller::begin(VkCommandBuffer cmd, const std::string& key) {
  auto [it, fresh] = views_.try_emplace(key);
  View& v = it->second;
  const VkDeviceSize flags = std::max<size_t>(scene_.clusters().size(), 1) * sizeof(uint32_t);
  if (fresh) {
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_CONDITIONAL_RENDERING_BIT_EXT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    for (gpu::Buffer& b : v.visible)
      b = gpu::Buffer(context_, flags, usage, gpu::MemoryUsage::kDevice);
    v.late = gpu::Buffer(context_, flags, usage, gpu::MemoryUsage::kDevice);
    v.listed = gpu::Buffer(context_, flags,
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           gpu::MemoryUsage::kDevice);
    v.stats = gpu::Buffer(context_, 4 * sizeof(uint32_t),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                          gpu::MemoryUsage::kDevice);
    v.set = descriptors_.allocate(set_layout_);
    // No history: every cluster counts as visible last frame, so the first half draws all.
    for (gpu::Buffer& b : v.visible) vkCmdFillBuffer(cmd, b.handle(), 0, VK_WHOLE_SIZE, 1u);
    vkCmdFillBuffer(cmd, v.late.handle(), 0, VK_WHOLE_SIZE, 0u);
    gpu::memory_barrier(cmd, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, kPredicate | kCompute,
                        kPredicateRead | kStorage);
  } else if (v.culled_at != ~0ull) {
    v.early = 1 - v.early;  // what the last cull found visible
  }
  // The last frame's cull wrote the flags this frame's first half reads.
  gpu::memory_barrier(cmd, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, kPredicate,
                      kPredicateRead);
  return v;
}

void OcclusionCuller::cull(PassContext& pass, View& v, const std::string& depth_resource,
                           uint32_t depth_layer, VkExtent2D extent, const mat4& clip,
                           const std::vector<uint32_t>& order, const std::string& scope) {
  const VkCommandBuffer cmd = pass.cmd();
  PassContext::Aside aside = pass.aside(scope);
  const gpu::GpuImage& image = resources_.image(depth_resource);
  // A layer of a depth array (the cascades) is read through its own 2-D view.
  const VkImageView depth = image.desc().layers > 1 ? image.layer_view(depth_layer) : image.view();
  const bool resized = !v.hzb || v.extent.width != extent.width || v.extent.height != extent.height;
  if (resized || v.bound_depth != depth) {
    if (resized)
      v.hzb = gpu::Buffer(context_, hzb_floats(extent) * sizeof(float),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kDevice);
    v.extent = extent;
    v.bound_depth = depth;
    const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu::DescriptorWriter()
        .image(v.set, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, depth, sampler_.handle(),
               VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
        .buffer(v.set, 1, ssbo, v.hzb.handle())
        .buffer(v.set, 2, ssbo, cluster_bounds_.handle())
        .buffer(v.set, 3, ssbo, v.visible[0].handle())
        .buffer(v.set, 4, ssbo, v.visible[1].handle())
        .buffer(v.set, 5, ssbo, v.late.handle())
        .buffer(v.set, 6, ssbo, v.listed.handle())
        .buffer(v.set, 7, ssbo, v.stats.handle())
        .commit(context_.device());
  }
  // The clusters the CPU drew, and zeroed flags and counts for the test to fill in (the
  // flags of clusters outside this frame's list stay 0: not visible).
  const VkBuffer now = v.now_flags();
  gpu::memory_barrier(cmd, kPredicate | kCompute | kTransfer,
                      kPredicateRead | kStorage | VK_ACCESS_2_TRANSFER_READ_BIT, kTransfer,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
  for (size_t first = 0; first < order.size(); first += 16384)  // vkCmdUpdateBuffer: ≤ 64 KiB
    vkCmdUpdateBuffer(cmd, v.listed.handle(), first * sizeof(uint32_t),
                      std::min<size_t>(16384, order.size() - first) * sizeof(uint32_t),
                      order.data() + first);
  vkCmdFillBuffer(cmd, now, 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, v.late.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, v.stats.handle(), 0, VK_WHOLE_SIZE, 0u);
  pass.use(depth_resource, kSampled, kComputeShader);
  gpu::memory_barrier(cmd, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, kCompute, kStorage);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &v.set, 0,
                          nullptr);
  CullPush push;
  push.extent = glm::uvec4(extent.width, extent.height, 0u, 0u);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, build_.handle());
  // Four levels a dispatch (shaders/hzb_build.comp), 16 × 16 texels of the first a group.
  const uint32_t levels = hzb_levels(extent);
  for (uint32_t first = 0; first < levels; first += 4) {
    const glm::uvec2 size = hzb_level_size(extent, first);
    push.extent.z = first;
    push.extent.w = std::min(4u, levels - first);
    vkCmdPushConstants(cmd, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (size.x + 15) / 16, (size.y + 15) / 16, 1);
    gpu::memory_barrier(cmd, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, kCompute, kStorage);
  }
  push.clip = clip;
  push.config =
      glm::uvec4(static_cast<uint32_t>(order.size()), static_cast<uint32_t>(v.early), 0u, 0u);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, test_.handle());
  vkCmdPushConstants(cmd, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
  if (!order.empty()) vkCmdDispatch(cmd, (static_cast<uint32_t>(order.size()) + 63) / 64, 1, 1);
  gpu::memory_barrier(cmd, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, kPredicate | kTransfer,
                      kPredicateRead | VK_ACCESS_2_TRANSFER_READ_BIT);
  pass.use(depth_resource, kDepthAttachment);
  v.culled_at = pass.frame();
  // Its memory bound: the depth read, every HZB level written and read once more, and per
  // listed cluster its bounds, its flags and a few HZB texels.
  const double hzb = 4.0 * hzb_floats(extent);
  pass.bytes(4.0 * extent.width * extent.height + 2.0 * hzb + 64.0 * order.size());
}

const OcclusionCuller::View* OcclusionCuller::culled(const std::string& key, uint64_t frame) const {
  const auto it = views_.find(key);
  return it != views_.end() && it->second.culled_at == frame ? &it->second : nullptr;
}

}  // namespace illum::realtime
