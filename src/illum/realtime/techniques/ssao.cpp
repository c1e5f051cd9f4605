// SSAO (S001 §4.3 with Méndez's term; docs/realtime.md "SSAO"): occlusion of the indirect
// terms from the depth buffer and the normals, blurred depth-aware, then applied to the
// ambient, light-map and ambient-cube terms only — not to PRT, whose transfer already holds
// the visibility (lighting.glsl, ambient_term_includes_visibility).
//
// Passes (each its own timer scope): "ssao.normals" (pipelines without a G-buffer: normals
// from the depth buffer, shaders/ssao_normals.comp), "ssao" (the estimator,
// shaders/ssao.comp, into "ssao.raw"), "ssao.blur" (into "ssao"), then "ssao.apply": the
// scene drawn once more with depth EQUAL over the HDR target, adding (a − 1)·indirect
// (shaders/ssao_apply.frag) — the pipelines' own shaders stay untouched and direct light is
// never scaled. With -p ssao.output=ao, "ssao.show" writes the AO buffer into the HDR
// target instead.
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/stencil_shadows.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// Must match shaders/ssao_set.glsl.
struct SsaoUniforms {
  glm::vec4 shape;  // radius, bias, intensity, falloff
  glm::ivec4 info;  // directions, blur radius, march steps, 0
};

constexpr VkFormat kAoFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // as gbuffer.normal
const char* const kGbufferNormals = "gbuffer.normal";

class Ssao final : public Technique {
 public:
  Ssao(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const auto storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    set_layout_ =
        gpu::DescriptorSetLayout(ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, cis},
                                           B{2, cis}, B{3, cis}, B{4, storage}, B{5, storage}});
    layout_ = ctx.globals.shading_layout(set_layout_.handle());
    normals_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_normals.comp");
    estimate_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao.comp");
    blur_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_blur.comp");
    show_ = param<std::string>("output") == "ao";
    if (show_) {
      show_pass_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_show.comp");
    } else {
      gpu::GraphicsPipelineDesc a;
      a.vertex_shader = "forward.vert";  // the pipelines' depths, repeated exactly
      a.fragment_shader = "ssao_apply.frag";
      a.vertex_input = mesh_vertex_input(false);
      a.cull = VK_CULL_MODE_NONE;
      a.color_formats = {kHdrFormat};
      a.depth_format = ctx.depth_format;
      a.stencil_format = ctx.depth_format;
      a.depth_write = false;
      a.depth_compare = VK_COMPARE_OP_EQUAL;
      a.additive_blend = true;
      // Coplanar duplicates pass EQUAL alike: the first one applies, the count stops the rest.
      a.stencil_test = true;
      a.stencil_front =
          stencil_op(VK_STENCIL_OP_INCREMENT_AND_CLAMP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL);
      a.stencil_back = a.stencil_front;
      apply_ = gpu::Pipeline(ctx.gpu, layout_.handle(), a);
    }
    uniforms_ = gpu::Buffer(ctx.gpu, sizeof(SsaoUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            gpu::MemoryUsage::kUpload);
    for (VkDescriptorSet& s : sets_) s = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    // Deferred: the G-buffer's normals; other pipelines: a normal pass from the depth.
    own_normals_ = !graph.has_resource(kGbufferNormals);
    normals_name_ = own_normals_ ? "ssao.normal" : kGbufferNormals;
    auto image = [&](const char* name, VkFormat format) {
      ResourceDesc r;
      r.name = name;
      r.frame_divisor = 1;
      r.format = format;
      graph.add_resource(r);
    };
    image("ssao.raw", kAoFormat);
    image("ssao", kAoFormat);
    if (own_normals_) image("ssao.normal", kNormalFormat);
    const auto cs = kComputeShader;
    if (own_normals_) {
      PassDesc n;
      n.name = "ssao.normals";
      n.technique = name();
      n.phase = Phase::kScreenSpace;
      n.accesses = {{"depth", kSampled, cs}, {"ssao.normal", kStorageWrite, cs}};
      n.record = [this](PassContext& pass) { dispatch(pass, normals_, sets_[kNormalsSet]); };
      graph.add_pass(std::move(n));
    }
    PassDesc e;
    e.name = "ssao";
    e.technique = name();
    e.phase = Phase::kScreenSpace;
    e.accesses = {
        {"depth", kSampled, cs}, {normals_name_, kSampled, cs}, {"ssao.raw", kStorageWrite, cs}};
    e.record = [this](PassContext& pass) { dispatch(pass, estimate_, sets_[kEstimateSet]); };
    graph.add_pass(std::move(e));
    PassDesc b;
    b.name = "ssao.blur";
    b.technique = name();
    b.phase = Phase::kScreenSpace;
    b.accesses = {{"depth", kSampled, cs},
                  {normals_name_, kSampled, cs},
                  {"ssao.raw", kSampled, cs},
                  {"ssao", kStorageWrite, cs}};
    b.record = [this](PassContext& pass) { dispatch(pass, blur_, sets_[kBlurSet]); };
    graph.add_pass(std::move(b));
    PassDesc a;
    a.technique = name();
    a.phase = Phase::kLighting;
    if (show_) {
      a.name = "ssao.show";
      a.accesses = {{"ssao", kSampled, cs}, {"hdr", kStorageWrite, cs}};
      a.record = [this](PassContext& pass) { dispatch(pass, show_pass_, sets_[kApplySet]); };
    } else {
      a.name = "ssao.apply";
      a.accesses = ctx_.shading_reads(kFragmentShader);
      a.accesses.push_back({"ssao", kSampled, kFragmentShader});
      a.accesses.push_back({"depth", kDepthReadOnly});
      a.accesses.push_back({"hdr", kColorAttachment});
      a.record = [this](PassContext& pass) { record_apply(pass); };
    }
    graph.add_pass(std::move(a));
  }

  void bind() override {
    FrameResources& r = ctx_.resources;
    const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const auto storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    const VkSampler nearest = ctx_.globals.nearest().handle();
    const VkImageView depth = r.image("depth").view();
    const VkImageView normals = r.image(normals_name_).view();
    const VkImageView raw = r.image("ssao.raw").view(), ao = r.image("ssao").view();
    const VkImageView dummy = ctx_.globals.dummy_2d().view();
    // Every binding of every set holds a valid image (lavapipe crashed in the dispatch
    // while bindings no shader of the set uses were left unwritten): what a pass does not
    // read is a dummy, what it does not write the raw AO.
    auto write = [&](gpu::DescriptorWriter& w, VkDescriptorSet s, VkImageView normal_view,
                     VkImageView source, VkImageView target, VkImageView hdr) {
      w.buffer(s, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
          .image(s, 1, cis, depth, nearest,
                 VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
          .image(s, 2, cis, normal_view, nearest, ro)
          .image(s, 3, cis, source, nearest, ro)
          .image(s, 4, storage, target, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL)
          .image(s, 5, storage, hdr, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    };
    gpu::DescriptorWriter w;
    write(w, sets_[kNormalsSet], dummy, dummy, own_normals_ ? normals : raw, raw);
    write(w, sets_[kEstimateSet], normals, dummy, raw, raw);
    write(w, sets_[kBlurSet], normals, raw, ao, raw);
    write(w, sets_[kApplySet], dummy, ao, raw, show_ ? r.image("hdr").view() : raw);
    w.commit(ctx_.gpu.device());
  }

  void update() override {
    SsaoUniforms u{};
    const float radius = radius_in_scene_units();
    const float falloff = param<float>("falloff");
    u.shape = vec4(radius, param<float>("bias"), param<float>("intensity"),
                   falloff > 0.0f ? falloff : radius);
    u.info = glm::ivec4(param<int>("samples"), param<int>("blur"), kMarchSteps, 0);
    uniforms_.write(&u, sizeof(u));
  }

 private:
  enum { kNormalsSet, kEstimateSet, kBlurSet, kApplySet, kSets };
  // Steps along each direction before the bisection (5 halvings: the hit distance is known
  // to R/(8·32)).
  static constexpr int kMarchSteps = 8;

  float radius_in_scene_units() const {
    const float radius = param<float>("radius");
    return radius > 0.0f ? radius : kAutoRadius * ctx_.scene.bounds().diagonal();
  }

  void dispatch(PassContext& pass, const gpu::Pipeline& pipeline, VkDescriptorSet set) {
    const VkCommandBuffer c = pass.cmd();
    bind_shading_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), ctx_.globals,
                      ctx_.shading_sets(set));
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 7) / 8, (ctx_.height() + 7) / 8, 1);
  }

  void record_apply(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    ctx_.drawer.begin_light_scope(c, ctx_.resources.image("hdr").view(),
                                  ctx_.resources.image("depth").layer_view(0),
                                  {ctx_.width(), ctx_.height()});
    vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
    const SceneView view = SceneView::camera(ctx_.view().view_proj, false);
    ctx_.drawer.draw(c, apply_, layout_.handle(), ctx_.shading_sets(sets_[kApplySet]), view);
    ctx_.drawer.end(c);
  }

  static constexpr float kAutoRadius = 0.02f;

  bool show_ = false, own_normals_ = true;
  std::string normals_name_;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline normals_, estimate_, blur_, apply_, show_pass_;
  gpu::Buffer uniforms_;
  VkDescriptorSet sets_[kSets] = {};
};

}  // namespace

