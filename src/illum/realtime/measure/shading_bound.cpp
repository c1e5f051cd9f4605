#include "illum/realtime/measure/shading_bound.h"

#include <algorithm>

#include "illum/core/error.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/techniques/frame_targets.h"

namespace illum::realtime {

namespace {

constexpr VkImageLayout kReadOnlyDepthLayout =
    VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL;
constexpr VkPipelineStageFlags2 kTests =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
// Albedo + exponent, both normals, specular + type, emission + ambient, depth: per pixel.
constexpr double kInputBytesPerPixel = 8 + 8 + 4 + 8 + 4;

}  // namespace

ShadingBound::ShadingBound(TechniqueContext& ctx) : ctx_(ctx), descriptors_(ctx.gpu) {
  using B = gpu::DescriptorBinding;
  const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  // shaders/gbuffer.glsl's bindings 0–3, and the emission + ambient at 4 (shading_bound.frag).
  set_layout_ =
      gpu::DescriptorSetLayout(ctx.gpu, {B{0, cis}, B{1, cis}, B{2, cis}, B{3, cis}, B{4, cis}});
  layout_ = ctx.globals.shading_layout(set_layout_.handle());
  // The deferred pipeline's G-buffer pass (techniques/deferred.cpp): a depth pre-pass, then
  // gbuffer.frag with depth EQUAL, from forward.vert like the forward pass, so the depths are
  // the forward pass's.
  gpu::GraphicsPipelineDesc g = gbuffer_pass_desc(ctx.depth_format);
  gpu::GraphicsPipelineDesc pre = g;
  pre.fragment_shader = "";
  pre.color_write = false;
  prepass_ = gpu::Pipeline(ctx.gpu, layout_.handle(), pre);
  g.depth_write = false;
  g.depth_compare = VK_COMPARE_OP_EQUAL;
  gbuffer_ = gpu::Pipeline(ctx.gpu, layout_.handle(), g);
  // The lighting: the forward pass's attachments (HDR target, depth and stencil), the depth
  // tested read-only.
  gpu::GraphicsPipelineDesc l;
  l.vertex_shader = "shading_bound.vert";
  l.fragment_shader = "shading_bound.frag";
  l.cull = VK_CULL_MODE_NONE;
  l.color_formats = {kHdrFormat};
  l.depth_format = l.stencil_format = ctx.depth_format;
  l.depth_write = false;
  l.depth_compare = VK_COMPARE_OP_GREATER;
  lighting_ = gpu::Pipeline(ctx.gpu, layout_.handle(), l);
}

ShadingBound::~ShadingBound() = default;

void ShadingBound::realize() {
  if (width_ == ctx_.width() && height_ == ctx_.height() && set_) return;
  ctx_.gpu.wait_idle();
  width_ = ctx_.width();
  height_ = ctx_.height();
  auto target = [&](VkFormat format, VkImageUsageFlags usage) {
    gpu::ImageDesc d;
    d.width = width_;
    d.height = height_;
    d.format = format;
    d.usage = usage;
    return gpu::GpuImage(ctx_.gpu, d);
  };
  const VkImageUsageFlags sampled_target =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  gbuffer_targets_.clear();
  for (VkFormat f : {kAlbedoFormat, kNormalFormat, kSpecularFormat, kHdrFormat})
    gbuffer_targets_.push_back(target(f, sampled_target));
  depth_ = target(ctx_.depth_format,
                  VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
  output_ =
      target(kHdrFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  if (!set_) set_ = descriptors_.allocate(set_layout_);
  const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  const VkSampler nearest = ctx_.globals.nearest().handle();
  gpu::DescriptorWriter()
      .image(set_, 0, cis, gbuffer_targets_[0].view(), nearest, ro)
      .image(set_, 1, cis, gbuffer_targets_[1].view(), nearest, ro)
      .image(set_, 2, cis, gbuffer_targets_[2].view(), nearest, ro)
      .image(set_, 3, cis, depth_.view(), nearest, kReadOnlyDepthLayout)
      .image(set_, 4, cis, gbuffer_targets_[3].view(), nearest, ro)
      .commit(ctx_.gpu.device());
}

ShadingTime ShadingBound::measure(int repeats, Image* image) {
  ILLUM_CHECK(repeats >= 1, "shading bound: {} repetitions", repeats);
  realize();
  gpu::Context& gpu = ctx_.gpu;
  const VkExtent2D extent{width_, height_};
  VkQueryPool covered = VK_NULL_HANDLE;
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_OCCLUSION;
  qi.queryCount = 1;
  ILLUM_VK(vkCreateQueryPool(gpu.device(), &qi, nullptr, &covered));
  gpu::GpuTimer timer(gpu, static_cast<uint32_t>(repeats));
  const std::array<VkDescriptorSet, 3> sets = ctx_.shading_sets(set_);
  gpu.immediate([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    vkCmdResetQueryPool(cmd, covered, 0, 1);
    // The G-buffer of the view (untimed).
    const auto color_stage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const auto color_access =
        VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    const auto ds_access = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                           VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    DrawTargets t;
    for (gpu::GpuImage& g : gbuffer_targets_) {
      g.transition(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, color_stage, color_access);
      t.colors.push_back({g.view(), true, {}});
    }
    depth_.transition(cmd, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, kTests, ds_access);
    t.depth = depth_.layer_view(0);
    t.stencil = true;
    t.extent = extent;
    ctx_.drawer.render(cmd, t, {&prepass_, &gbuffer_}, layout_.handle(), sets,
                       SceneView::camera(ctx_.view().view_proj, false));
    for (gpu::GpuImage& g : gbuffer_targets_)
      g.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    depth_.transition(cmd, kReadOnlyDepthLayout, kTests | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                      VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | ds_access);
    // The lighting: one untimed run counting the covered pixels, one more untimed (lavapipe
    // compiles the pipeline's shaders again outside the query: 0.8 s), then the timed ones,
    // each after the last as a frame's passes into one target are.
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = output_.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;  // as the forward pass clears its target
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = depth_.layer_view(0);
    depth.imageLayout = kReadOnlyDepthLayout;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth;
    info.pStencilAttachment = &depth;
    const VkViewport vp{0.0f, 0.0f, float(width_), float(height_), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    const PushConstants push{};
    for (int r = 0; r < repeats + 2; ++r) {
      output_.transition(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, color_stage, color_access);
      const uint32_t scope = r > 1 ? timer.begin(cmd, "shading_bound") : 0;
      if (r == 0)
        vkCmdBeginQuery(cmd, covered, 0,
                        gpu.occlusion_query_precise() ? VK_QUERY_CONTROL_PRECISE_BIT : 0);
      vkCmdBeginRendering(cmd, &info);
      vkCmdSetViewport(cmd, 0, 1, &vp);
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lighting_.handle());
      bind_shading_sets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.handle(), ctx_.globals, sets);
      vkCmdPushConstants(cmd, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
      vkCmdDraw(cmd, 3, 1, 0, 0);
      vkCmdEndRendering(cmd);
      if (r == 0) vkCmdEndQuery(cmd, covered, 0);
      if (r > 1) timer.end(cmd, scope);
    }
  });
  ShadingTime out;
  out.pass = "forward";
  out.width = width_;
  out.height = height_;
  for (const gpu::PassTime& p : timer.resolve()) out.runs_ms.push_back(p.ms);
  uint64_t samples = 0;
  const VkResult got =
      vkGetQueryPoolResults(gpu.device(), covered, 0, 1, sizeof(samples), &samples, sizeof(samples),
                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
  vkDestroyQueryPool(gpu.device(), covered, nullptr);
  ILLUM_VK(got);
  out.pixels = static_cast<double>(samples);
  out.input_bytes = out.pixels * kInputBytesPerPixel;
  if (image) *image = output_.readback();
  return out;
}

}  // namespace illum::realtime
