// SSAO (S001 §4.3 with Méndez's term; docs/realtime.md "SSAO"): occlusion of the indirect
// terms from the depth buffer and the normals, blurred depth-aware, then applied to the
// ambient, light-map and ambient-cube terms only — not to PRT, whose transfer already holds
// the visibility (shaders/lighting_inputs.glsl, indirect_occlusion).
//
// Passes (each its own timer scope): "ssao.prepare" (the plane pyramid "ssao.planes": per
// pixel its surface plane, normals from the G-buffer or the depth buffer,
// and its coarser levels in one dispatch, shaders/ssao_prepare.comp), "ssao" (the
// estimator, shaders/ssao.comp, into "ssao.raw": one estimate per 2×2 pixels by default, per
// pixel with -p ssao.resolution=full), "ssao.blur" (the bilateral upsample and blur to the
// full-resolution "ssao"). "ssao" is the `ssao` lighting input
// (lighting_inputs.h, shaders/inputs/ssao.glsl): every pipeline's shading multiplies the
// indirect term by it (by the minimum with any other occlusion), never the direct light. With
// -p ssao.output=ao, "ssao.show" writes the AO buffer into the HDR target instead.
#include <algorithm>
#include <bit>

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
  glm::ivec4 info;  // directions, blur radius, march steps, 1: G-buffer normals bound
  glm::ivec4 grid;  // estimator divisor, pyramid levels, estimates across and down
};

constexpr VkFormat kAoFormat = VK_FORMAT_R32_SFLOAT;
// Distances, plane offsets and packed normals as bits (ssao_set.glsl).
constexpr VkFormat kPlaneFormat = VK_FORMAT_R32G32B32A32_UINT;
// Level m serves taps 2^(m+3) pixels away and more: 6 levels keep 32-pixel texels for the
// farthest taps (a radius projected past 256 pixels), and one prepare group (32×32 pixels,
// shaders/ssao_prepare.comp) holds every source of its coarse texels. Must match
// kSsaoMaxLevels of shaders/ssao_set.glsl.
constexpr uint32_t kMaxLevels = 6;
const char* const kGbufferNormals = "gbuffer.normal";