TechniqueDecl ssao_technique() {
  TechniqueDecl t;
  t.name = "ssao";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "screen-space ambient occlusion with Méndez's term saturate(N·ω − bias)/(1 + (t/falloff)²) "
      "over a hemisphere of marched directions, depth-aware blur; scales the ambient, "
      "light-map and ambient-cube terms only, not PRT (its transfer holds the visibility; "
      "normals: the G-buffer's in deferred, from "
      "the depth buffer otherwise)";
  t.params = {
      float_param("radius", 0.0f, 0.0f, 1e9f,
                  "occluder search distance R in scene units (0: 2% of the scene's "
                  "bounding-box diagonal)")
          .slider(UiHint::kLinear, 0, 10),
      float_param("bias", 0.1f, 0.0f, 0.99f,
                  "subtracted from N·ω: directions closer than acos(bias) to the tangent plane "
                  "do not occlude")
          .slider(UiHint::kLinear, 0, 0.5),
      float_param("intensity", 1.0f, 0.0f, 10.0f,
                  "AO = 1 − intensity·O (1: the estimand of illum render --integrator ao)")
          .slider(UiHint::kLinear, 0, 4),
      float_param("falloff", 0.0f, 0.0f, 1e9f,
                  "distance unit s of the falloff 1/(1 + (t/s)²) in scene units (0: s = R)")
          .slider(UiHint::kLinear, 0, 10),
      int_param("samples", 16, 1, 256, "hemisphere directions per pixel")
          .slider(UiHint::kLinear, 1, 64),
      int_param("blur", 2, 0, 8, "depth-aware blur radius in pixels (0: none)"),
      enum_param("output", "frame", {"frame", "ao"},
                 "frame: AO applied to the indirect terms; ao: the AO buffer shown as the "
                 "frame (grey)")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Ssao>(ctx, *find_technique("ssao"));
  };
  return t;
}

}  // namespace illum::realtime
