// Auto-exposure: core/auto_exposure.h's rule on the GPU. Each 16×16 workgroup counts its
// pixels' log2 luminance in a shared-memory histogram and adds it to the frame's
// (luminance.comp); one workgroup applies the percentile rule to it (luminance_reduce.comp)
// and leaves the exposure after the bins; tonemap reads it. Every frame's exposure is that
// frame's own (no adaptation over time), so a single `illum frame` gets the rule's value.
#include "illum/core/auto_exposure.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

class Luminance final : public Technique {
 public:
  Luminance(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu,
        {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 0);
    tiles_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "luminance.comp");
    reduce_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "luminance_reduce.comp");
    set_ = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    ResourceDesc r;
    r.name = "luminance";
    r.kind = ResourceDesc::Kind::kBuffer;
    r.bytes = kExposureBufferBytes;
    // Cleared by a fill; read back by Renderer::auto_exposure().
    r.extra_usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    graph.add_resource(r);
    PassDesc p;
    p.name = "luminance";
    p.technique = name();
    p.phase = Phase::kPost;
    p.accesses = {{"hdr", kSampled, kComputeShader},
                  {"luminance", kStorageWrite, kComputeShader},
                  {"luminance", kStorageRead | kStorageWrite, kComputeShader}};
    p.record = [this](PassContext& pass) {
      const VkCommandBuffer c = pass.cmd();
      const uint32_t tx = (ctx_.width() + 15) / 16, ty = (ctx_.height() + 15) / 16;
      const VkBuffer buffer = ctx_.resources.buffer("luminance").handle();
      // The last frame's tonemap read the buffer; the histogram starts from zero.
      gpu::memory_barrier(
          c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
          VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      vkCmdFillBuffer(c, buffer, 0, kExposureBufferBytes, 0u);
      gpu::memory_barrier(
          c, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &set_, 0,
                              nullptr);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, tiles_.handle());
      vkCmdDispatch(c, tx, ty, 1);
      pass.use("luminance", kStorageRead | kStorageWrite, kComputeShader);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_.handle());
      vkCmdDispatch(c, 1, 1, 1);
    };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    gpu::DescriptorWriter()
        .image(set_, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
               ctx_.resources.image("hdr").view(), ctx_.globals.nearest().handle(),
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        .buffer(set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                ctx_.resources.buffer("luminance").handle())
        .commit(ctx_.gpu.device());
  }

 private:
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline tiles_, reduce_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace

TechniqueDecl luminance_technique() {
  TechniqueDecl t;
  t.name = "luminance";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "auto-exposure: core's rule on the GPU (log2-luminance histogram, mean of the 50–95 % "
      "percentiles mapped to 0.18); tonemap scales by exposure × it (off: --fixed-exposure)";
  t.default_on = true;
  t.switch_alias = "auto_exposure";
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Luminance>(ctx, *find_technique("luminance"));
  };
  return t;
}

}  // namespace illum::realtime
