// Stencil shadow volumes (S002 §4.3) as a shadow method, forward and deferred alike: the
// volumes come from "silhouettes" (a compute pass, or the CPU reference as a CPU pass) on the
// lights' schedule; then "shadow_volumes" runs per light a z-fail stencil count of its
// volumes against the depth buffer ("stencil_volumes") and has the frame pipeline add the
// light where the count is 0 ("volume_lighting"). The geometry and the stencil pipeline are
// in stencil_shadows.h.
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/stencil_shadows.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

class ShadowVolumes final : public ShadowMethod {
 public:
  ShadowVolumes(TechniqueContext& ctx, const TechniqueDecl& decl) : ShadowMethod(ctx, decl) {
    if (!ctx.gpu.depth_clamp())
      throw Error(
          fmt::format("shadows 'volume' need depthClamp, which '{}' lacks", ctx.gpu.device_name()));
    gpu_ = param<std::string>("silhouettes") == "gpu";
    update_period_ = param<int>("update_period");
    stencil_ = std::make_unique<StencilShadows>(
        ctx.gpu, ctx.scene, ctx.lights().size(),
        gpu_ ? SilhouetteSource::kGpu : SilhouetteSource::kCpu, ctx.globals.default_layout(),
        kHdrFormat, ctx.depth_format);
  }

  bool masks_lights() const override { return true; }

  void declare(FrameGraph& graph) override {
    // Lights, geometry and the caster choice (back_faces, a per-frame parameter) change the
    // volumes.
    const Changes changes = kLightsChanged | kGeometryChanged | kParametersChanged;
    const Schedule schedule = update_period_ > 0 ? Schedule::every_n(update_period_, 0, changes)
                                                 : Schedule::on_change(changes);
    PassDesc build;
    build.name = "silhouettes";
    build.technique = name();
    build.phase = Phase::kShadows;
    build.schedule = schedule;
    if (gpu_) {
      // Technique-owned buffers: the graph derives their barriers (global memory barriers).
      for (const char* b : {"volume.args", "volume.vertices"}) {
        ResourceDesc r;
        r.name = b;
        r.kind = ResourceDesc::Kind::kBuffer;
        r.external = true;
        graph.add_resource(r);
      }
      build.accesses = {{"volume.args", kTransferDst},
                        {"volume.vertices", kStorageWrite, kComputeShader},
                        {"volume.args", kStorageRead | kStorageWrite, kComputeShader}};
      build.record = [this](PassContext& pass) {
        stencil_->record_clear(pass.cmd(), ctx_.lights().size());
        pass.use("volume.args", kStorageRead | kStorageWrite, kComputeShader);
        stencil_->record_extraction(pass.cmd(), ctx_.lights(), param<bool>("back_faces"));
      };
    } else {
      // Built on the CPU into a host-visible buffer before the frame is submitted.
      build.cpu = true;
      build.record = [this](PassContext&) {
        stencil_->build_on_cpu(ctx_.lights(), param<bool>("back_faces"));
      };
    }
    graph.add_pass(std::move(build));

    PassDesc p;
    p.name = "shadow_volumes";
    p.technique = name();
    p.phase = Phase::kLighting;
    p.accesses = {{"hdr", kColorAttachment}, {"depth", kDepthReadOnly, kFragmentShader}};
    for (const Access& a : ctx_.pipeline().masked_light_reads()) merge_access(&p.accesses, a);
    if (gpu_) {
      p.accesses.push_back({"volume.vertices", kVertexInput});
      p.accesses.push_back({"volume.args", kIndirectArgs});
    }
    depth_access_ = p.accesses[1];
    p.nested_scopes = 2 * static_cast<int>(ctx_.lights().size());
    p.record = [this](PassContext& pass) { record_lights(pass); };
    graph.add_pass(std::move(p));
  }

