// Bloom: a bright pass into "bloom" at half resolution (what exceeds the threshold), then a
// separable Gaussian (σ = 8/3 texels): "bloom" → "bloom.scratch" horizontally, back into
// "bloom" vertically. Tonemap adds strength × bloom before mapping.
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

class Bloom final : public Technique {
 public:
  Bloom(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu,
        {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 16);
    bright_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "bloom_bright.comp");
    blur_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "bloom_blur.comp");
    for (VkDescriptorSet& s : sets_) s = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    for (const char* name : {"bloom", "bloom.scratch"}) {
      ResourceDesc r;
      r.name = name;
      r.frame_divisor = 2;
      r.format = VK_FORMAT_R16G16B16A16_SFLOAT;
      r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
      graph.add_resource(r);
    }
    PassDesc p;
    p.name = "bloom";
    p.technique = name();
    p.phase = Phase::kPost;
    p.accesses = {{"hdr", kSampled, kComputeShader},
                  {"bloom", kStorageWrite, kComputeShader},
                  {"bloom", kSampled, kComputeShader},
                  {"bloom.scratch", kStorageWrite, kComputeShader},
                  {"bloom.scratch", kSampled, kComputeShader}};
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    FrameResources& r = ctx_.resources;
    const VkImageView src[3] = {r.image("hdr").view(), r.image("bloom").view(),
                                r.image("bloom.scratch").view()};
    const VkImageView dst[3] = {r.image("bloom").view(), r.image("bloom.scratch").view(),
                                r.image("bloom").view()};
    gpu::DescriptorWriter w;
    for (int k = 0; k < 3; ++k)
      w.image(sets_[k], 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src[k],
              ctx_.globals.clamp_linear().handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
          .image(sets_[k], 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, dst[k], VK_NULL_HANDLE,
                 VK_IMAGE_LAYOUT_GENERAL);
    w.commit(ctx_.gpu.device());
  }

 private:
  // Bright pass into bloom, Gaussian bloom → scratch horizontally, scratch → bloom vertically.
  void record(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const gpu::ImageDesc& d = ctx_.resources.image("bloom").desc();
    struct {
      float dx, dy, threshold;
      int32_t radius;
    } push{0.0f, 0.0f, param<float>("threshold"), 8};
    for (int k = 0; k < 3; ++k) {
      if (k == 1) pass.use("bloom", kSampled, kComputeShader);
      if (k == 2) {
        pass.use("bloom.scratch", kSampled, kComputeShader);
        pass.use("bloom", kStorageWrite, kComputeShader);
      }
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE,
                        k == 0 ? bright_.handle() : blur_.handle());
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &sets_[k],
                              0, nullptr);
      push.dx = k == 1 ? 1.0f : 0.0f;
      push.dy = k == 2 ? 1.0f : 0.0f;
      vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
      vkCmdDispatch(c, (d.width + 15) / 16, (d.height + 15) / 16, 1);
    }
  }

  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline bright_, blur_;
  VkDescriptorSet sets_[3] = {VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE};
};

}  // namespace

TechniqueDecl bloom_technique() {
  TechniqueDecl t;
  t.name = "bloom";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "bright pass above a threshold at half resolution, separable Gaussian (σ = 8/3 texels), "
      "added before tone mapping";
  t.params = {
      float_param("strength", 0.5f, 0.0f, 100.0f,
                  "how much of the blurred bright pass is added (alias bloom_strength: a value "
                  "> 0 also switches bloom on, 0 off)")
          .aka("bloom_strength", true)
          .slider(UiHint::kLinear, 0, 2),
      float_param("threshold", 1.0f, 0.0f, 1e6f, "radiance above which pixels glow")
          .aka("bloom_threshold")
          .slider(UiHint::kLinear, 0, 10),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Bloom>(ctx, *find_technique("bloom"));
  };
  return t;
}

}  // namespace illum::realtime
