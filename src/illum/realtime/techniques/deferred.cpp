// The deferred pipeline: a compact G-buffer after a depth pre-pass (a pass and timer scope of
// its own; albedo + exponent RGBA16F,
// both normals octahedral in one RGBA16F, specular + material type RGBA8; position from
// depth; emission + ambient straight into the HDR target), then the lights: one compute
// dispatch looping over them (default), or per-light volumes with the stencil trick (S001
// §4.1). With stencil shadow volumes the lighting pass is left out and each light is added
// by record_masked_light() in a full-screen pass over the G-buffer.
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/stencil_shadows.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/depth_prepass.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// Compact G-buffer (frame_targets.h), 20 bytes a pixel plus the HDR target (was 28 + 8 in
// four fp16 targets).
const auto& kTargets = kGbufferTargets;
constexpr uint32_t kUncleared = 0b0111;  // the three G-buffer targets of the MRT set
// While a screen-space lighting input is active: the indirect term before occlusion and the
// occlusion it took (shaders/gbuffer_pass.glsl).
const char* const kIndirectTarget = "gbuffer.indirect";
constexpr VkFormat kIndirectFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// Unit icosphere (icosahedron subdivided once, 80 faces) for deferred light volumes.
void icosphere(std::vector<vec3>* positions, std::vector<uint32_t>* indices) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (vec3& v : p) v = glm::normalize(v);
  const std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                   1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                   3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                   4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  std::vector<uint32_t> out;
  auto mid = [&](uint32_t a, uint32_t b) {
    p.push_back(glm::normalize(p[a] + p[b]));
    return static_cast<uint32_t>(p.size() - 1);
  };
  for (size_t i = 0; i < f.size(); i += 3) {
    const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
    const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.insert(out.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
  }
  *positions = std::move(p);
  *indices = std::move(out);
}

}  // namespace

