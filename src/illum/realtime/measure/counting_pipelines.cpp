#include "illum/realtime/measure/counting_pipelines.h"

#include "illum/realtime/scene_draw.h"

namespace illum::realtime {

gpu::GraphicsPipelineDesc counting_variant(gpu::GraphicsPipelineDesc d) {
  d.fragment_shader = "";
  d.color_write = false;
  d.additive_blend = false;
  d.depth_test = false;
  d.depth_write = false;
  d.stencil_test = false;
  return d;
}

CountingPipelines::CountingPipelines(gpu::Context& context, VkPipelineLayout layout,
                                     const gpu::GraphicsPipelineDesc& pass)
    : context_(&context), pass_(pass), rasterized_(context, layout, counting_variant(pass)) {}

const gpu::Pipeline& CountingPipelines::quads(VkPipelineLayout quad_count_layout) const {
  if (!quads_) {
    gpu::GraphicsPipelineDesc d = pass_;
    d.fragment_shader = "quad_count.frag";
    d.fragment_specialization = nullptr;
    d.color_write = false;
    d.additive_blend = false;
    quads_ = gpu::Pipeline(*context_, quad_count_layout, d);
  }
  return quads_;
}

bool CountingPipelines::replays(const DrawTargets& targets) const {
  return targets.clear_depth || !pass_.depth_write || targets.depth == VK_NULL_HANDLE;
}

}  // namespace illum::realtime
