// `light_volume`: the worked example of docs/realtime-techniques.md, small on purpose. It owns
// a 3-D volume over the scene's bounds holding, per cell, the linear irradiance E(n) = a + b·n
// of the frame's lights at the cell centre (shaders/light_volume.comp, closed form per
// light), keeps a history copy of it and blends each update with the previous one (after a
// light moves the volume converges by (1 − blend)^k instead of jumping), and contributes
// albedo · E(n)/π × strength as the indirect term of every frame pipeline through the
// lighting input of the same name (shaders/inputs/light_volume.glsl). What it is not: no
// visibility (light passes through walls), no bounce (it is direct light, added again as an
// ambient term) — a demonstration of the interface, not a global-illumination method.
#include <algorithm>
#include <array>

#include "illum/gpu/buffer.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

constexpr const char* kVolume = "light_volume";
constexpr const char* kPrevious = "light_volume.previous";

// shaders/inputs/light_volume.glsl and light_volume.comp `LightVolumeInput` (std140).
struct LightVolumeUniforms {
  glm::vec4 lo;      // xyz: the volume's min corner; w: strength
  glm::vec4 extent;  // xyz: its size; w: blend
  glm::ivec4 info;  // x: cells per axis, y: the copy written last, z: a previous copy holds a frame
  glm::vec4 limits;  // x: the least squared distance to a light
};
static_assert(sizeof(LightVolumeUniforms) == 64);

class LightVolume final : public Technique {
 public:
  LightVolume(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                  B{2, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}});
    // Sets 0 and 1 as the shading passes have them (the lights), set 2 the volume's.
    layout_ = gpu::PipelineLayout(
        ctx.gpu,
        {ctx.globals.layout(0).handle(), ctx.globals.layout(1).handle(), set_layout_.handle()}, 0);
    update_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "light_volume.comp");
    for (VkDescriptorSet& s : sets_) s = descriptors_.allocate(set_layout_);
    uniforms_ = gpu::Buffer(ctx.gpu, sizeof(LightVolumeUniforms),
                            VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
    cells_ = static_cast<uint32_t>(param<int>("cells"));
    // The scene's bounds; a flat scene still gets a box with some thickness.
    const Bounds3 b = ctx.scene.bounds();
    const vec3 size = b.max - b.min;
    const float largest = std::max({size.x, size.y, size.z, 1e-3f});
    u_.lo = vec4(b.min, 0.0f);
    u_.extent = vec4(glm::max(size, vec3(1e-3f * largest)), 0.0f);
    const vec3 cell = vec3(u_.extent) / static_cast<float>(cells_);
    const float half = 0.5f * std::min({cell.x, cell.y, cell.z});
    u_.limits = vec4(half * half, 0.0f, 0.0f, 0.0f);
    u_.info = glm::ivec4(static_cast<int>(cells_), 0, 0, 0);
  }

  void declare(FrameGraph& graph) override {
    ResourceDesc r;
    r.name = kVolume;
    r.width = 3 * cells_;  // R, G and B parts side by side
    r.height = cells_;
    r.depth = cells_;  // a 3-D image, sampled trilinearly
    r.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    r.history = true;  // "light_volume.previous": the copy the blend starts from
    // Read back by tests and shown by -p debug.show=light_volume.
    r.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    graph.add_resource(r);

    PassDesc p;
    p.name = "light_volume";
    p.technique = name();
    // Before every pass that shades: the deferred G-buffer pass gathers the surface inputs in
    // the geometry phase.
    p.phase = Phase::kShadows;
    p.accesses = {{kVolume, kStorageWrite, kComputeShader},
                  {kPrevious, kStorageRead, kComputeShader}};
    // Every `period` frames, and at the next frame after the lights or this technique's
    // parameters change.
    p.schedule = Schedule::every_n(param<int>("period"), 0, kLightsChanged | kParametersChanged);
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    // Set k writes copy k and reads the other: the copies swap each time the pass runs.
    gpu::DescriptorWriter w;
    for (int k = 0; k < 2; ++k) {
      w.image(sets_[k], 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
              ctx_.resources.image(kVolume, k).view(), VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL)
          .image(sets_[k], 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                 ctx_.resources.image(kVolume, 1 - k).view(), VK_NULL_HANDLE,
                 VK_IMAGE_LAYOUT_GENERAL)
          .buffer(sets_[k], 2, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle());
    }
    w.commit(ctx_.gpu.device());
  }

  void update() override {
    u_.lo.w = param<float>("strength");
    u_.extent.w = param<float>("blend");
    uniforms_.write(&u_, sizeof(u_));
  }

  std::vector<LightingContribution> lighting_inputs() const override {
    LightingContribution c;
    c.input = "light_volume";
    // Set 4 is written once per assembly while the copies alternate, so both are bound and
    // the uniforms name the newest (record()).
    c.write = [this](gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
      w.buffer(set, base, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle());
      for (uint32_t k = 0; k < 2; ++k)
        w.image(set, base + 1 + k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                ctx_.resources.image(kVolume, static_cast<int>(k)).view(),
                ctx_.globals.clamp_linear().handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    c.reads = {kVolume, kPrevious};
    return {c};
  }

 private:
  void record(PassContext& pass) {
    // The frame has not been submitted yet and the previous one is complete (Renderer::render
    // waits), so the uniforms written here are the ones this whole frame reads.
    const int copy = pass.copy(kVolume);
    u_.info.y = copy;
    u_.info.z = pass.has_history(kVolume) ? 1 : 0;
    uniforms_.write(&u_, sizeof(u_));
    const VkCommandBuffer c = pass.cmd();
    const std::array<VkDescriptorSet, 3> sets = {ctx_.globals.frame_set(),
                                                 ctx_.globals.material_set(0), sets_[copy]};
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 3, sets.data(),
                            0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, update_.handle());
    const uint32_t groups = (cells_ + 3) / 4;
    vkCmdDispatch(c, groups, groups, groups);
  }

  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline update_;
  std::array<VkDescriptorSet, 2> sets_{};
  gpu::Buffer uniforms_;
  LightVolumeUniforms u_{};
  uint32_t cells_ = 16;
};

}  // namespace

TechniqueDecl light_volume_technique() {
  TechniqueDecl t;
  t.name = "light_volume";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "teaching example (docs/realtime-techniques.md): a cells³ volume of the lights' "
      "unshadowed linear irradiance, blended over frames, as the indirect term albedo·E/π × "
      "strength; no visibility, no bounce";
  t.params = {
      int_param("cells", 16, 2, 64, "cells along each axis of the scene's bounds").structural(),
      float_param("blend", 0.1f, 0.001f, 1.0f,
                  "weight of the new value at each update (1: no history; smaller converges "
                  "more slowly after a light moves)"),
      float_param("strength", 1.0f, 0.0f, 100.0f, "scales the indirect term"),
      int_param("period", 1, 1, 60, "update every N frames (readers keep the newest copy)")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<LightVolume>(ctx, *find_technique("light_volume"));
  };
  return t;
}

}  // namespace illum::realtime
