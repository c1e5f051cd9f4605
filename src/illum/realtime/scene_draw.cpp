#include "illum/realtime/scene_draw.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>

#include "illum/realtime/gpu_types.h"

namespace illum::realtime {

gpu::VertexInput mesh_vertex_input(bool position_only) {
  gpu::VertexInput in;
  if (position_only) {
    in.stride = kPositionStride;  // GpuScene::positions()
    in.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0});
    return in;
  }
  in.stride = sizeof(Vertex);
  in.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)});
  in.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)});
  in.attributes.push_back({2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)});
  in.attributes.push_back({3, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv0)});
  in.attributes.push_back({4, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv1)});
  return in;
}

namespace {

void set_viewport(VkCommandBuffer cmd, VkExtent2D extent) {
  VkViewport vp{0.0f, 0.0f, static_cast<float>(extent.width), static_cast<float>(extent.height),
                0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

VkRenderingAttachmentInfo attachment(VkImageView view, VkImageLayout layout, bool clear) {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = view;
  a.imageLayout = layout;
  a.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  return a;
}

// Corner k (0..7) of `b`: bit 0 picks max.x, bit 1 max.y, bit 2 max.z.
vec3 box_corner(const Bounds3& b, int k) {
  return vec3((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
              (k & 4) ? b.max.z : b.min.z);
}

// Whether every corner of `b` lies outside one clip plane of `clip` (then nothing of it can be
// rasterized); the near and far planes count only when `near` and `far` are true.
bool outside(const mat4& clip, const Bounds3& b, bool near, bool far) {
  int below_x = 0, above_x = 0, below_y = 0, above_y = 0, below_z = 0, above_z = 0;
  for (int k = 0; k < 8; ++k) {
    const vec3 p = box_corner(b, k);
    const vec4 h = clip * vec4(p, 1.0f);
    below_x += h.x < -h.w;
    above_x += h.x > h.w;
    below_y += h.y < -h.w;
    above_y += h.y > h.w;
    below_z += h.z < 0.0f;
    above_z += h.z > h.w;
  }
  return below_x == 8 || above_x == 8 || below_y == 8 || above_y == 8 || (near && below_z == 8) ||
         (far && above_z == 8);
}

}  // namespace

float cluster_depth(const mat4& clip, const Bounds3& b, SceneView::DepthKey key) {
  // Clip-space z (not divided by w) grows with distance for perspective and orthographic
  // views alike.
  const vec4 row(clip[0][2], clip[1][2], clip[2][2], clip[3][2]);
  float nearest = std::numeric_limits<float>::infinity();
  float farthest = -std::numeric_limits<float>::infinity();
  for (int k = 0; k < 8; ++k) {
    const float z = glm::dot(row, vec4(box_corner(b, k), 1.0f));
    nearest = std::min(nearest, z);
    farthest = std::max(farthest, z);
  }
  return key == SceneView::DepthKey::kCentre ? 0.5f * (nearest + farthest) : farthest;
}

std::vector<uint32_t> visible_clusters(const GpuScene& scene, const SceneView& view) {
  const std::vector<Cluster>& clusters = scene.clusters();
  std::vector<uint32_t> out;
  out.reserve(clusters.size());
  for (uint32_t c = 0; c < clusters.size(); ++c)
    if ((!view.cull ||
         !outside(*view.cull, clusters[c].bounds, view.cull_depth, view.cull_depth)) &&
        (!view.receivers || !outside(*view.receivers, clusters[c].bounds, false, true)))
      out.push_back(c);
  if (view.cull && view.front_to_back) {
    std::vector<float> depth(clusters.size());
    for (uint32_t c : out) depth[c] = cluster_depth(*view.cull, clusters[c].bounds, view.depth_key);
    std::stable_sort(out.begin(), out.end(),
                     [&](uint32_t a, uint32_t b) { return depth[a] < depth[b]; });
  }
  return out;
}

void SceneDrawer::begin(VkCommandBuffer cmd, const DrawTargets& t) const {
  std::vector<VkRenderingAttachmentInfo> colors;
  for (const DrawTargets::Color& c : t.colors) {
    colors.push_back(attachment(c.view, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, c.clear));
    colors.back().clearValue.color = c.value;
    if (c.undefined) colors.back().loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  }
  VkRenderingAttachmentInfo depth =
      attachment(t.depth, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, t.clear_depth);
  depth.clearValue.depthStencil = {1.0f, 0};
  if (!t.store_depth) depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, t.extent};
  info.layerCount = 1;
  info.colorAttachmentCount = static_cast<uint32_t>(colors.size());
  info.pColorAttachments = colors.data();
  info.pDepthAttachment = t.depth != VK_NULL_HANDLE ? &depth : nullptr;
  info.pStencilAttachment = t.stencil ? &depth : nullptr;
  vkCmdBeginRendering(cmd, &info);
  set_viewport(cmd, t.extent);
}

SceneDrawer::Drawn SceneDrawer::draw_clusters(VkCommandBuffer cmd, const gpu::Pipeline& pipeline,
                                              VkPipelineLayout layout,
                                              const std::array<VkDescriptorSet, 3>& sets,
                                              const SceneView& view,
                                              const std::vector<uint32_t>& order,
                                              VkBuffer predicates) const {
  Drawn drawn;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  bind_shading_sets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, globals_, sets);
  VkDeviceSize offset = 0;
  // Depth-like passes read positions only, from their packed stream with the index buffer of
  // welded positions (the same triangles in the same order); and no fragment stage of theirs
  // reads a material, so they bind none.
  const bool position_only = pipeline.vertex_stride() == kPositionStride;
  VkBuffer vb = position_only ? scene_.positions().handle() : scene_.vertices().handle();
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(
      cmd, position_only ? scene_.position_indices().handle() : scene_.indices().handle(), 0,
      VK_INDEX_TYPE_UINT32);
  PushConstants push{};
  push.view = view.view;
  push.light_index = view.light_index;
  push.mode = view.mode;
  const std::vector<Cluster>& clusters = scene_.clusters();
  VkDescriptorSet bound = VK_NULL_HANDLE;
  int pushed_draw = -1;
  // What was last pushed: a draw item whose constants equal it pushes nothing (the scenes'
  // draws mostly share one transform; position-only pipelines read no material, so theirs is
  // left at 0). Sorted clusters alternate draw items: the cascades pushed for 670 of their 1014
  // draws, 0.014 ms of the H200's 0.371 (bench/results/raster.md#design-choices; the run is in git
  // at c416128).
  std::optional<PushConstants> pushed;
  for (size_t k = 0; k < order.size();) {
    const Cluster& first = clusters[order[k]];
    // Runs of clusters adjacent in the index buffer go out as one draw — unless each
    // cluster's draw is predicated on its own flag.
    uint32_t count = first.index_count;
    size_t next = k + 1;
    while (!predicates && next < order.size() && order[next] == order[next - 1] + 1 &&
           clusters[order[next]].draw == first.draw) {
      count += clusters[order[next]].index_count;
      ++next;
    }
    const DrawItem& d = scene_.draws()[first.draw];
    if (pushed_draw != static_cast<int>(first.draw)) {
      pushed_draw = static_cast<int>(first.draw);
      if (view.per_draw) push.draw = static_cast<int>(first.draw);
      push.model = view.clip_from_world ? *view.clip_from_world * d.transform : d.transform;
      push.material = position_only ? 0 : globals_.material_index(d.material);
      const VkDescriptorSet material = globals_.material_set(push.material);
      if (material != bound && !position_only) {
        bound = material;
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, kMaterialSet, 1,
                                &material, 0, nullptr);
      }
      if (!pushed || std::memcmp(&*pushed, &push, sizeof(push)) != 0) {
        vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
        pushed = push;
      }
    }
    if (predicates)
      occlusion_->context().begin_conditional(cmd, predicates, order[k] * sizeof(uint32_t));
    vkCmdDrawIndexed(cmd, count, 1, first.first_index, scene_.meshes()[d.mesh].vertex_offset,
                     first.first_triangle);
    if (predicates) occlusion_->context().end_conditional(cmd);
    drawn.triangles += count / 3;
    drawn.clusters += next - k;
    k = next;
  }
  return drawn;
}