namespace {

class Deferred final : public FramePipeline {
 public:
  Deferred(TechniqueContext& ctx, const TechniqueDecl& decl)
      : FramePipeline(ctx, decl), descriptors_(ctx.gpu) {
    masked_ = ctx.shadow_method().masks_lights();
    compute_ = param<std::string>("lighting") == "compute";
    using B = gpu::DescriptorBinding;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    // shaders/gbuffer.glsl; binding 4 (the HDR target as a storage image) is used by the
    // compute passes only, binding 5 ("gbuffer.indirect") by deferred_inputs.comp.
    set_layout_ =
        gpu::DescriptorSetLayout(ctx.gpu, {B{0, cis}, B{1, cis}, B{2, cis}, B{3, cis},
                                           B{4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, B{5, cis}});
    set_ = descriptors_.allocate(set_layout_);
    layout_ = ctx.globals.shading_layout(set_layout_.handle());
    const VkPipelineLayout layout = layout_.handle();
    gpu::GraphicsPipelineDesc g = gbuffer_pass_desc(ctx.depth_format);
    // Depth pre-pass as in the forward path: each pixel then writes its G-buffer bytes once.
    prepass_ = DepthPrepass(ctx.gpu, layout, g);
    g.depth_write = false;
    g.depth_compare = VK_COMPARE_OP_EQUAL;
    gbuffer_ = gpu::Pipeline(ctx.gpu, layout, g);
    gbuffer_count_ = CountingPipelines(ctx.gpu, layout, g);
    gbuffer_desc_ = g;
    gpu::GraphicsPipelineDesc l;
    l.vertex_shader = "deferred_light.vert";
    l.fragment_shader = "deferred_light.frag";
    l.vertex_input.stride = sizeof(vec3);
    l.vertex_input.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    l.color_formats = {kHdrFormat};
    l.depth_format = ctx.depth_format;
    l.stencil_format = ctx.depth_format;
    l.depth_write = false;
    l.depth_clamp = ctx.gpu.depth_clamp();
    gpu::GraphicsPipelineDesc fs = l;
    fs.cull = VK_CULL_MODE_NONE;
    fs.depth_test = false;
    fs.additive_blend = true;
    if (masked_) {
      use_stencil_zero_test(&fs);
      masked_light_ = gpu::Pipeline(ctx.gpu, layout, fs);
      return;
    }
    if (compute_) {
      compute_light_ = gpu::Pipeline(ctx.gpu, layout, "deferred_light.comp");
      return;
    }
    std::vector<vec3> sp;
    std::vector<uint32_t> si;
    icosphere(&sp, &si);
    sphere_vertices_ = gpu::make_device_buffer(ctx.gpu, sp.data(), sp.size() * sizeof(vec3),
                                               VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    sphere_indices_ = gpu::make_device_buffer(ctx.gpu, si.data(), si.size() * sizeof(uint32_t),
                                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    sphere_index_count_ = static_cast<uint32_t>(si.size());
    // Stencil trick (S001 §4.1): mark pixels whose surface lies inside the sphere (z-fail
    // count ≠ 0), then shade them once through the back faces.
    gpu::GraphicsPipelineDesc st = l;
    st.fragment_shader = "";
    st.color_write = false;
    use_z_fail_count(&st);
    light_stencil_ = gpu::Pipeline(ctx.gpu, layout, st);
    gpu::GraphicsPipelineDesc lv = l;
    // Both faces, no depth test (works with the camera inside the sphere); a shaded pixel
    // zeroes its stencil so the other face cannot light it twice.
    lv.cull = VK_CULL_MODE_NONE;
    lv.depth_test = false;
    lv.additive_blend = true;
    lv.stencil_test = true;
    lv.stencil_front = stencil_op(VK_STENCIL_OP_ZERO, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_NOT_EQUAL);
    lv.stencil_back = lv.stencil_front;
    light_volume_ = gpu::Pipeline(ctx.gpu, layout, lv);
    light_fullscreen_ = gpu::Pipeline(ctx.gpu, layout, fs);
  }

  void declare(FrameGraph& graph) override {
    // The G-buffer set always holds the HDR target as a storage image and the depth as a
    // texture, whichever lighting runs.
    graph.add_resource(hdr_target(VK_IMAGE_USAGE_STORAGE_BIT));
    graph.add_resource(depth_target(ctx_.depth_format));
    for (int k = 0; k < 3; ++k) {
      ResourceDesc r;
      r.name = kTargets[k];
      r.frame_divisor = 1;
      r.format = kGbufferFormats[k];
      r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT;
      graph.add_resource(r);
    }
    // A screen-space lighting input (SSAO) is written after this G-buffer pass: the pass
    // then also keeps the indirect term, and "deferred.inputs" applies that input's occlusion.
    indirect_ = ctx_.lighting_inputs().any_screen_space();
    if (indirect_) {
      ResourceDesc r;
      r.name = kIndirectTarget;
      r.frame_divisor = 1;
      r.format = kIndirectFormat;
      graph.add_resource(r);
      if (!gbuffer_indirect_.handle()) {
        gpu::GraphicsPipelineDesc g = gbuffer_desc_;
        g.fragment_shader = "gbuffer_indirect.frag";
        g.color_formats.push_back(kIndirectFormat);
        gbuffer_indirect_ = gpu::Pipeline(ctx_.gpu, layout_.handle(), g);
        gbuffer_indirect_count_ = CountingPipelines(ctx_.gpu, layout_.handle(), g);
        inputs_ = gpu::Pipeline(ctx_.gpu, layout_.handle(), "deferred_inputs.comp");
      }
    }
    graph.add_pass(DepthPrepass::pass(name(), [this](PassContext& pass) {
      prepass_.record(ctx_, pass, {ctx_.width(), ctx_.height()}, layout_.handle(),
                      ctx_.shading_sets(set_));
    }));
    PassDesc g;
    g.name = "gbuffer";
    g.technique = name();
    g.phase = Phase::kGeometry;
    g.accesses = ctx_.shading_reads(kFragmentShader, InputReads::kSurface);
    for (const char* t : kTargets) g.accesses.push_back({t, kColorAttachment});
    g.accesses.push_back({"hdr", kColorAttachment});
    if (indirect_) g.accesses.push_back({kIndirectTarget, kColorAttachment});
    g.accesses.push_back({"depth", kDepthAttachment});
    g.record = [this](PassContext& pass) { record_gbuffer(pass); };
    graph.add_pass(std::move(g));
    if (indirect_) {
      PassDesc in;
      in.name = "deferred.inputs";
      in.technique = name();
      in.phase = Phase::kLighting;
      const auto cs = kComputeShader;
      for (const char* t : kTargets) in.accesses.push_back({t, kSampled, cs});
      in.accesses.push_back({kIndirectTarget, kSampled, cs});
      in.accesses.push_back({"depth", kSampled, cs});
      in.accesses.push_back({"hdr", kStorageRead | kStorageWrite, cs});
      for (const Access& a : ctx_.shading_reads(cs, InputReads::kScreenSpace))
        in.accesses.push_back(a);
      in.record = [this](PassContext& pass) { record_inputs(pass); };
      graph.add_pass(std::move(in));
    }
    if (masked_) return;  // the shadow volumes' per-light passes add the lights
    PassDesc l;
    l.name = "lighting";
    l.technique = name();
    l.phase = Phase::kLighting;
    const VkPipelineStageFlags2 stage = compute_ ? kComputeShader : kFragmentShader;
    for (const char* t : kTargets) l.accesses.push_back({t, kSampled, stage});
    if (compute_) {
      l.accesses.push_back({"depth", kSampled, stage});
      l.accesses.push_back({"hdr", kStorageRead | kStorageWrite, stage});
    } else {
      l.accesses.push_back({"depth", kDepthReadOnly | kSampled, stage});
      l.accesses.push_back({"hdr", kColorAttachment});
    }
    for (const Access& a : ctx_.shading_reads(stage)) l.accesses.push_back(a);
    l.record = [this](PassContext& pass) {
      compute_ ? record_compute_lighting(pass) : record_light_volumes(pass);
    };
    graph.add_pass(std::move(l));
  }

  void bind() override {
    const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const VkSampler nearest = ctx_.globals.nearest().handle();
    FrameResources& r = ctx_.resources;
    gpu::DescriptorWriter()
        .image(set_, 0, cis, r.image(kTargets[0]).view(), nearest, ro)
        .image(set_, 1, cis, r.image(kTargets[1]).view(), nearest, ro)
        .image(set_, 2, cis, r.image(kTargets[2]).view(), nearest, ro)
        .image(set_, 3, cis, r.image("depth").view(), nearest,
               VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
        .image(set_, 4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, r.image("hdr").view(), VK_NULL_HANDLE,
               VK_IMAGE_LAYOUT_GENERAL)
        .image(set_, 5, cis,
               indirect_ ? r.image(kIndirectTarget).view() : ctx_.globals.dummy_2d().view(),
               nearest, ro)
        .commit(ctx_.gpu.device());
  }

  void record_masked_light(PassContext& pass, int light) override {
    const VkCommandBuffer c = pass.cmd();
    bind_sets(c, VK_PIPELINE_BIND_POINT_GRAPHICS);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, masked_light_.handle());
    vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
    PushConstants push{};
    push.light_index = light;
    push.mode = 1;  // deferred_light.vert: the full-screen triangle
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDraw(c, 3, 1, 0, 0);
  }

  std::vector<Access> masked_light_reads() const override {
    std::vector<Access> reads;
    for (const char* t : kTargets) reads.push_back({t, kSampled, kFragmentShader});
    reads.push_back({"depth", kSampled, kFragmentShader});
    return reads;
  }

 private:
  void bind_sets(VkCommandBuffer c, VkPipelineBindPoint point) const {
    bind_shading_sets(c, point, layout_.handle(), ctx_.globals, ctx_.shading_sets(set_));
  }

  void record_gbuffer(PassContext& pass) {
    FrameResources& r = ctx_.resources;
    DrawTargets t;
    // The G-buffer targets are read only where the depth is below 1, which this pass writes:
    // they start undefined. The HDR target is cleared (the background shows it).
    for (const char* name : kTargets) t.colors.push_back({r.image(name).view(), false, {}, true});
    t.colors.push_back({r.image("hdr").view(), true, {}});
    if (indirect_) t.colors.push_back({r.image(kIndirectTarget).view(), false, {}, true});
    t.depth = r.image("depth").layer_view(0);
    t.clear_depth = false;
    t.stencil = true;
    t.extent = {ctx_.width(), ctx_.height()};
    using D = gpu::RasterFill::Depth;
    const uint32_t w = t.extent.width, h = t.extent.height;
    std::vector<VkFormat> mrt = {kAlbedoFormat, kNormalFormat, kSpecularFormat, kHdrFormat};
    uint32_t uncleared = kUncleared;
    if (indirect_) {
      mrt.push_back(kIndirectFormat);
      uncleared |= 1u << 4;
    }
    ctx_.drawer.render_counted(
        pass, t, indirect_ ? gbuffer_indirect_ : gbuffer_,
        indirect_ ? gbuffer_indirect_count_ : gbuffer_count_, layout_.handle(),
        ctx_.shading_sets(set_),
        SceneView::camera(ctx_.view().view_proj, false, SceneView::Occlusion::kVisibleNow),
        {w, h, mrt, ctx_.depth_format, D::kTest, false, uncleared},
        {w, h, mrt, ctx_.depth_format, D::kReject, false, uncleared});
  }

  // The screen-space inputs' occlusion over the HDR target (shaders/deferred_inputs.comp).
  void record_inputs(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    bind_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, inputs_.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 7) / 8, (ctx_.height() + 7) / 8, 1);
  }

  // One dispatch: every pixel loops over the lights and adds to the HDR target in place.
  void record_compute_lighting(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    bind_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, compute_light_.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 7) / 8, (ctx_.height() + 7) / 8, 1);
  }

