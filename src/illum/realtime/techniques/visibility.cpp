// The visibility-buffer pipeline: one raster pass writes the depth and a 32-bit id per pixel
// (no pre-pass: the pass writes 4 bytes of colour a pixel, whatever the overdraw), then one
// compute pass rebuilds each pixel's surface from the vertex and index buffers
// (shaders/visibility_resolve.comp: the pixel ray against the triangle for the barycentrics,
// analytic UV derivatives for the texture LOD; one indirect dispatch per material in use
// over the 8×8 tiles a classification pass found showing it, with that material's textures
// bound as a draw binds them) and lights it with the lighting.glsl functions
// the other pipelines use, the same shadow lookups and the same baked-lighting set.
//
// Id packing: id = draw << T | triangle, T = the bits of the largest mesh's triangle count
// (at least 1), the draw index in the remaining 32 − T bits; 0xFFFFFFFF (every bit set)
// marks pixels nothing covered, so the last draw index that fits is 2^(32−T) − 2. A scene
// whose draws and triangles do not fit is refused with both counts.
#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

VisibilityPacking visibility_packing(size_t draws, size_t max_triangles) {
  VisibilityPacking p;
  p.triangle_bits =
      std::max(1, static_cast<int>(std::bit_width(max_triangles > 0 ? max_triangles - 1 : 0)));
  if (p.triangle_bits >= 32 ||
      (draws > 0 && static_cast<uint64_t>(draws - 1) > (uint64_t(1) << (32 - p.triangle_bits)) - 2))
    throw Error(fmt::format(
        "--technique visibility: {} draws and up to {} triangles a mesh do not fit the 32-bit "
        "visibility id ({} triangle bits leave room for {} draws); use deferred",
        draws, max_triangles, p.triangle_bits,
        p.triangle_bits >= 32 ? 0 : (uint64_t(1) << (32 - p.triangle_bits)) - 1));
  return p;
}

namespace {

constexpr VkFormat kIdFormat = VK_FORMAT_R32_UINT;
constexpr const char* kIds = "visibility.ids";
constexpr const char* kTileArgs = "visibility.tile_args";  // per slot: dispatch x, 1, 1, 0
constexpr const char* kTiles = "visibility.tiles";         // per slot: its tiles
constexpr size_t kMaxSlots = 2048;  // shaders/visibility_classify.comp: 64 × 32 bits

// shaders/visibility_resolve.comp DrawData (std430).
struct GpuDrawData {
  glm::mat4 model;
  glm::ivec4 info;  // material, first index, vertex offset, 0
};
static_assert(sizeof(GpuDrawData) == 80);

class Visibility final : public FramePipeline {
 public:
  Visibility(TechniqueContext& ctx, const TechniqueDecl& decl)
      : FramePipeline(ctx, decl), descriptors_(ctx.gpu) {
    if (ctx.shadow_method().masks_lights())
      throw Error(
          "--technique visibility does not run with --shadows volume (the volumes add each "
          "light over a G-buffer or a second scene draw); use deferred or forward");
    if (!ctx.gpu.primitive_id())
      throw Error(
          fmt::format("--technique visibility: device '{}' lacks the geometryShader feature "
                      "(gl_PrimitiveID in the id pass)",
                      ctx.gpu.device_name()));
    const GpuScene& scene = ctx.scene;
    size_t max_triangles = 0;
    std::vector<GpuDrawData> draws;
    for (const DrawItem& d : scene.draws()) {
      const MeshRange& r = scene.meshes()[d.mesh];
      max_triangles = std::max<size_t>(max_triangles, r.index_count / 3);
      const int material = ctx.globals.material_index(d.material);
      auto slot = std::find(materials_.begin(), materials_.end(), material);
      if (slot == materials_.end()) slot = materials_.insert(materials_.end(), material);
      draws.push_back(
          {d.transform, glm::ivec4(material, static_cast<int>(r.first_index), r.vertex_offset,
                                   static_cast<int>(slot - materials_.begin()))});
    }
    packing_ = visibility_packing(draws.size(), max_triangles);
    if (materials_.size() > kMaxSlots)
      throw Error(fmt::format(
          "--technique visibility: the scene's draws use {} materials (the tile classification "
          "holds {}); use deferred",
          materials_.size(), kMaxSlots));
    if (draws.empty()) draws.push_back({});
    draws_ = gpu::make_device_buffer(ctx.gpu, draws.data(), draws.size() * sizeof(GpuDrawData),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);

    using B = gpu::DescriptorBinding;
    const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu, {B{0, cis}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, B{2, ssbo}, B{3, ssbo},
                  B{4, ssbo}, B{5, ssbo}, B{6, ssbo}, B{7, cis}});
    set_ = descriptors_.allocate(set_layout_);
    layout_ = ctx.globals.shading_layout(set_layout_.handle());
    gpu::DescriptorWriter w;
    w.buffer(set_, 2, ssbo, scene.vertices().handle())
        .buffer(set_, 3, ssbo, scene.indices().handle())
        .buffer(set_, 4, ssbo, draws_.handle())
        .commit(ctx.gpu.device());