class Ssao final : public Technique {
 public:
  Ssao(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const auto storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, cis}, B{2, cis}, B{3, cis},
                  B{4, storage}, B{5, storage}, B{6, cis}, B{7, storage, kMaxLevels}});
    layout_ = ctx.globals.shading_layout(set_layout_.handle());
    prepare_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_prepare.comp");
    estimate_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao.comp");
    blur_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_blur.comp");
    show_ = param<std::string>("output") == "ao";
    if (show_) show_pass_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "ssao_show.comp");
    uniforms_ = gpu::Buffer(ctx.gpu, sizeof(SsaoUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            gpu::MemoryUsage::kUpload);
    for (VkDescriptorSet& s : sets_) s = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    // Deferred: the G-buffer's normals (an optional read, resolved in bind()); other
    // pipelines: normals from the depth buffer, computed where they are needed.
    divisor_ = param<std::string>("resolution") == "half" ? 2 : 1;
    grid_ = {std::max(ctx_.width() / divisor_, 1u), std::max(ctx_.height() / divisor_, 1u)};
    levels_ = std::min<uint32_t>(kMaxLevels, std::bit_width(std::max(ctx_.width(), ctx_.height())));
    auto image = [&](const char* name, VkFormat format, uint32_t divisor, uint32_t mips) {
      ResourceDesc r;
      r.name = name;
      r.frame_divisor = divisor;
      r.format = format;
      r.mips = mips;
      graph.add_resource(r);
    };
    image("ssao.planes", kPlaneFormat, 1, levels_);
    image("ssao.raw", kAoFormat, divisor_, 1);
    image("ssao", kAoFormat, 1, 1);
    const auto cs = kComputeShader;
    const Access planes_write{"ssao.planes", kStorageWrite, cs};
    const Access planes_read{"ssao.planes", kSampled, cs};
    std::vector<Access> inputs = {{"depth", kSampled, cs}};
    inputs.push_back(Access{kGbufferNormals, kSampled, cs}.if_produced());
    PassDesc n;
    n.name = "ssao.prepare";
    n.technique = name();
    n.phase = Phase::kScreenSpace;
    n.accesses = inputs;
    n.accesses.push_back(planes_write);
    n.record = [this](PassContext& pass) {
      dispatch(pass, prepare_, sets_[kPrepareSet], {0, 0}, kPrepareBlock);
    };
    graph.add_pass(std::move(n));
    PassDesc e;
    e.name = "ssao";
    e.technique = name();
    e.phase = Phase::kScreenSpace;
    e.accesses = {{"depth", kSampled, cs}, planes_read, {"ssao.raw", kStorageWrite, cs}};
    e.record = [this](PassContext& pass) { dispatch(pass, estimate_, sets_[kEstimateSet], grid_); };
    graph.add_pass(std::move(e));
    PassDesc b;
    b.name = "ssao.blur";
    b.technique = name();
    b.phase = Phase::kScreenSpace;
    b.accesses = inputs;
    b.accesses.push_back(planes_read);
    b.accesses.push_back({"ssao.raw", kSampled, cs});
    b.accesses.push_back({"ssao", kStorageWrite, cs});
    b.record = [this](PassContext& pass) {
      dispatch(pass, blur_, sets_[kBlurSet], {ctx_.width(), ctx_.height()});
    };
    graph.add_pass(std::move(b));
    if (!show_) return;  // the shading passes read "ssao" as a lighting input
    PassDesc a;
    a.technique = name();
    a.phase = Phase::kLighting;
    a.name = "ssao.show";
    a.accesses = {{"ssao", kSampled, cs}, {"hdr", kStorageWrite, cs}};
    a.record = [this](PassContext& pass) { dispatch(pass, show_pass_, sets_[kApplySet]); };
    graph.add_pass(std::move(a));
  }

  std::vector<LightingContribution> lighting_inputs() const override {
    if (show_) return {};  // the frame shows the AO buffer itself
    return {{"ssao",
             [this](gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
               w.image(set, base, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                       ctx_.resources.image("ssao").view(), ctx_.globals.nearest().handle(),
                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
             },
             {"ssao"}}};
  }

  void bind() override {
    gbuffer_normals_ = ctx_.graph().reads("ssao.prepare", kGbufferNormals);
    FrameResources& r = ctx_.resources;
    const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const auto storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    const VkSampler nearest = ctx_.globals.nearest().handle();
    const VkImageView depth = r.image("depth").view();
    const VkImageView dummy = ctx_.globals.dummy_2d().view();
    const VkImageView normals = gbuffer_normals_ ? r.image(kGbufferNormals).view() : dummy;
    const VkImageView raw = r.image("ssao.raw").view(), ao = r.image("ssao").view();
    const gpu::GpuImage& planes = r.image("ssao.planes");
    // Every binding of every set holds a valid image (lavapipe crashed in the dispatch
    // while bindings no shader of the set uses were left unwritten): what a pass does not
    // read is a dummy, what it does not write the raw AO.
    auto write = [&](gpu::DescriptorWriter& w, VkDescriptorSet s, VkImageView normal_view,
                     VkImageView source, VkImageView target, VkImageView hdr,
                     VkImageView plane_view) {
      // Binding 7: the pyramid's levels as storage images (levels past levels_ repeat the
      // last; the prepare pass writes only levels_).
      for (uint32_t m = 0; m < kMaxLevels; ++m)
        w.image(s, 7, storage, planes.mip_view(std::min(m, levels_ - 1)), VK_NULL_HANDLE,
                VK_IMAGE_LAYOUT_GENERAL, m);
      w.buffer(s, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
          .image(s, 1, cis, depth, nearest,
                 VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
          .image(s, 2, cis, normal_view, nearest, ro)
          .image(s, 3, cis, source, nearest, ro)
          .image(s, 4, storage, target, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL)
          .image(s, 5, storage, hdr, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL)
          .image(s, 6, cis, plane_view, nearest, ro);
    };
    gpu::DescriptorWriter w;
    const VkImageView all_planes = planes.view();
    write(w, sets_[kPrepareSet], normals, dummy, planes.mip_view(0), raw, all_planes);
    write(w, sets_[kEstimateSet], normals, dummy, raw, raw, all_planes);
    write(w, sets_[kBlurSet], normals, raw, ao, raw, all_planes);
    write(w, sets_[kApplySet], dummy, ao, raw, show_ ? r.image("hdr").view() : raw, all_planes);
    w.commit(ctx_.gpu.device());
  }

  void update() override {
    SsaoUniforms u{};
    const float radius = radius_in_scene_units();
    const float falloff = param<float>("falloff");
    u.shape = vec4(radius, param<float>("bias"), param<float>("intensity"),
                   falloff > 0.0f ? falloff : radius);
    u.info = glm::ivec4(param<int>("samples"), param<int>("blur"), kMarchSteps,
                        gbuffer_normals_ ? 1 : 0);
    u.grid = glm::ivec4(divisor_, levels_, grid_.x, grid_.y);
    uniforms_.write(&u, sizeof(u));
  }

 private:
  enum { kPrepareSet, kEstimateSet, kBlurSet, kApplySet, kSets };
  // Steps along each direction before the bisection (6 halvings: the hit distance is known
  // to R/(6·64)). Six steps estimate as closely as eight did (Cornell and Sibenik against the
  // offline ao, docs/realtime-ssao.md) with a quarter fewer fetches and comparisons.
  static constexpr int kMarchSteps = 6;

  float radius_in_scene_units() const {
    const float radius = param<float>("radius");
    return radius > 0.0f ? radius : kAutoRadius * ctx_.scene.bounds().diagonal();
  }

  // Over `size` pixels (0: the frame's size), group × group pixels a workgroup.
  void dispatch(PassContext& pass, const gpu::Pipeline& pipeline, VkDescriptorSet set,
                glm::uvec2 size = {0, 0}, uint32_t group = 8) {
    if (size.x == 0) size = {ctx_.width(), ctx_.height()};
    const VkCommandBuffer c = pass.cmd();
    bind_shading_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), ctx_.globals,
                      ctx_.shading_sets(set));
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (size.x + group - 1) / group, (size.y + group - 1) / group, 1);
  }

  static constexpr float kAutoRadius = 0.02f;
  // The pixels of one prepare workgroup across: its coarsest texel.
  static constexpr uint32_t kPrepareBlock = 1u << (kMaxLevels - 1);

  bool show_ = false, gbuffer_normals_ = false;
  uint32_t divisor_ = 1, levels_ = 1;
  glm::uvec2 grid_{1, 1};  // the estimates: the frame's size ÷ divisor_
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline prepare_, estimate_, blur_, show_pass_;
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
      "over a hemisphere of marched directions against a pyramid of the depth buffer's "
      "planes, at half (default) or full resolution, depth-aware upsample and blur; scales "
      "the ambient, "
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
      enum_param("resolution", "half", {"full", "half"},
                 "estimator resolution: half estimates one pixel of each 2×2 and upsamples "
                 "depth-aware to full resolution")
          .structural(),
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
