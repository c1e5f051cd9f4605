// `vpl`: instant radiosity from the reflective shadow maps (Keller 1997 with Dachsbacher &
// Stamminger's maps as the light's first bounce; docs/realtime-vpl.md). Two compute passes:
//
// - "vpl.build" (shadows phase, after rsm): per layer of the source maps (rsm_views.h), one
//   virtual point light per block of texels — `count` per layer, 8×8 … 64×64, or one per
//   texel where the map has fewer — drawn within the block in proportion to its flux and
//   weighted so that its expected contribution is the block's (shaders/vpl_build.comp), into
//   the buffer "vpl.lights";
// - "vpl" (screen-space phase): every pixel's irradiance from all of them, cosine-lobed
//   point lights with an optional minimum distance (shaders/vpl_gather.comp), into
//   "vpl.irradiance", which the lighting input `vpl` reads at the pixel as the indirect term
//   (shaders/inputs/vpl.glsl). The sum runs once per pixel in a compute pass, not inside the
//   frame pipelines' shaders: a loop over a thousand lights in a lighting input is the kind of
//   per-pixel code lavapipe's compiler has corrupted its heap on (docs/realtime-techniques.md).
//
// No visibility between a VPL and the points it lights (docs/realtime-vpl.md: shadows).
#include <cmath>
#include <string>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/rsm_views.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

constexpr const char* kLights = "vpl.lights";
constexpr const char* kIrradiance = "vpl.irradiance";
// The draw within each block is a hash of the block and this: fixed, so that a still scene
// keeps its VPLs from frame to frame (no flicker) and results repeat.
constexpr int kSeed = 1;

// shaders/vpl_common.glsl `Vpl` (std430).
struct VplLight {
  glm::vec4 position, normal, flux;
};
static_assert(sizeof(VplLight) == 48);

// shaders/vpl_build.comp `VplBuild` (std140).
struct BuildUniforms {
  glm::ivec4 info;  // VPLs per side of a layer, texels per side, layers, seed
};
// shaders/vpl_gather.comp `VplGather` (std140).
struct GatherUniforms {
  glm::ivec4 info;   // x: VPLs in the buffer
  glm::vec4 params;  // x: clamp²
};