    gpu::GraphicsPipelineDesc g;
    g.vertex_shader = "visibility.vert";
    g.fragment_shader = "visibility.frag";
    g.vertex_input = mesh_vertex_input(true);
    g.cull = VK_CULL_MODE_NONE;  // two-sided, as the other pipelines
    g.color_formats = {kIdFormat};
    g.depth_format = ctx.depth_format;
    g.stencil_format = ctx.depth_format;
    raster_ = gpu::Pipeline(ctx.gpu, ctx.globals.default_layout(), g);
    raster_count_ = CountingPipelines(ctx.gpu, ctx.globals.default_layout(), g);
    resolve_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "visibility_resolve.comp");
    classify_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "visibility_classify.comp");
  }

  void declare(FrameGraph& graph) override {
    graph.add_resource(hdr_target(VK_IMAGE_USAGE_STORAGE_BIT));
    graph.add_resource(depth_target(ctx_.depth_format));
    ResourceDesc ids;
    ids.name = kIds;
    ids.frame_divisor = 1;
    ids.format = kIdFormat;
    ids.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // Renderer::read_resource (tests)
    graph.add_resource(ids);
    PassDesc p;
    p.name = "visibility";
    p.technique = name();
    p.phase = Phase::kGeometry;
    // Occlusion culling samples the depth between the pass's two halves, in a scope beside it.
    p.accesses = {
        {kIds, kColorAttachment}, {"depth", kDepthAttachment}, {"depth", kSampled, kComputeShader}};
    p.nested_scopes = 2;
    p.record = [this](PassContext& pass) { record_ids(pass); };
    graph.add_pass(std::move(p));
    const uint64_t tiles = uint64_t((ctx_.width() + 7) / 8) * ((ctx_.height() + 7) / 8);
    ResourceDesc args;
    args.name = kTileArgs;
    args.kind = ResourceDesc::Kind::kBuffer;
    args.bytes = 16 * materials_.size();
    graph.add_resource(args);
    ResourceDesc list = args;
    list.name = kTiles;
    list.bytes = 4 * tiles * materials_.size();
    graph.add_resource(list);
    PassDesc c;
    c.name = "visibility_classify";
    c.technique = name();
    c.phase = Phase::kLighting;
    c.accesses = {{kIds, kSampled, kComputeShader},
                  {"depth", kSampled, kComputeShader},
                  {"hdr", kStorageWrite, kComputeShader},
                  {kTileArgs, kTransferDst},
                  {kTiles, kStorageWrite, kComputeShader},
                  {kTileArgs, kStorageRead | kStorageWrite, kComputeShader}};
    c.record = [this](PassContext& pass) { record_classify(pass); };
    graph.add_pass(std::move(c));
    PassDesc r;
    r.name = "visibility_resolve";
    r.technique = name();
    r.phase = Phase::kLighting;
    r.accesses = {{kIds, kSampled, kComputeShader},
                  {"depth", kSampled, kComputeShader},
                  {"hdr", kStorageWrite, kComputeShader},
                  {kTileArgs, kIndirectArgs},
                  {kTiles, kStorageRead, kComputeShader}};
    for (const Access& a : ctx_.shading_reads(kComputeShader)) r.accesses.push_back(a);
    r.record = [this](PassContext& pass) { record_resolve(pass); };
    graph.add_pass(std::move(r));
  }

  void bind() override {
    FrameResources& r = ctx_.resources;
    gpu::DescriptorWriter()
        .image(set_, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, r.image(kIds).view(),
               ctx_.globals.nearest().handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        .image(set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, r.image("hdr").view(), VK_NULL_HANDLE,
               VK_IMAGE_LAYOUT_GENERAL)
        .buffer(set_, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, r.buffer(kTileArgs).handle())
        .buffer(set_, 6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, r.buffer(kTiles).handle())
        .image(set_, 7, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, r.image("depth").view(),
               ctx_.globals.nearest().handle(),
               VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
        .commit(ctx_.gpu.device());
  }

  void record_masked_light(PassContext&, int) override {
    throw InternalError("the visibility pipeline runs without masked lights");
  }

 private:
  void record_ids(PassContext& pass) {
    DrawTargets t;
    // Undefined where nothing is drawn: the classification and the resolve test the depth.
    t.colors = {{ctx_.resources.image(kIds).view(), false, {}, true}};
    t.depth = ctx_.resources.image("depth").layer_view(0);
    t.depth_resource = "depth";
    t.stencil = true;
    t.extent = {ctx_.width(), ctx_.height()};
    SceneView view =
        SceneView::camera(ctx_.view().view_proj, true, SceneView::Occlusion::kTwoPhase);
    view.mode = packing_.triangle_bits;  // push.mode, read by visibility.frag
    using D = gpu::RasterFill::Depth;
    const uint32_t w = t.extent.width, h = t.extent.height;
    ctx_.drawer.render_counted(pass, t, raster_, raster_count_, ctx_.globals.default_layout(),
                               ctx_.shading_sets(), view,
                               {w, h, {kIdFormat}, ctx_.depth_format, D::kWrite, false, 1u},
                               {w, h, {kIdFormat}, ctx_.depth_format, D::kReject, false, 1u});
  }

  // Zeroes every slot's tile count (y = z = 1), then classifies the tiles.
  void record_classify(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const std::vector<glm::uvec4> zero(materials_.size(), glm::uvec4(0, 1, 1, 0));
    if (!zero.empty())  // a scene without draws: only the empty pixels to write
      vkCmdUpdateBuffer(c, ctx_.resources.buffer(kTileArgs).handle(), 0,
                        zero.size() * sizeof(glm::uvec4), zero.data());
    pass.use(kTileArgs, kStorageRead | kStorageWrite, kComputeShader);
    const VkPipelineLayout layout = layout_.handle();
    bind_shading_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout, ctx_.globals,
                      ctx_.shading_sets(set_));
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, classify_.handle());
    PushConstants push{};
    push.mode = packing_.triangle_bits;
    vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(c, (ctx_.width() + 7) / 8, (ctx_.height() + 7) / 8, 1);
  }

  // One indirect dispatch per material in use over the tiles that show it, its textures
  // bound as set 1 (the resolve shades that material's pixels only). The dispatches write
  // disjoint pixels: no barrier between them.
  void record_resolve(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const VkPipelineLayout layout = layout_.handle();
    bind_shading_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout, ctx_.globals,
                      ctx_.shading_sets(set_));
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_.handle());
    PushConstants push{};
    push.mode = packing_.triangle_bits;
    const VkBuffer args = ctx_.resources.buffer(kTileArgs).handle();
    for (size_t slot = 0; slot < materials_.size(); ++slot) {
      const int m = materials_[slot];
      const VkDescriptorSet material = ctx_.globals.material_set(m);
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout, kMaterialSet, 1, &material,
                              0, nullptr);
      push.material = m;
      push.light_index = static_cast<int>(slot);
      vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
      vkCmdDispatchIndirect(c, args, slot * sizeof(glm::uvec4));
    }
  }

  VisibilityPacking packing_;
  std::vector<int> materials_;  // the material sets the draws use, each once
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  gpu::PipelineLayout layout_;
  gpu::Buffer draws_;
  gpu::Pipeline raster_, classify_, resolve_;
  CountingPipelines raster_count_;
};

}  // namespace

TechniqueDecl visibility_technique() {
  TechniqueDecl t;
  t.name = "visibility";
  t.kind = TechniqueKind::kFramePipeline;
  t.summary =
      "visibility buffer: one raster pass of depth + a 32-bit draw/triangle id (no pre-pass), "
      "then one compute pass rebuilds each pixel's surface from the vertex and index buffers "
      "(analytic UV derivatives) and lights it";
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Visibility>(ctx, *find_technique("visibility"));
  };
  return t;
}

}  // namespace illum::realtime