  void record_light_volumes(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const VkExtent2D extent{ctx_.width(), ctx_.height()};
    ctx_.drawer.begin_light_scope(c, ctx_.resources.image("hdr").view(),
                                  ctx_.resources.image("depth").layer_view(0), extent);
    const VkPipelineLayout layout = layout_.handle();
    bind_sets(c, VK_PIPELINE_BIND_POINT_GRAPHICS);
    VkDeviceSize offset = 0;
    VkBuffer vb = sphere_vertices_.handle();
    vkCmdBindVertexBuffers(c, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(c, sphere_indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
    const std::vector<Light>& lights = ctx_.lights();
    const int single = ctx_.settings().get<int>("lighting.single_light");
    for (size_t i = 0; i < lights.size(); ++i) {
      if (single >= 0 && static_cast<int>(i) != single) continue;
      const Light& l = lights[i];
      if (!lit_in_real_time(l)) continue;
      PushConstants push{};
      push.light_index = static_cast<int>(i);
      const bool volume = l.type != LightType::kDirectional && l.range > 0.0f;
      if (volume) {
        VkClearAttachment clear{VK_IMAGE_ASPECT_STENCIL_BIT, 0, {}};
        clear.clearValue.depthStencil = {1.0f, 0};
        VkClearRect rect{{{0, 0}, extent}, 0, 1};
        vkCmdClearAttachments(c, 1, &clear, 1, &rect);
        push.mode = 0;
        vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_stencil_.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        vkCmdDrawIndexed(c, sphere_index_count_, 1, 0, 0, 0);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_volume_.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        vkCmdDrawIndexed(c, sphere_index_count_, 1, 0, 0, 0);
      } else {
        push.mode = 1;
        vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_fullscreen_.handle());
        vkCmdDraw(c, 3, 1, 0, 0);
      }
    }
    vkCmdEndRendering(c);
  }

  bool masked_ = false, compute_ = true, indirect_ = false;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  gpu::PipelineLayout layout_;
  DepthPrepass prepass_;
  gpu::Pipeline gbuffer_, compute_light_, light_stencil_, light_volume_, light_fullscreen_,
      masked_light_, gbuffer_indirect_, inputs_;
  gpu::GraphicsPipelineDesc gbuffer_desc_;
  CountingPipelines gbuffer_indirect_count_;
  gpu::Buffer sphere_vertices_, sphere_indices_;
  CountingPipelines gbuffer_count_;
  uint32_t sphere_index_count_ = 0;
};

}  // namespace

TechniqueDecl deferred_technique() {
  TechniqueDecl t;
  t.name = "deferred";
  t.kind = TechniqueKind::kFramePipeline;
  t.summary =
      "compact G-buffer after a depth pre-pass (albedo + exponent, two octahedral normals, "
      "specular + type; position from depth), then the lights over it";
  t.params = {
      enum_param("lighting", "compute", {"compute", "volumes"},
                 "compute: one dispatch looping over the lights; volumes: per-light light "
                 "volumes with the stencil trick (S001 §4.1)")
          .structural()
          .aka("deferred_lighting"),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Deferred>(ctx, *find_technique("deferred"));
  };
  return t;
}

}  // namespace illum::realtime
