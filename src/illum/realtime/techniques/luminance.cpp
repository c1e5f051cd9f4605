// Auto-exposure's measurement: the log-average luminance of the HDR frame. Each 16×16 tile
// sums log(δ + L) (luminance.comp), one workgroup reduces the partials and leaves
// L_avg = exp(mean) after them (luminance_reduce.comp); tonemap reads it.
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

uint32_t luminance_tiles(uint32_t width, uint32_t height) {
  return ((width + 15) / 16) * ((height + 15) / 16);
}

namespace {

class Luminance final : public Technique {
 public:
  Luminance(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu,
        {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 8);
    tiles_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "luminance.comp");
    reduce_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "luminance_reduce.comp");
    set_ = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    ResourceDesc r;
    r.name = "luminance";
    r.kind = ResourceDesc::Kind::kBuffer;
    r.bytes = (luminance_tiles(ctx_.width(), ctx_.height()) + 1) * sizeof(float);
    r.extra_usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;  // Renderer::log_average_luminance()
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
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &set_, 0,
                              nullptr);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, tiles_.handle());
      vkCmdDispatch(c, tx, ty, 1);
      pass.use("luminance", kStorageRead | kStorageWrite, kComputeShader);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_.handle());
      const uint32_t push[2] = {tx * ty, ctx_.width() * ctx_.height()};
      vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), push);
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
      "auto-exposure: the log-average luminance L_avg of the HDR frame (16×16 tile sums, one "
      "reduction); tonemap then scales by exposure · key / L_avg (off: --fixed-exposure)";
  t.default_on = true;
  t.switch_alias = "auto_exposure";
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Luminance>(ctx, *find_technique("luminance"));
  };
  return t;
}

}  // namespace illum::realtime
