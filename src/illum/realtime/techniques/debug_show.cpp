// -p debug.show=RESOURCE[:LAYER][:mip=N]: any image the frame graph declares, shown in the
// 8-bit output in place of the frame. The pass runs after tone mapping and overwrites "ldr",
// so what is written and shown is the resource, not the lit frame, whatever the exposure.
// LAYER picks a layer of an array or cube (array) image, or a depth slice of a 3-D one;
// mip=N a mip level. The texel under each output pixel (nearest, stretched to the frame):
// float colour as is (clamped to [0, 1]), a single channel as grey, depth linearised with the
// camera's planes (view depth ÷ far; debug.depth=raw shows the stored value, e.g. for shadow
// maps), unsigned integers (the visibility buffer's ids) as hashed colours. An unknown name
// is refused with the declared ones listed.
#include <algorithm>
#include <charconv>
#include <map>

#include "illum/core/error.h"
#include "illum/gpu/pipeline.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// Must match shaders/debug_show.glsl.
enum ShowMode : int32_t { kColour = 0, kGrey = 1, kDepth = 2, kHashed = 3, kRawDepth = 4 };

struct ShowSpec {
  std::string resource;
  uint32_t layer = 0;
  uint32_t mip = 0;
};

uint32_t number(const std::string& text, const std::string& spec) {
  uint32_t n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    throw Error(fmt::format("-p debug.show={}: '{}' is not a layer or mip=N", spec, text));
  return n;
}

ShowSpec parse_spec(const std::string& text) {
  ShowSpec s;
  size_t start = 0;
  for (int field = 0;; ++field) {
    const size_t colon = text.find(':', start);
    const std::string part = text.substr(start, colon - start);
    if (field == 0)
      s.resource = part;
    else if (part.rfind("mip=", 0) == 0)
      s.mip = number(part.substr(4), text);
    else if (field == 1)
      s.layer = number(part, text);
    else
      throw Error(
          fmt::format("-p debug.show={}: expected RESOURCE[:LAYER][:mip=N], not '{}'", text, part));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  if (s.resource.empty())
    throw Error(fmt::format("-p debug.show={}: no resource name before ':'", text));
  return s;
}

bool is_unsigned_integer(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R8_UINT:
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32G32_UINT:
    case VK_FORMAT_R32G32B32A32_UINT:
      return true;
    default:
      return false;
  }
}

bool single_channel(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R8_UNORM:
    case VK_FORMAT_R16_UNORM:
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R32_SFLOAT:
      return true;
    default:
      return false;
  }
}

class DebugShow final : public Technique {
 public:
  DebugShow(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    spec_text_ = param<std::string>("show");
    if (!spec_text_.empty()) spec_ = parse_spec(spec_text_);
    using B = gpu::DescriptorBinding;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu,
        {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 16);
    for (View& v : views_) v.set = descriptors_.allocate(set_layout_);
  }

  ~DebugShow() override { drop_views(); }

