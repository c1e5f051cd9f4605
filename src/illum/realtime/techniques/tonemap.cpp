// HDR → display: exposure (× the auto exposure when luminance is on), bloom added (when on),
// a tone mapper, sRGB encoding into "ldr", the 8-bit image the frame is written and shown
// from.
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

int mapper_index(const std::string& name) {
  const std::vector<std::string>& choices = find_technique("tonemap")->param("operator")->choices;
  return static_cast<int>(std::find(choices.begin(), choices.end(), name) - choices.begin());
}

class Tonemap final : public Technique {
 public:
  Tonemap(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    set_layout_ =
        gpu::DescriptorSetLayout(ctx.gpu, {B{0, cis}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                           B{2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, B{3, cis}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 16);
    pipeline_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "tonemap.comp");
    set_ = descriptors_.allocate(set_layout_);
  }

  void declare(FrameGraph& graph) override {
    ResourceDesc ldr;
    ldr.name = "ldr";
    ldr.frame_divisor = 1;
    ldr.format = kLdrFormat;
    // Read back (Renderer::ldr()) and blitted to the window (illum view).
    ldr.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    graph.add_resource(ldr);
    PassDesc p;
    p.name = "tonemap";
    p.technique = name();
    p.phase = Phase::kDisplay;
    // The auto exposure and bloom where those add-ons are on (optional reads).
    p.accesses = {{"hdr", kSampled, kComputeShader},
                  {"ldr", kStorageWrite, kComputeShader},
                  Access{"luminance", kStorageRead, kComputeShader}.if_produced(),
                  Access{"bloom", kSampled, kComputeShader}.if_produced()};
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    luminance_ = ctx_.graph().reads("tonemap", "luminance");
    bloom_ = ctx_.graph().reads("tonemap", "bloom");
    FrameResources& r = ctx_.resources;
    const FrameGlobals& g = ctx_.globals;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    gpu::DescriptorWriter()
        .image(set_, 0, cis, r.image("hdr").view(), g.nearest().handle(),
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        .buffer(set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                luminance_ ? r.buffer("luminance").handle() : g.dummy_buffer().handle())
        .image(set_, 2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, r.image("ldr").view(), VK_NULL_HANDLE,
               VK_IMAGE_LAYOUT_GENERAL)
        .image(set_, 3, cis, bloom_ ? r.image("bloom").view() : g.dummy_2d().view(),
               g.clamp_linear().handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        .commit(ctx_.gpu.device());
  }

 private:
  void record(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const uint32_t tx = (ctx_.width() + 15) / 16, ty = (ctx_.height() + 15) / 16;
    struct {
      int32_t mapper, auto_exposure;
      float exposure, bloom_strength;
    } push{mapper_index(param<std::string>("operator")), luminance_ ? 1 : 0,
           param<float>("exposure"), bloom_ ? ctx_.settings().get<float>("bloom.strength") : 0.0f};
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &set_, 0,
                            nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, tx, ty, 1);
  }

  bool luminance_ = false, bloom_ = false;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline pipeline_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace

TechniqueDecl tonemap_technique() {
  TechniqueDecl t;
  t.name = "tonemap";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "exposure (× the auto exposure with luminance on), bloom added, a tone mapper, sRGB into "
      "the 8-bit output the frame is written and shown from";
  t.default_on = true;
  t.params = {
      enum_param("operator", "aces", {"clamp", "reinhard", "aces", "agx"},
                 "clamp, Reinhard (luminance), ACES (Narkowicz fit), AgX (Sobotka)")
          .aka("tone_mapper"),
      float_param("exposure", 1.0f, 0.0f, 1e6f,
                  "exposure: a multiplier on the auto exposure, or the whole exposure without it")
          .aka("exposure")
          .slider(UiHint::kLogarithmic, 0.01, 100),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Tonemap>(ctx, *find_technique("tonemap"));
  };
  return t;
}

}  // namespace illum::realtime