class Vpl final : public Technique {
 public:
  Vpl(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    const int count = param<int>("count");
    if (count != 64 && count != 256 && count != 1024 && count != 4096)
      throw Error(fmt::format("-p vpl.count={}: one of 64, 256, 1024, 4096", count));
    if (ctx.settings().pipeline == "deferred")
      throw Error(
          "vpl: the deferred pipeline applies screen-space lighting inputs' occlusion only, not "
          "an indirect term; use -t forward or visibility");
    side_ = static_cast<int>(std::lround(std::sqrt(static_cast<double>(count))));
    source_ = param<std::string>("source");
    using B = gpu::DescriptorBinding;
    constexpr VkDescriptorType kSsbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    constexpr VkDescriptorType kTexture = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    build_set_layout_ =
        gpu::DescriptorSetLayout(ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, kTexture},
                                           B{2, kTexture}, B{3, kTexture}, B{4, kSsbo}});
    build_layout_ = gpu::PipelineLayout(ctx.gpu, {build_set_layout_.handle()}, 0);
    build_ = gpu::Pipeline(ctx.gpu, build_layout_.handle(), "vpl_build.comp");
    gather_set_layout_ =
        gpu::DescriptorSetLayout(ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, kTexture},
                                           B{2, kSsbo}, B{3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
    gather_layout_ = ctx.globals.shading_layout(gather_set_layout_.handle());
    gather_ = gpu::Pipeline(ctx.gpu, gather_layout_.handle(), "vpl_gather.comp");
    build_set_ = descriptors_.allocate(build_set_layout_);
    gather_set_ = descriptors_.allocate(gather_set_layout_);
    build_uniforms_ = gpu::Buffer(ctx.gpu, sizeof(BuildUniforms),
                                  VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
    gather_uniforms_ = gpu::Buffer(ctx.gpu, sizeof(GatherUniforms),
                                   VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  }

  void declare(FrameGraph& graph) override {
    // The source is named by the user: its maps must be declared before vpl is (rsm, and
    // shadow methods, declare earlier).
    for (const char* part : {".position", ".normal", ".flux"})
      if (!graph.has_resource(source_ + part))
        throw Error(fmt::format("-p vpl.source={}: nothing in this frame declares '{}{}'", source_,
                                source_, part));
    ResourceDesc lights;
    lights.name = kLights;
    lights.kind = ResourceDesc::Kind::kBuffer;
    // Room for the most layers a source has (rsm_views.h); bind() counts those used.
    lights.bytes = VkDeviceSize(rsm::kRsmMaxLayers) * side_ * side_ * sizeof(VplLight);
    graph.add_resource(lights);
    ResourceDesc e;
    e.name = kIrradiance;
    e.frame_divisor = 1;
    e.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    // Read back by tests, shown by -p debug.show=vpl.irradiance.
    e.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    graph.add_resource(e);

    const auto cs = kComputeShader;
    PassDesc b;
    b.name = "vpl.build";
    b.technique = name();
    b.phase = Phase::kShadows;  // after the maps (declared later in the same phase)
    b.accesses = {{kLights, kStorageWrite, cs},
                  Access{source_ + ".position", kSampled, cs}.if_produced(),
                  Access{source_ + ".normal", kSampled, cs}.if_produced(),
                  Access{source_ + ".flux", kSampled, cs}.if_produced()};
    b.record = [this](PassContext& pass) { record_build(pass); };
    graph.add_pass(std::move(b));

    PassDesc g;
    g.name = "vpl";
    g.technique = name();
    g.phase = Phase::kScreenSpace;
    g.accesses = {
        {"depth", kSampled, cs}, {kLights, kStorageRead, cs}, {kIrradiance, kStorageWrite, cs}};
    g.record = [this](PassContext& pass) { record_gather(pass); };
    graph.add_pass(std::move(g));
  }

  void bind() override {
    const std::string names[3] = {source_ + ".position", source_ + ".normal", source_ + ".flux"};
    builds_ = true;
    for (const std::string& n : names) builds_ = builds_ && ctx_.graph().reads("vpl.build", n);
    layers_ = 0;
    gpu::DescriptorWriter w;
    if (builds_) {
      const gpu::ImageDesc& d = ctx_.resources.image(names[0]).desc();
      resolution_ = static_cast<int>(d.width);
      layers_ = static_cast<int>(d.layers);
      if (d.width != d.height || layers_ > rsm::kRsmMaxLayers)
        throw Error(fmt::format("-p vpl.source={}: square maps of at most {} layers", source_,
                                rsm::kRsmMaxLayers));
      // One VPL per texel where the map has fewer texels than `count`.
      per_side_ = std::min(side_, resolution_);
      if (resolution_ % per_side_ != 0)
        throw Error(fmt::format("-p vpl.count: {} VPLs a side do not divide {}-texel maps",
                                per_side_, resolution_));
      w.buffer(build_set_, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, build_uniforms_.handle());
      for (uint32_t k = 0; k < 3; ++k)
        w.image(build_set_, 1 + k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                ctx_.resources.image(names[k]).view(), ctx_.globals.nearest().handle(),
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      w.buffer(build_set_, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
               ctx_.resources.buffer(kLights).handle());
      const BuildUniforms u{glm::ivec4(per_side_, resolution_, layers_, kSeed)};
      build_uniforms_.write(&u, sizeof(u));
    }
    w.buffer(gather_set_, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, gather_uniforms_.handle())
        .image(gather_set_, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
               ctx_.resources.image("depth").view(), ctx_.globals.nearest().handle(),
               VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
        .buffer(gather_set_, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                ctx_.resources.buffer(kLights).handle())
        .image(gather_set_, 3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
               ctx_.resources.image(kIrradiance).view(), VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    w.commit(ctx_.gpu.device());
  }

  void update() override {
    const float c = param<float>("clamp");
    GatherUniforms u{};
    u.info = glm::ivec4(layers_ * per_side_ * per_side_, 0, 0, 0);
    u.params = glm::vec4(c * c, 0.0f, 0.0f, 0.0f);
    gather_uniforms_.write(&u, sizeof(u));
  }

  std::vector<LightingContribution> lighting_inputs() const override {
    LightingContribution c;
    c.input = "vpl";
    c.write = [this](gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
      w.image(set, base, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
              ctx_.resources.image(kIrradiance).view(), ctx_.globals.nearest().handle(),
              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    c.reads = {kIrradiance};
    return {c};
  }

 private:
  void record_build(PassContext& pass) {
    if (!builds_) return;  // nothing produces the maps: the gather sums no lights
    const VkCommandBuffer c = pass.cmd();
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, build_layout_.handle(), 0, 1,
                            &build_set_, 0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, build_.handle());
    const uint32_t groups = (static_cast<uint32_t>(per_side_) + 7) / 8;
    vkCmdDispatch(c, groups, groups, static_cast<uint32_t>(layers_));
  }

  void record_gather(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    bind_shading_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE, gather_layout_.handle(), ctx_.globals,
                      ctx_.shading_sets(gather_set_));
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, gather_.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, gather_layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 7) / 8, (ctx_.height() + 7) / 8, 1);
  }

  int side_ = 16, per_side_ = 16, resolution_ = 0, layers_ = 0;
  bool builds_ = false;
  std::string source_;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout build_set_layout_, gather_set_layout_;
  gpu::PipelineLayout build_layout_, gather_layout_;
  gpu::Pipeline build_, gather_;
  VkDescriptorSet build_set_ = VK_NULL_HANDLE, gather_set_ = VK_NULL_HANDLE;
  gpu::Buffer build_uniforms_, gather_uniforms_;
};

}  // namespace

TechniqueDecl vpl_technique() {
  TechniqueDecl t;
  t.name = "vpl";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "instant radiosity: virtual point lights drawn from the reflective shadow maps (one per "
      "block of texels, flux-weighted), summed per pixel as cosine lobes into the indirect term "
      "(no visibility between a VPL and what it lights)";
  t.dependencies = {"rsm"};
  t.params = {
      int_param("count", 256, 64, 4096,
                "VPLs per light view: 64, 256, 1024 or 4096 (8×8 … 64×64 blocks of texels)")
          .structural(),
      float_param("clamp", 0.0f, 0.0f, 1e6f,
                  "minimum distance (world units) in the 1/d² falloff, against the spikes "
                  "next to a VPL (0: none; biased when > 0)"),
      string_param("source", "rsm",
                   "the maps the VPLs are drawn from: SOURCE.position, .normal and .flux, laid "
                   "out as the reflective shadow maps' (rsm_views.h)")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Vpl>(ctx, *find_technique("vpl"));
  };
  return t;
}

}  // namespace illum::realtime
