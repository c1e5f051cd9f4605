#include "illum/realtime/scene_draw.h"

#include "illum/realtime/gpu_types.h"

namespace illum::realtime {

gpu::VertexInput mesh_vertex_input(bool position_only) {
  gpu::VertexInput in;
  in.stride = sizeof(Vertex);
  in.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)});
  if (position_only) return in;
  in.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)});
  in.attributes.push_back({2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)});
  in.attributes.push_back({3, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv0)});
  in.attributes.push_back({4, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv1)});
  return in;
}

gpu::GraphicsPipelineDesc counting_variant(gpu::GraphicsPipelineDesc d) {
  d.fragment_shader = "";
  d.color_write = false;
  d.additive_blend = false;
  d.depth_test = false;
  d.depth_write = false;
  d.stencil_test = false;
  return d;
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

}  // namespace

void SceneDrawer::begin(VkCommandBuffer cmd, const DrawTargets& t) const {
  std::vector<VkRenderingAttachmentInfo> colors;
  for (const DrawTargets::Color& c : t.colors) {
    colors.push_back(attachment(c.view, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, c.clear));
    colors.back().clearValue.color = c.value;
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

size_t SceneDrawer::draw(VkCommandBuffer cmd, const gpu::Pipeline& pipeline,
                         VkPipelineLayout layout, const std::array<VkDescriptorSet, 3>& sets,
                         const SceneView& view) const {
  size_t triangles = 0;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  bind_shading_sets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, globals_, sets);
  VkDeviceSize offset = 0;
  VkBuffer vb = scene_.vertices().handle();
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(cmd, scene_.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  PushConstants push{};
  push.view_index = view.view_index;
  push.light_index = view.light_index;
  push.pad = view.mode;
  VkDescriptorSet bound = globals_.material_set(0);
  for (size_t di = 0; di < scene_.draws().size(); ++di) {
    const DrawItem& d = scene_.draws()[di];
    if (view.per_draw) push.view_index = static_cast<int>(di);
    push.model = d.transform;
    push.material = globals_.material_index(d.material);
    const VkDescriptorSet material = globals_.material_set(push.material);
    if (material != bound || di == 0) {
      bound = material;
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, kMaterialSet, 1,
                              &material, 0, nullptr);
    }
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    const MeshRange& r = scene_.meshes()[d.mesh];
    vkCmdDrawIndexed(cmd, r.index_count, 1, r.first_index, r.vertex_offset, 0);
    triangles += r.index_count / 3;
  }
  return triangles;
}

void SceneDrawer::render(VkCommandBuffer cmd, const DrawTargets& targets,
                         std::initializer_list<const gpu::Pipeline*> variants,
                         VkPipelineLayout layout, const std::array<VkDescriptorSet, 3>& sets,
                         const SceneView& view) const {
  begin(cmd, targets);
  for (const gpu::Pipeline* p : variants) draw(cmd, *p, layout, sets, view);
  end(cmd);
}

void SceneDrawer::render_counted(PassContext& pass, const DrawTargets& targets,
                                 const gpu::Pipeline& variant, const gpu::Pipeline& counter,
                                 VkPipelineLayout layout,
                                 const std::array<VkDescriptorSet, 3>& sets, const SceneView& view,
                                 const gpu::RasterFill& passing,
                                 const gpu::RasterFill& rejected) const {
  const VkCommandBuffer cmd = pass.cmd();
  begin(cmd, targets);
  // Lavapipe crashes on occlusion queries around depth-tested draws in frames that also
  // build shadow volumes on the GPU: there every fragment counts as rejected (a lower bound).
  const bool split = pass.counts_tested();
  const uint32_t passed = split ? pass.begin_count() : 0;
  pass.triangles(static_cast<double>(draw(cmd, variant, layout, sets, view)));
  if (split) pass.end_count(passed, passing);
  end(cmd);
  if (!pass.counting()) return;
  // Everything rasterized, drawn again untested into the kept targets.
  DrawTargets again = targets;
  for (DrawTargets::Color& c : again.colors) c.clear = false;
  again.clear_depth = false;
  begin(cmd, again);
  const uint32_t all = pass.begin_count();
  draw(cmd, counter, layout, sets, view);
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