size_t SceneDrawer::draw(VkCommandBuffer cmd, const gpu::Pipeline& pipeline,
                         VkPipelineLayout layout, const std::array<VkDescriptorSet, 3>& sets,
                         const SceneView& view) const {
  return draw_clusters(cmd, pipeline, layout, sets, view, visible_clusters(scene_, view),
                       VK_NULL_HANDLE)
      .triangles;
}

void SceneDrawer::render(VkCommandBuffer cmd, const DrawTargets& targets,
                         std::initializer_list<const gpu::Pipeline*> variants,
                         VkPipelineLayout layout, const std::array<VkDescriptorSet, 3>& sets,
                         const SceneView& view) const {
  begin(cmd, targets);
  for (const gpu::Pipeline* p : variants) draw(cmd, *p, layout, sets, view);
  end(cmd);
}

namespace {

// `targets` kept as they are: every colour and the depth loaded.
DrawTargets loaded(DrawTargets t) {
  for (DrawTargets::Color& c : t.colors) c.clear = c.undefined = false;
  t.clear_depth = false;
  return t;
}

}  // namespace

void SceneDrawer::render_counted(PassContext& pass, const DrawTargets& targets,
                                 const gpu::Pipeline& variant, const CountingPipelines& counter,
                                 VkPipelineLayout layout,
                                 const std::array<VkDescriptorSet, 3>& sets, const SceneView& view,
                                 const gpu::RasterFill& passing,
                                 const gpu::RasterFill& rejected) const {
  const VkCommandBuffer cmd = pass.cmd();
  const std::vector<uint32_t> order = visible_clusters(scene_, view);
  using Occlusion = SceneView::Occlusion;
  const bool culling = occlusion_ && occlusion_->enabled(view.occlusion_key) && view.cull &&
                       view.occlusion != Occlusion::kNone && cmd != VK_NULL_HANDLE;
  const bool two_phase = culling && view.occlusion == Occlusion::kTwoPhase;
  const OcclusionCuller::View* now =
      culling && !two_phase ? occlusion_->culled(view.occlusion_key, pass.frame()) : nullptr;
  // The predicates of each half the pass draws (VK_NULL_HANDLE: every listed cluster); the
  // counting replays draw the same halves in one rendering.
  std::vector<VkBuffer> halves = {now ? now->now_flags() : VK_NULL_HANDLE};
  OcclusionCuller::View* culled = nullptr;
  if (two_phase) {
    culled = &occlusion_->begin(cmd, view.occlusion_key);
    halves = {culled->early_flags(), culled->late.handle()};
  }
  auto draw_halves = [&](const gpu::Pipeline& p, VkPipelineLayout l,
                         const std::array<VkDescriptorSet, 3>& s) {
    for (VkBuffer h : halves) draw_clusters(cmd, p, l, s, view, order, h);
  };
  // Before the pass with occlusion culling: the quads are counted after it (the replay needs
  // the predicates the culling between its halves writes) from the same start, the colours
  // loaded (the quad count writes none) and the depth cleared again, ending as the pass did.
  auto count_quads = [&](const DrawTargets& from) {
    const VkPipelineLayout quad_layout = globals_.quad_count_layout();
    pass.begin_quads(globals_.quad_counter());
    begin(cmd, from);
    draw_halves(counter.quads(quad_layout), quad_layout,
                {globals_.quad_count_set(), sets[1], sets[2]});
    end(cmd);
    pass.end_quads(globals_.quad_counter());
  };
  const bool quads = pass.counts_quads() && counter.replays(targets);
  if (quads && !culling) count_quads(targets);
  // Lavapipe crashes on occlusion queries around depth-tested draws in frames that also
  // build shadow volumes on the GPU: there every fragment counts as rejected (a lower bound).
  // The queries span both halves and the culling between them, which draws nothing.
  const bool split = pass.counts_tested();
  const uint32_t passed = split ? pass.begin_count() : 0;
  const uint32_t rasterized = pass.begin_rasterized();
  DrawTargets first = targets;
  first.store_depth = first.store_depth || two_phase;  // the culling and the second half read it
  begin(cmd, first);
  const Drawn drawn = draw_clusters(cmd, variant, layout, sets, view, order, halves[0]);
  if (two_phase) {
    end(cmd);
    occlusion_->cull(pass, *culled, targets.depth_resource, targets.depth_layer, targets.extent,
                     *view.cull, order, pass.label() + ".occlusion");
    begin(cmd, loaded(targets));
    draw_clusters(cmd, variant, layout, sets, view, order, halves[1]);
  }
  end(cmd);
  pass.end_rasterized(rasterized);
  if (split) pass.end_count(passed, passing);
  // What was drawn: counted by the culling shader where predicates chose it.
  if (two_phase) {
    pass.drawn(culled->stats.handle(), 0);
  } else if (now) {
    pass.drawn(now->stats.handle(), 2 * sizeof(uint32_t));
  } else {
    pass.triangles(static_cast<double>(drawn.triangles));
    pass.clusters(static_cast<double>(order.size()));
  }
  if (quads && culling) {
    DrawTargets from = loaded(targets);
    from.clear_depth = targets.clear_depth;  // the pass's own start
    count_quads(from);
  }
  if (!pass.counting()) return;
  // Everything rasterized, drawn again untested into the kept targets.
  begin(cmd, loaded(targets));
  const uint32_t all = pass.begin_count();
  draw_halves(counter.rasterized(), layout, sets);
  pass.end_count(all, rejected, split ? static_cast<int>(passed) : -1);
  end(cmd);
}

void SceneDrawer::begin_light_scope(VkCommandBuffer cmd, VkImageView hdr, VkImageView depth,
                                    VkExtent2D extent) const {
  const VkImageLayout ds = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL;
  VkRenderingAttachmentInfo color =
      attachment(hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, false);
  VkRenderingAttachmentInfo depth_att = attachment(depth, ds, false);
  depth_att.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
  VkRenderingAttachmentInfo stencil_att = attachment(depth, ds, true);
  stencil_att.clearValue.depthStencil = {1.0f, 0};
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, extent};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &color;
  info.pDepthAttachment = &depth_att;
  info.pStencilAttachment = &stencil_att;
  vkCmdBeginRendering(cmd, &info);
  set_viewport(cmd, extent);
}

}  // namespace illum::realtime
