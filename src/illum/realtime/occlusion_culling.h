// Two-phase GPU occlusion culling of clusters for the depth-writing scene passes (the depth
// pre-pass, the visibility raster, every shadow view), used by SceneDrawer::render_counted.
//
// Each persistent view (the camera, each shadow view) keeps one flag per cluster: visible
// last frame. A culled pass draws in two halves inside its rendering:
//  1. the clusters its CPU list holds (frustum, front to back) predicated on "visible last
//     frame" (VK_EXT_conditional_rendering, one predicate per cluster);
//  2. between the halves, outside the rendering: a hierarchical max-depth buffer (HZB) of
//     what the first half wrote, and a test of every listed cluster's bounding box against
//     it (shaders/occlusion_cull.comp) that writes "visible now" (next frame's first half)
//     and the second half's flags (visible now, not drawn by the first);
//  3. the second half, the depth loaded, draws what the first half missed.
// The test is conservative (a cluster is dropped only when its box lies behind the farthest
// depth under its screen rectangle) and everything visible now is drawn by one half, so the
// depth and the surviving fragments are those of drawing every cluster; a view without a
// history (its first frame) draws every cluster in the first half. The flags ping-pong
// between two buffers so a counting frame's replays re-use exactly the predicates the pass
// used. Passes that test against the finished depth (the G-buffer, forward shading) can draw
// only the clusters visible now.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/gpu_scene.h"

namespace illum::realtime {

class FrameResources;

class OcclusionCuller {
 public:
  OcclusionCuller(gpu::Context& context, const GpuScene& scene, FrameResources& resources);

  // Culling runs when switched on and the device has conditional rendering; switching it on
  // where it cannot run logs why, once. `shadows`: also in the shadow views (keys
  // "shadow.*"), which draw many more clusters than the camera (each a predicated draw).
  void set_enabled(bool on, bool shadows = true);
  bool enabled(const std::string& key) const {
    return enabled_ && (shadows_ || key.rfind("shadow.", 0) != 0);
  }
  const gpu::Context& context() const { return context_; }

  // The GPU state of one persistent view.
  struct View {
    gpu::Buffer visible[2];  // "visible" flags of two frames (ping-pong)
    gpu::Buffer late;        // the second half's flags
    gpu::Buffer listed;      // the clusters the CPU listed this frame
    gpu::Buffer stats;       // {triangles, clusters} drawn, {triangles, clusters} visible now
    gpu::Buffer hzb;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkImageView bound_depth = VK_NULL_HANDLE;
    VkExtent2D extent{};
    int early = 0;               // visible[early]: the first half's flags
    uint64_t culled_at = ~0ull;  // the frame cull() last ran (visible[1 − early] is now)

    VkBuffer early_flags() const { return visible[early].handle(); }
    VkBuffer now_flags() const { return visible[1 - early].handle(); }
  };

  // Before the first half of `key`'s pass: the view's state (created on first use with every
  // flag set: the first frame draws everything), the previous cull's "visible now" becoming
  // this frame's first-half flags.
  View& begin(VkCommandBuffer cmd, const std::string& key);
  // Between the halves, outside any rendering: the HZB of `depth_resource` (`extent`; its
  // layer `depth_layer` when it has several), the test of the clusters in `order` against it
  // with the view's clip transform, and the counts of what the two halves draw. Its own timer
  // scope `scope` beside the pass's.
  void cull(PassContext& pass, View& view, const std::string& depth_resource, uint32_t depth_layer,
            VkExtent2D extent, const mat4& clip, const std::vector<uint32_t>& order,
            const std::string& scope);
  // The view culled at `frame`, if any (passes that draw only what is visible now).
  const View* culled(const std::string& key, uint64_t frame) const;

 private:
  gpu::Context& context_;
  const GpuScene& scene_;
  FrameResources& resources_;
  bool enabled_ = false;
  bool shadows_ = true;
  bool warned_ = false;
  gpu::Buffer cluster_bounds_;
  gpu::Sampler sampler_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::DescriptorAllocator descriptors_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline build_, test_;
  std::map<std::string, View> views_;
};

}  // namespace illum::realtime