 private:
  // Per light: the z-fail count of its volumes against the depth buffer, then the light added
  // where the count is 0 — the scene again with depth LESS_OR_EQUAL (forward) or one
  // full-screen pass over the G-buffer (deferred).
  void record_lights(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const std::vector<Light>& lights = ctx_.lights();
    const int single = ctx_.settings().get<int>("lighting.single_light");
    const VkExtent2D extent{ctx_.width(), ctx_.height()};
    for (size_t i = 0; i < lights.size(); ++i) {
      if (single >= 0 && static_cast<int>(i) != single) continue;
      if (!lit_in_real_time(lights[i])) continue;
      // The last light's additions and stencil are done before this light's scope.
      pass.use("hdr", kColorAttachment);
      pass.use("depth", depth_access_.uses, depth_access_.shaders);
      const VkRect2D scissor = light_scissor(lights[i], ctx_.scene.bounds(), ctx_.view().view_proj,
                                             extent.width, extent.height);
      {
        const PassContext::Scope scope = pass.scope("stencil_volumes");
        ctx_.drawer.begin_light_scope(c, ctx_.resources.image("hdr").view(),
                                      ctx_.resources.image("depth").layer_view(0), extent);
        vkCmdSetScissor(c, 0, 1, &scissor);
        stencil_->record_stencil(c, ctx_.globals.frame_set(), i);
        if (pass.counting()) {
          // Every sample the volumes rasterize (drawn again, untested, writing nothing),
          // each taken as a z-fail stencil update: most fail the depth test, behind the
          // visible surfaces; those in front only test, so the bound is on the high side
          // for them. (Counting the depth-passing samples apart, with an occlusion query
          // around depth-tested draws in this read-only-depth scope, crashes lavapipe.)
          using D = gpu::RasterFill::Depth;
          const uint32_t all = pass.begin_count();
          stencil_->record_stencil(c, ctx_.globals.frame_set(), i,
                                   StencilShadows::StencilDraw::kRasterized);
          pass.end_count(all,
                         {extent.width, extent.height, {}, ctx_.depth_format, D::kStencilZFail});
        }
      }
      const PassContext::Scope scope = pass.scope("volume_lighting");
      // The light's pixels: every one inside the scissor is tested and, where lit, blended
      // (one layer: deferred's full-screen pass; forward's second scene draw may rasterize
      // more). An occlusion query around these stencil-tested draws crashes lavapipe, so the
      // scissor's area stands for the count.
      pass.fill({extent.width,
                 extent.height,
                 {kHdrFormat},
                 ctx_.depth_format,
                 gpu::RasterFill::Depth::kStencilTest,
                 true},
                static_cast<double>(scissor.extent.width) * scissor.extent.height /
                    (static_cast<double>(extent.width) * extent.height));
      ctx_.pipeline().record_masked_light(pass, static_cast<int>(i));
      vkCmdEndRendering(c);
    }
  }

  bool gpu_ = true;
  int update_period_ = 0;
  Access depth_access_;
  std::unique_ptr<StencilShadows> stencil_;
};

}  // namespace

TechniqueDecl shadow_volume_technique() {
  TechniqueDecl t;
  t.name = "volume";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "stencil shadow volumes (S002 §4.3): per light a z-fail stencil count of its volumes, "
      "then the light added where the count is 0 (forward: the scene again; deferred: one "
      "full-screen pass)";
  t.params = {
      int_param("update_period", 0, 0, 1000000,
                "0: rebuild the volumes only when the lights change; N: every N frames")
          .structural()
          .aka("shadow_update_period")
          .slider(UiHint::kLinear, 0, 30),
      bool_param("back_faces", false, "build the volumes from back-facing casters (S002 §4.3)")
          .aka("volume_back_faces"),
      enum_param("silhouettes", "gpu", {"gpu", "cpu"},
                 "gpu: one compute dispatch per light, drawn indirectly; cpu: the CPU reference "
                 "builder, uploaded")
          .structural()
          .aka("silhouettes"),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<ShadowVolumes>(ctx, *find_technique("volume"));
  };
  return t;
}

}  // namespace illum::realtime
