// The forward pipeline: a depth pre-pass (same vertex shader, no fragment shader; a pass and
// timer scope of its own), then forward.frag with depth EQUAL over all lights, so each pixel shades
// once however deep the overdraw (in the lighting phase, after the screen-space passes). With
// stencil shadow volumes the main pass writes emission + ambient only and each light is added by
// record_masked_light().
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/measure/shading_bound.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/stencil_shadows.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/depth_prepass.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

class Forward final : public FramePipeline {
 public:
  Forward(TechniqueContext& ctx, const TechniqueDecl& decl) : FramePipeline(ctx, decl) {
    masked_ = ctx.shadow_method().masks_lights();
    const VkPipelineLayout layout = ctx.globals.default_layout();
    gpu::GraphicsPipelineDesc fwd;
    fwd.vertex_shader = "forward.vert";
    fwd.fragment_shader = "forward.frag";
    fwd.vertex_input = mesh_vertex_input(false);
    fwd.cull = VK_CULL_MODE_NONE;  // scenes are two-sided, like the offline renderers
    fwd.color_formats = {kHdrFormat};
    fwd.depth_format = ctx.depth_format;
    fwd.stencil_format = ctx.depth_format;
    prepass_ = DepthPrepass(ctx.gpu, layout, fwd);
    fwd.depth_write = false;
    fwd.depth_compare = VK_COMPARE_OP_EQUAL;
    shade_ = gpu::Pipeline(ctx.gpu, layout, fwd);
    shade_count_ = CountingPipelines(ctx.gpu, layout, fwd);
    if (masked_) {
      gpu::GraphicsPipelineDesc l = fwd;
      // Same vertex shader and state as the depth pass, so the depths repeat exactly (the
      // SPIR-V Invariant decoration on gl_Position trips the validator's struct-member rule).
      l.depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL;
      l.additive_blend = true;
      use_stencil_zero_test(&l);
      // The first fragment that adds the light sets the count to 1, so a second, coplanar
      // surface at the same depth (Sibenik has such duplicates) fails the test instead of
      // adding the light again; the stencil is cleared before the next light.
      l.stencil_front =
          stencil_op(VK_STENCIL_OP_INCREMENT_AND_CLAMP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL);
      l.stencil_back = l.stencil_front;
      masked_light_ = gpu::Pipeline(ctx.gpu, layout, l);
    }
  }

  void declare(FrameGraph& graph) override {
    graph.add_resource(hdr_target());
    graph.add_resource(depth_target(ctx_.depth_format));
    const VkExtent2D extent{ctx_.width(), ctx_.height()};
    graph.add_pass(DepthPrepass::pass(name(), [this, extent](PassContext& pass) {
      prepass_.record(ctx_, pass, extent, ctx_.globals.default_layout(), ctx_.shading_sets());
    }));
    PassDesc p;
    p.name = "forward";
    p.technique = name();
    // After the screen-space phase, whose images (SSAO) the shading reads as lighting inputs;
    // the depth pre-pass stays in the geometry phase.
    p.phase = Phase::kLighting;
    p.accesses = ctx_.shading_reads(kFragmentShader);
    p.accesses.push_back({"hdr", kColorAttachment});
    p.accesses.push_back({"depth", kDepthAttachment});
    p.record = [this, extent](PassContext& pass) {
      DrawTargets t;
      t.colors = {{ctx_.resources.image("hdr").view(), true, {}}};
      t.depth = ctx_.resources.image("depth").layer_view(0);
      t.clear_depth = false;
      t.stencil = true;
      t.extent = extent;
      SceneView view =
          SceneView::camera(ctx_.view().view_proj, false, SceneView::Occlusion::kVisibleNow);
      view.mode = masked_ ? 1 : 0;
      using D = gpu::RasterFill::Depth;
      const uint32_t w = extent.width, h = extent.height;
      ctx_.drawer.render_counted(pass, t, shade_, shade_count_, ctx_.globals.default_layout(),
                                 ctx_.shading_sets(), view,
                                 {w, h, {kHdrFormat}, ctx_.depth_format, D::kTest},
                                 {w, h, {kHdrFormat}, ctx_.depth_format, D::kReject});
    };
    graph.add_pass(std::move(p));
  }

  bool measure_shading(int repeats, ShadingTime* out, Image* image) override {
    if (masked_) return false;  // the shading pass writes emission + ambient only
    if (!shading_bound_) shading_bound_ = std::make_unique<ShadingBound>(ctx_);
    *out = shading_bound_->measure(repeats, image);
    return true;
  }

  void record_masked_light(PassContext& pass, int light) override {
    SceneView view = SceneView::camera(ctx_.view().view_proj, false);
    view.light_index = light;
    view.mode = 2;  // forward.frag: only this light, no shadow-map lookup (the stencil masks)
    vkCmdSetStencilReference(pass.cmd(), VK_STENCIL_FACE_FRONT_AND_BACK, 0);
    ctx_.drawer.draw(pass.cmd(), masked_light_, ctx_.globals.default_layout(), ctx_.shading_sets(),
                     view);
  }

 private:
  bool masked_ = false;
  DepthPrepass prepass_;
  gpu::Pipeline shade_, masked_light_;
  CountingPipelines shade_count_;
  std::unique_ptr<ShadingBound> shading_bound_;  // built on the first measure_shading()
};

}  // namespace

TechniqueDecl forward_technique() {
  TechniqueDecl t;
  t.name = "forward";
  t.kind = TechniqueKind::kFramePipeline;
  t.summary =
      "depth pre-pass, then one shading pass over all lights with depth EQUAL (with stencil "
      "shadow volumes: emission + ambient, then the scene again per light)";
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Forward>(ctx, *find_technique("forward"));
  };
  return t;
}

}  // namespace illum::realtime
