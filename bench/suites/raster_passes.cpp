#include "raster_passes.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "suites.h"

namespace illum::bench {

namespace {

using Depth = gpu::RasterFill::Depth;

// The mixed pass's index buffer and its push constants (bound_mixed.vert's block).
struct MixedMesh {
  std::vector<uint32_t> indices;
  struct {
    int32_t width = 1, height = 1, setup_vertices = 0;
    float partial = 1.0f;
    int32_t rectangles = 0, patch = 1, spread = 0;
  } push;
};

}  // namespace

uint32_t patch_vertices(uint32_t triangles, uint32_t patch) {
  const uint32_t per_patch = 2 * patch * patch;
  return (triangles + per_patch - 1) / per_patch * (patch + 1) * (patch + 1);
}

void append_patch_triangle(std::vector<uint32_t>& indices, uint32_t t, uint32_t patch) {
  const uint32_t per_patch = 2 * patch * patch, side = patch + 1;
  const uint32_t base = t / per_patch * side * side, cell = t % per_patch / 2;
  const uint32_t i = cell % patch, j = cell / patch;
  const auto v = [&](uint32_t x, uint32_t y) { return base + y * side + x; };
  if (t % 2 == 0)
    indices.insert(indices.end(), {v(i, j), v(i + 1, j), v(i, j + 1)});
  else
    indices.insert(indices.end(), {v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
}

namespace {

// The rectangles spread evenly among the setup triangles, as a scene's large and small
// triangles mix, so the chip can overlap the setup of the one with the pixels of the other.
MixedMesh make_mixed(uint32_t width, uint32_t height, uint32_t triangles, double layers,
                     uint32_t patch, bool scatter, bool cover) {
  MixedMesh m;
  const int full = static_cast<int>(std::floor(layers));
  const double partial = layers - full;
  m.push.width = static_cast<int32_t>(width);
  m.push.height = static_cast<int32_t>(height);
  const uint32_t setup_vertices = patch_vertices(triangles, patch);
  m.push.setup_vertices = static_cast<int32_t>(setup_vertices);
  m.push.patch = static_cast<int32_t>(patch);
  m.push.spread = cover ? 2 : scatter ? 1 : 0;
  m.push.rectangles = full + (partial > 1e-6 ? 1 : 0);
  m.push.partial = partial > 1e-6 ? static_cast<float>(partial) : 1.0f;
  const uint32_t rectangles = static_cast<uint32_t>(m.push.rectangles);
  m.indices.reserve(3 * (static_cast<size_t>(triangles) + 2 * rectangles));
  uint32_t next = 0;  // rectangle
  for (uint32_t t = 0; t <= triangles; ++t) {
    while (next < rectangles &&
           static_cast<uint64_t>(next + 1) * triangles / (rectangles + 1) <= t) {
      const uint32_t base = setup_vertices + 4 * next++;
      m.indices.insert(m.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
    }
    if (t < triangles) append_patch_triangle(m.indices, t, patch);
  }
  return m;
}

}  // namespace

bool is_uint(VkFormat f) {
  return f == VK_FORMAT_R32_UINT || f == VK_FORMAT_R32G32_UINT || f == VK_FORMAT_R8_UINT;
}

// The trivial pass into `f`'s attachments, `repeats` times (after 2 untimed), each its own
// rendering scope after a barrier as a frame's passes are; returns the times.
std::vector<double> time_fill(gpu::Context& ctx, const gpu::RasterFill& f, int repeats,
                              const BoundGeometry& geometry, double* vertex_invocations) {
  const bool mixed = geometry.setup_triangles > 0;
  std::vector<gpu::GpuImage> colors;
  for (VkFormat c : f.colors) {
    gpu::ImageDesc d;
    d.width = f.width;
    d.height = f.height;
    d.format = c;
    d.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    colors.emplace_back(ctx, d);
  }
  gpu::GpuImage depth;
  if (f.depth != Depth::kNone) {
    gpu::ImageDesc d;
    d.width = f.width;
    d.height = f.height;
    d.format = f.depth_format;
    d.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    depth = gpu::GpuImage(ctx, d);
  }
  const bool stencil_mode = f.depth == Depth::kStencil || f.depth == Depth::kStencilTest ||
                            f.depth == Depth::kStencilZFail;
  // Rejected fragments: the depth is cleared to 0 so the full-screen triangle (z = 0.5)
  // fails LESS everywhere, as overdraw behind nearer surfaces fails.
  const bool rejecting = f.depth == Depth::kReject || f.depth == Depth::kStencilZFail;
  if (stencil_mode && !gpu::has_stencil(f.depth_format))
    throw Error(fmt::format("fill {}: a stencil mode on a format without stencil", f.key()));
  const bool uint_target = !f.colors.empty() && is_uint(f.colors[0]);
  for (VkFormat c : f.colors)
    if (is_uint(c) != uint_target)
      throw Error(fmt::format("fill {}: mixed integer and float colour targets", f.key()));
  if (uint_target && f.colors.size() > 1)
    throw Error(fmt::format("fill {}: more than one integer target", f.key()));

  MixedMesh mesh;
  gpu::Buffer index_buffer;
  if (mixed) {
    mesh = make_mixed(f.width, f.height, geometry.setup_triangles, geometry.mixed_layers,
                      geometry.patch, geometry.scatter, geometry.cover);
    index_buffer =
        gpu::make_device_buffer(ctx, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t),
                                VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  }
  gpu::PipelineLayout layout(ctx, {}, mixed ? sizeof(mesh.push) : 0);
  gpu::GraphicsPipelineDesc p;
  p.vertex_shader = mixed ? "bound_mixed.vert" : "bound_fill.vert";
  p.fragment_shader = f.colors.empty() ? ""
                      : uint_target    ? "bound_fill_uint.frag"
                                       : fmt::format("bound_fill{}.frag", f.colors.size());
  p.cull = VK_CULL_MODE_NONE;
  p.color_formats = f.colors;
  p.color_write = !f.colors.empty();
  p.additive_blend = f.blend;
  p.depth_format = f.depth_format;
  if (gpu::has_stencil(f.depth_format)) p.stencil_format = f.depth_format;
  p.depth_test = f.depth == Depth::kWrite || f.depth == Depth::kTest || rejecting;
  p.depth_write = f.depth == Depth::kWrite;
  p.depth_compare = rejecting ? VK_COMPARE_OP_LESS : VK_COMPARE_OP_LESS_OR_EQUAL;
  if (stencil_mode) {
    p.stencil_test = true;
    VkStencilOpState s{};
    s.failOp = s.depthFailOp = VK_STENCIL_OP_KEEP;
    s.passOp = f.depth == Depth::kStencil ? VK_STENCIL_OP_INCREMENT_AND_WRAP : VK_STENCIL_OP_KEEP;
    if (f.depth == Depth::kStencilZFail) s.depthFailOp = VK_STENCIL_OP_INCREMENT_AND_WRAP;
    s.compareOp = f.depth == Depth::kStencilTest ? VK_COMPARE_OP_EQUAL : VK_COMPARE_OP_ALWAYS;
    s.compareMask = s.writeMask = 0xff;
    p.stencil_front = p.stencil_back = s;
  }
  gpu::Pipeline pipeline(ctx, layout.handle(), p);

  // The depth is loaded where the frame's passes load it (tested, not written), cleared
  // where they clear it.
  const bool load_depth = f.depth == Depth::kTest || f.depth == Depth::kStencilTest;
  const VkImageLayout ds = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  const VkPipelineStageFlags2 ds_stages =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  const VkAccessFlags2 ds_access = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  const VkPipelineStageFlags2 color_stage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  const VkAccessFlags2 color_access =
      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  // The mixed pass checks what it drew: an occlusion query around its first (untimed)
  // repetition must count exactly its layers' samples (the set-up triangles cover none).
  VkQueryPool samples = VK_NULL_HANDLE;
  if (mixed) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_OCCLUSION;
    qi.queryCount = 1;
    if (vkCreateQueryPool(ctx.device(), &qi, nullptr, &samples) != VK_SUCCESS)
      throw Error("illum-bench raster: cannot create an occlusion query pool");
  }
  // And, where the device counts them, its vertex shader invocations (what the setup
  // triangles' shared vertices save).
  VkQueryPool statistics = VK_NULL_HANDLE;
  if (mixed && vertex_invocations && ctx.pipeline_statistics()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    qi.queryCount = 1;
    qi.pipelineStatistics = VK_QUERY_PIPELINE_STATISTIC_VERTEX_SHADER_INVOCATIONS_BIT;
    if (vkCreateQueryPool(ctx.device(), &qi, nullptr, &statistics) != VK_SUCCESS)
      throw Error("illum-bench raster: cannot create a pipeline statistics query pool");
  }
  const int total = repeats + 2;
  gpu::GpuTimer timer(ctx, static_cast<uint32_t>(total));
  ctx.immediate([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    if (samples) vkCmdResetQueryPool(cmd, samples, 0, 1);
    if (statistics) vkCmdResetQueryPool(cmd, statistics, 0, 1);
    for (int r = 0; r < total; ++r) {
      // Each pass waits for the last, as a frame's passes writing one target do.
      for (gpu::GpuImage& c : colors)
        c.transition(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, color_stage, color_access);
      if (depth) depth.transition(cmd, ds, ds_stages, ds_access);
      std::vector<VkRenderingAttachmentInfo> attachments;
      for (size_t i = 0; i < colors.size(); ++i) {
        const gpu::GpuImage& c = colors[i];
        VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        a.imageView = c.view();
        a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        a.loadOp =
            (f.uncleared >> i) & 1u ? VK_ATTACHMENT_LOAD_OP_DONT_CARE : VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        attachments.push_back(a);
      }
      VkRenderingAttachmentInfo d{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      d.imageView = depth ? depth.view() : VK_NULL_HANDLE;
      d.imageLayout = ds;
      // The first (untimed) repetition clears what the others load.
      d.loadOp = load_depth && r > 0 ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
      d.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      d.clearValue.depthStencil = {rejecting ? 0.0f : 1.0f, 0};
      VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
      info.renderArea = {{0, 0}, {f.width, f.height}};
      info.layerCount = 1;
      info.colorAttachmentCount = static_cast<uint32_t>(attachments.size());
      info.pColorAttachments = attachments.data();
      info.pDepthAttachment = depth ? &d : nullptr;
      info.pStencilAttachment = depth && gpu::has_stencil(f.depth_format) ? &d : nullptr;
      const uint32_t scope = timer.begin(cmd, "fill");
      vkCmdBeginRendering(cmd, &info);
      const VkViewport vp{0.0f, 0.0f, static_cast<float>(f.width), static_cast<float>(f.height),
                          0.0f, 1.0f};
      const VkRect2D scissor{{0, 0}, {f.width, f.height}};
      vkCmdSetViewport(cmd, 0, 1, &vp);
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
      if (stencil_mode) vkCmdSetStencilReference(cmd, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
      // Everything at one depth: each layer passes (LESS_OR_EQUAL) or fails alike.
      if (mixed) {
        vkCmdPushConstants(cmd, layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(mesh.push),
                           &mesh.push);
        vkCmdBindIndexBuffer(cmd, index_buffer.handle(), 0, VK_INDEX_TYPE_UINT32);
        if (r == 0) vkCmdBeginQuery(cmd, samples, 0, VK_QUERY_CONTROL_PRECISE_BIT);
        if (r == 0 && statistics) vkCmdBeginQuery(cmd, statistics, 0, 0);
        vkCmdDrawIndexed(cmd, static_cast<uint32_t>(mesh.indices.size()), 1, 0, 0, 0);
        if (r == 0 && statistics) vkCmdEndQuery(cmd, statistics, 0);
        if (r == 0) vkCmdEndQuery(cmd, samples, 0);
      } else {
        for (int l = 0; l < geometry.layers; ++l) vkCmdDraw(cmd, 3, 1, 0, 0);
      }
      vkCmdEndRendering(cmd);
      timer.end(cmd, scope);
      // Tell the tracked state what the pass did, so the next barrier starts from it.
      for (gpu::GpuImage& c : colors)
        c.assume_state(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, color_stage, color_access);
      if (depth) depth.assume_state(ds, ds_stages, ds_access);
    }
  });
  // A one-query pool's result, the pool destroyed; false where the result did not come.
  auto take_result = [&](VkQueryPool pool, uint64_t* counted) {
    const VkResult got =
        vkGetQueryPoolResults(ctx.device(), pool, 0, 1, sizeof(*counted), counted, sizeof(*counted),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
    vkDestroyQueryPool(ctx.device(), pool, nullptr);
    return got == VK_SUCCESS;
  };
  if (vertex_invocations) *vertex_invocations = -1.0;
  uint64_t invocations = 0;
  if (statistics && take_result(statistics, &invocations))
    *vertex_invocations = static_cast<double>(invocations);
  if (samples) {
    uint64_t counted = 0;
    const bool got = take_result(samples, &counted);
    // Whole layers, and the rows of the partial one whose pixel centres it covers (one row
    // of slack for how the edge falls on them).
    const double full = std::floor(geometry.mixed_layers);
    const double rows = std::ceil((geometry.mixed_layers - full) * f.height - 0.5 - 1e-9);
    const double want = (full * f.height + std::max(0.0, rows)) * f.width +
                        (geometry.cover && !rejecting ? geometry.setup_triangles : 0.0);
    if (!got || std::abs(static_cast<double>(counted) - want) > f.width)
      throw Error(fmt::format(
          "illum-bench raster: the mixed pass for {} covered {} samples, not the {} of {:.4f} "
          "layers{}",
          f.key(), counted, want, geometry.mixed_layers,
          geometry.cover ? fmt::format(" and {} one-sample triangles", geometry.setup_triangles)
                         : ""));
  }
  std::vector<double> ms;
  const std::vector<gpu::PassTime> times = timer.resolve();
  for (size_t i = 2; i < times.size(); ++i) ms.push_back(times[i].ms);
  return ms;
}

// The geometry bound: ms per triangle of `triangles` indexed triangles in `patch` grids of
// shared vertices (as the setup triangles below), every vertex at one point
// (shaders/bound_tris.vert): vertex work and assembly of every triangle, culled before
// rasterization — less than a real triangle costs (no setup, no pixel), so passes judged by
// it are at least this slow.
double ms_per_triangle(gpu::Context& ctx, uint32_t triangles, int repeats,
                       std::vector<double>* runs, uint32_t patch) {
  std::vector<uint32_t> indices;
  indices.reserve(3 * static_cast<size_t>(triangles));
  for (uint32_t t = 0; t < triangles; ++t) append_patch_triangle(indices, t, patch);
  gpu::Buffer index_buffer = gpu::make_device_buffer(
      ctx, indices.data(), indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  gpu::ImageDesc d;
  d.width = d.height = 1;
  d.format = VK_FORMAT_R8G8B8A8_UNORM;
  d.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  gpu::GpuImage target(ctx, d);
  gpu::PipelineLayout layout(ctx, {}, 0);
  gpu::GraphicsPipelineDesc p;
  p.vertex_shader = "bound_tris.vert";
  p.fragment_shader = "bound_fill1.frag";
  p.cull = VK_CULL_MODE_NONE;
  p.depth_test = p.depth_write = false;
  p.color_formats = {d.format};
  gpu::Pipeline pipeline(ctx, layout.handle(), p);
  const int total = repeats + 2;
  gpu::GpuTimer timer(ctx, static_cast<uint32_t>(total));
  const VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  const VkAccessFlags2 access =
      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  ctx.immediate([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    for (int r = 0; r < total; ++r) {
      target.transition(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, stage, access);
      VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      a.imageView = target.view();
      a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
      info.renderArea = {{0, 0}, {d.width, d.height}};
      info.layerCount = 1;
      info.colorAttachmentCount = 1;
      info.pColorAttachments = &a;
      const uint32_t scope = timer.begin(cmd, "triangles");
      vkCmdBeginRendering(cmd, &info);
      const float size = static_cast<float>(d.width);
      const VkViewport vp{0.0f, 0.0f, size, size, 0.0f, 1.0f};
      const VkRect2D scissor{{0, 0}, {d.width, d.height}};
      vkCmdSetViewport(cmd, 0, 1, &vp);
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
      vkCmdBindIndexBuffer(cmd, index_buffer.handle(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, 3 * triangles, 1, 0, 0, 0);
      vkCmdEndRendering(cmd);
      timer.end(cmd, scope);
      target.assume_state(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, stage, access);
    }
  });
  const std::vector<gpu::PassTime> times = timer.resolve();
  for (size_t i = 2; i < times.size(); ++i) runs->push_back(times[i].ms);
  return median(*runs) / triangles;
}

// The setup bound: ms per triangle of `triangles` sub-pixel triangles covering no sample on a
// 1024² colour target — the mixed pass without rectangles (bound_mixed.vert), `patch` × `patch`
// cells of shared vertices in a corner of a pixel each, pixels row by row or scattered.
double setup_ms_per_triangle(gpu::Context& ctx, uint32_t triangles, int repeats,
                             std::vector<double>* runs, uint32_t patch, bool scatter,
                             double* vertex_invocations) {
  gpu::RasterFill f;
  f.width = f.height = 1024;
  f.colors = {VK_FORMAT_R8G8B8A8_UNORM};
  f.depth = Depth::kNone;
  BoundGeometry g;
  g.setup_triangles = triangles;
  g.patch = patch;
  g.scatter = scatter;
  *runs = time_fill(ctx, f, repeats, g, vertex_invocations);
  return median(*runs) / triangles;
}

double covering_ms_per_triangle(gpu::Context& ctx, const gpu::RasterFill& f, uint32_t triangles,
                                int repeats, std::vector<double>* runs, uint32_t patch) {
  BoundGeometry g;
  g.setup_triangles = triangles;
  g.patch = patch;
  g.cover = true;
  *runs = time_fill(ctx, f, repeats, g);
  return median(*runs) / triangles;
}

// Copy bandwidth (bytes read + written per ms) of two device-local buffers of `bytes`.
double copy_bytes_per_ms(gpu::Context& ctx, VkDeviceSize bytes, int repeats,
                         std::vector<double>* runs) {
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  gpu::Buffer a(ctx, bytes, usage, gpu::MemoryUsage::kDevice);
  gpu::Buffer b(ctx, bytes, usage, gpu::MemoryUsage::kDevice);
  const int total = repeats + 2;
  gpu::GpuTimer timer(ctx, static_cast<uint32_t>(total));
  ctx.immediate([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    vkCmdFillBuffer(cmd, a.handle(), 0, VK_WHOLE_SIZE, 0x3f800000u);
    for (int r = 0; r < total; ++r) {
      gpu::memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                          VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                          VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                          VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
      const uint32_t scope = timer.begin(cmd, "copy");
      const VkBufferCopy region{0, 0, bytes};
      // Alternate directions so every copy reads what the last one wrote.
      vkCmdCopyBuffer(cmd, r % 2 ? b.handle() : a.handle(), r % 2 ? a.handle() : b.handle(), 1,
                      &region);
      timer.end(cmd, scope);
    }
  });
  const std::vector<gpu::PassTime> times = timer.resolve();
  for (size_t i = 2; i < times.size(); ++i) runs->push_back(times[i].ms);
  const double ms = median(*runs);
  return ms > 0.0 ? 2.0 * static_cast<double>(bytes) / ms : 0.0;
}

}  // namespace illum::bench
