// The depth pre-pass of the forward and deferred pipelines: the shading pass's pipeline with
// depth_only.vert (forward.vert's transform on the packed positions, so depths repeat exactly)
// and an empty fragment stage, writing depth and stencil only. The shading pass after it tests
// depth EQUAL, so each pixel runs its fragment shader once however deep the overdraw (where
// Sibenik's nave would otherwise shade every overlapping layer).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <utility>

#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"

namespace illum::realtime {

class DepthPrepass {
 public:
  DepthPrepass() = default;
  // `shading`: the shading pass's pipeline, before its depth test becomes EQUAL.
  DepthPrepass(gpu::Context& gpu, VkPipelineLayout layout,
               const gpu::GraphicsPipelineDesc& shading) {
    gpu::GraphicsPipelineDesc pre = shading;
    pre.vertex_shader = "depth_only.vert";  // forward.vert's transform, positions only
    pre.vertex_input = mesh_vertex_input(true);
    pre.fragment_shader = "depth_only.frag";  // empty: see the shader
    pre.color_formats = {};                   // a rendering of its own: depth and stencil only
    pre.color_write = false;
    pipeline_ = gpu::Pipeline(gpu, layout, pre);
    counting_ = CountingPipelines(gpu, layout, pre);
  }

  // The frame-graph pass "depth_prepass" of `technique`: a pass of its own so it is timed (and
  // bounded) on its own. Occlusion culling samples the depth between the pass's two halves,
  // in a scope beside it.
  static PassDesc pass(const std::string& technique, std::function<void(PassContext&)> record) {
    PassDesc pre;
    pre.name = "depth_prepass";
    pre.technique = technique;
    pre.phase = Phase::kGeometry;
    pre.accesses = {{"depth", kDepthAttachment}, {"depth", kSampled, kComputeShader}};
    pre.nested_scopes = 2;
    pre.record = std::move(record);
    return pre;
  }

  // Records the scene into "depth" (cleared, stencil included) from the camera, culled in two
  // phases.
  void record(TechniqueContext& ctx, PassContext& pass, VkExtent2D extent, VkPipelineLayout layout,
              const std::array<VkDescriptorSet, 3>& sets) const {
    DrawTargets t;
    t.depth = ctx.resources.image("depth").layer_view(0);
    t.depth_resource = "depth";
    t.stencil = true;
    t.extent = extent;
    using D = gpu::RasterFill::Depth;
    const uint32_t w = extent.width, h = extent.height;
    ctx.drawer.render_counted(
        pass, t, pipeline_, counting_, layout, sets,
        SceneView::camera(ctx.view().view_proj, true, SceneView::Occlusion::kTwoPhase),
        {w, h, {}, ctx.depth_format, D::kWrite}, {w, h, {}, ctx.depth_format, D::kReject});
  }

 private:
  gpu::Pipeline pipeline_;
  CountingPipelines counting_;
};

}  // namespace illum::realtime