  void declare(FrameGraph& graph) override {
    if (spec_text_.empty()) return;  // switched on without a resource: nothing to show
    std::vector<std::string> known;
    for (const ResourceDesc& r : graph.resources()) {
      if (r.kind != ResourceDesc::Kind::kImage) continue;
      known.push_back(r.name);
      if (r.history) known.push_back(r.name + ".previous");
    }
    if (std::find(known.begin(), known.end(), spec_.resource) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      const bool buffer = graph.has_resource(spec_.resource);
      throw Error(fmt::format("-p debug.show={}: {} '{}' (images of this frame: {})", spec_text_,
                              buffer ? "debug.show shows images; a buffer is" : "no image",
                              spec_.resource, list));
    }
    if (spec_.resource == "ldr")
      throw Error(fmt::format("-p debug.show={}: 'ldr' is the output it is shown in", spec_text_));
    const ResourceDesc& r = graph.resource(spec_.resource);
    const uint32_t w = r.frame_divisor ? std::max(1u, ctx_.width() / r.frame_divisor) : r.width;
    const uint32_t h = r.frame_divisor ? std::max(1u, ctx_.height() / r.frame_divisor) : r.height;
    const uint32_t levels = r.mips ? r.mips : gpu::mip_chain_length(w, h, r.depth);
    if (spec_.mip >= levels)
      throw Error(fmt::format("-p debug.show={}: '{}' has {} mip level(s)", spec_text_,
                              spec_.resource, levels));
    volume_ = r.depth > 1;
    const uint32_t layers = volume_ ? std::max(1u, r.depth >> spec_.mip) : r.layers;
    if (spec_.layer >= layers)
      throw Error(fmt::format("-p debug.show={}: '{}' has {} {}", spec_text_, spec_.resource,
                              layers, volume_ ? "slice(s) at that level" : "layer(s)"));
    format_ = r.format;
    depth_ = is_depth_format(r.format);
    if (depth_)
      mode_ = param<std::string>("depth") == "raw" ? kRawDepth : kDepth;
    else if (is_unsigned_integer(r.format))
      mode_ = kHashed;
    else
      mode_ = single_channel(r.format) ? kGrey : kColour;
    if (volume_ && mode_ == kHashed)
      throw Error(fmt::format("-p debug.show={}: integer 3-D images are not shown", spec_text_));
    const std::string shader = volume_            ? "debug_show_3d.comp"
                               : mode_ == kHashed ? "debug_show_uint.comp"
                                                  : "debug_show.comp";
    if (!pipelines_.count(shader))
      pipelines_[shader] = gpu::Pipeline(ctx_.gpu, layout_.handle(), shader);
    pipeline_ = pipelines_.at(shader).handle();

    PassDesc p;
    p.name = "debug.show";
    p.technique = name();
    p.phase = Phase::kDisplay;  // after tonemap (registry order): the output is the resource
    p.accesses = {Access{spec_.resource, kSampled, kComputeShader}.mips(spec_.mip).layers(
                      volume_ ? 0 : spec_.layer),
                  {"ldr", kStorageWrite, kComputeShader}};
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  // The frame's images may have been re-created: views are made again at the next record.
  void bind() override { drop_views(); }

 private:
  struct View {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
  };

  void drop_views() {
    for (View& v : views_) {
      if (v.view) vkDestroyImageView(ctx_.gpu.device(), v.view, nullptr);
      v.view = VK_NULL_HANDLE;
      v.image = VK_NULL_HANDLE;
    }
  }

  // The set for the copy of the resource bound now (history resources alternate two).
  VkDescriptorSet set_for(const gpu::GpuImage& image) {
    for (const View& v : views_)
      if (v.image == image.handle()) return v.set;
    View* slot = &views_[0];
    for (View& v : views_)
      if (!v.view) slot = &v;
    if (slot->view) vkDestroyImageView(ctx_.gpu.device(), slot->view, nullptr);
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image.handle();
    vi.viewType = volume_ ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format_;
    vi.subresourceRange = {static_cast<VkImageAspectFlags>(depth_ ? VK_IMAGE_ASPECT_DEPTH_BIT
                                                                  : VK_IMAGE_ASPECT_COLOR_BIT),
                           spec_.mip, 1, volume_ ? 0 : spec_.layer, 1};
    ILLUM_VK(vkCreateImageView(ctx_.gpu.device(), &vi, nullptr, &slot->view));
    slot->image = image.handle();
    // The frame graph leaves a sampled depth buffer in the read-only depth layout.
    const VkImageLayout layout = depth_ ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
                                        : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    gpu::DescriptorWriter()
        .image(slot->set, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, slot->view,
               ctx_.globals.nearest().handle(), layout)
        .image(slot->set, 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ctx_.resources.image("ldr").view(),
               VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL)
        .commit(ctx_.gpu.device());
    return slot->set;
  }

  void record(PassContext& pass) {
    const gpu::GpuImage* image = pass.image(spec_.resource);
    ILLUM_CHECK(image, "debug.show: no image bound to '{}'", spec_.resource);
    const VkDescriptorSet set = set_for(*image);
    const VkCommandBuffer c = pass.cmd();
    struct {
      int32_t mode, slice;
      float near_over_far, unused;
    } push{mode_, static_cast<int32_t>(spec_.layer), ctx_.view().near_plane / ctx_.view().far_plane,
           0.0f};
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1, &set, 0,
                            nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdPushConstants(c, layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 15) / 16, (ctx_.height() + 15) / 16, 1);
  }

  std::string spec_text_;
  ShowSpec spec_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  bool depth_ = false, volume_ = false;
  ShowMode mode_ = kColour;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  std::map<std::string, gpu::Pipeline> pipelines_;  // by shader: the resource's kind
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  View views_[2];
};

}  // namespace

TechniqueDecl debug_show_technique() {
  TechniqueDecl t;
  t.name = "debug";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "inspection: shows one image of the frame graph in the output instead of the frame "
      "(after tone mapping; switched on by -p debug.show=RESOURCE)";
  // It writes over the 8-bit output that tone mapping declares and writes.
  t.dependencies = {"tonemap"};
  ParamDecl show =
      string_param("show", "",
                   "RESOURCE[:LAYER][:mip=N]: the image to show (a layer of an array or "
                   "cube, a slice of a 3-D image); colour as is, one channel as grey, depth "
                   "linearised, unsigned integers as hashed colours")
          .structural();
  show.key_switches = true;
  t.params = {
      show,
      enum_param("depth", "camera", {"camera", "raw"},
                 "depth images: view depth ÷ far with the camera's planes, or the stored value")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<DebugShow>(ctx, *find_technique("debug"));
  };
  return t;
}

}  // namespace illum::realtime
