// The one "draw the scene from view V with variant P into targets T" service: shadow maps
// (cube faces, spot maps, cascades), the forward and G-buffer passes (a depth pre-pass, then
// shading), the forward pass of stencil-masked lights — and any technique's own views
// (reflective shadow maps, cube-map captures). A variant is a gpu::Pipeline built on a shading
// layout (FrameGlobals::shading_layout); the view is a camera of FrameGlobals' camera block,
// named in the push constants (push.view), which every variant's vertex stage reads.
#pragma once

#include <array>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "illum/gpu/gpu_timer.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/measure/counting_pipelines.h"
#include "illum/realtime/occlusion_culling.h"

namespace illum::realtime {

// The vertex layout of the scene's vertex buffer, or for depth-like passes of its packed
// positions (GpuScene::positions(), this stride; SceneDrawer binds that stream to pipelines
// built with it).
inline constexpr uint32_t kPositionStride = sizeof(vec3);
gpu::VertexInput mesh_vertex_input(bool position_only);

struct DrawTargets {
  struct Color {
    VkImageView view = VK_NULL_HANDLE;
    bool clear = true;
    VkClearColorValue value{};
    // Neither cleared nor loaded: for targets the pass writes at every pixel that anything
    // reads later (the G-buffer where the depth is not 1). Their clear is a fixed cost.
    bool undefined = false;
  };
  std::vector<Color> colors;
  VkImageView depth = VK_NULL_HANDLE;  // a view with every aspect of a depth(-stencil) image
  bool clear_depth = true;
  bool store_depth = true;
  bool stencil = false;  // the depth image's stencil is an attachment too
  VkExtent2D extent{};
  // The depth's frame-graph resource: occlusion culling samples it between the pass's halves
  // (the pass declares it kSampled in kComputeShader besides its attachment use).
  std::string depth_resource;
  uint32_t depth_layer = 0;  // the layer `depth` views, when the resource has several
};

// What the push constants say about the view: `view` is the camera block's view every variant
// draws from (push.view: view 0 the frame's camera, others added by a technique,
// FrameGlobals::add_views); shadow passes also name their light. Colour passes (per_draw) push
// each draw's index as push.draw, for per-draw data such as the ambient cube
// (shaders/inputs/probes.glsl); depth-like ones leave it 0, so draws sharing a transform push
// nothing. `mode` goes to push.mode (forward.frag: 0 all lights, 1 emission + ambient only, 2 the
// one light light_index, unshadowed).
//
// `cull`, when set, is the view's clip transform (world to clip): clusters wholly outside its
// clip volume are not drawn — exactly what the clipper would discard, so the image does not
// change. A pipeline with depth clamp keeps what lies beyond the near and far planes
// (`cull_depth` false). `front_to_back` draws the clusters nearest the view first, so the
// depth test rejects what they hide before it is shaded or written (depth, visibility and
// shadow passes); passes that test against a finished depth keep the material order.
// A draw's first instance (gl_InstanceIndex) is its first triangle within the mesh, so
// gl_InstanceIndex + gl_PrimitiveID numbers the mesh's triangles whatever the clusters drawn.
struct SceneView {
  int view = 0;
  int light_index = 0;
  int mode = 0;
  bool per_draw = true;
  std::optional<mat4> cull;
  bool cull_depth = true;
  // When set, the clip transform of the region the view's map is read in (a cascade's slice
  // of the camera's frustum, widened by the lookup's reach): clusters wholly outside its x or
  // y planes, or wholly beyond z = 1, are not drawn (they write no texel a lookup reads); its
  // near side culls nothing. Unlike `cull`, it changes the map outside that region.
  std::optional<mat4> receivers;
  // When set, each draw pushes clip_from_world × its model matrix as push.model: the vertex
  // shader of a depth-only view (shadow_depth.vert) then runs one transform, not two.
  std::optional<mat4> clip_from_world;
  bool front_to_back = false;
  // The clip-space depth a front-to-back view sorts its clusters by (cluster_depth below).
  enum class DepthKey { kFarthest, kCentre };
  DepthKey depth_key = DepthKey::kFarthest;
  // Occlusion culling (OcclusionCuller, when switched on): kTwoPhase for a pass that writes
  // the depth from cleared (pre-pass, visibility raster, shadow views), kVisibleNow for one
  // that tests against the depth such a pass of `occlusion_key` finished this frame (it then
  // draws only the clusters that pass found visible).
  enum class Occlusion { kNone, kTwoPhase, kVisibleNow };
  Occlusion occlusion = Occlusion::kNone;
  std::string occlusion_key;

  // A colour or depth pass from the frame's camera, view 0 (`view_proj`: its); occlusion culled
  // against the camera's depth ("camera") as `occlusion` says.
  static SceneView camera(const mat4& view_proj, bool front_to_back,
                          Occlusion occlusion = Occlusion::kNone) {
    SceneView v;
    v.view = 0;
    v.cull = view_proj;
    v.front_to_back = front_to_back;
    v.occlusion = occlusion;
    v.occlusion_key = "camera";
    return v;
  }
  // A colour or depth pass from the camera block's view `view` (`view_proj`: that view's, for
  // culling), not occlusion culled.
  static SceneView from(int view, const mat4& view_proj, bool front_to_back) {
    SceneView v;
    v.view = view;
    v.cull = view_proj;
    v.front_to_back = front_to_back;
    return v;
  }
};

// The clip-space depth (z before the divide) of `b`'s farthest corner, or of the middle of its
// depth range: the keys depth-like passes sort clusters by. A cluster whose farthest corner is
// nearer than another's lies wholly in front of it when their depth ranges do not overlap, and
// a large cluster that spans depth (a floor, a wall) goes after the compact ones in front of
// it, so they occlude it — on the H200 (Sibenik 1080p) the pre-pass passes 1.15 layers instead
// of 1.49 with the centre as the key, and the frame takes 2.000 ms instead of 2.147
// (bench/results/raster.md#design-choices); the nearest corner was worse (2.79 ms), and the spot
// maps too prefer the farthest corner (0.351 ms against 0.369 with the centre). The cascades'
// orthographic views from a high sun are the exception: the centre gives 0.364 ms against
// 0.371 (the nearest corner 0.414, no order 0.438; bench/results/raster.md#design-choices; the run
// is in git at c416128).
float cluster_depth(const mat4& clip, const Bounds3& b, SceneView::DepthKey key);

// The clusters `view` draws, in the order it draws them (every cluster, in draw order, when
// the view neither culls nor sorts).
std::vector<uint32_t> visible_clusters(const GpuScene& scene, const SceneView& view);

class SceneDrawer {
 public:
  SceneDrawer(const GpuScene& scene, const FrameGlobals& globals,
              OcclusionCuller* occlusion = nullptr)
      : scene_(scene), globals_(globals), occlusion_(occlusion) {}

  // A rendering scope over `targets` with the viewport and scissor set to their extent.
  void begin(VkCommandBuffer cmd, const DrawTargets& targets) const;
  void end(VkCommandBuffer cmd) const { vkCmdEndRendering(cmd); }
  // Inside a scope: binds `pipeline` and the shading sets (slots 2..4 from `sets`), then
  // draws every draw item with its material (set 1) and push constants. Returns the
  // triangles drawn.
  size_t draw(VkCommandBuffer cmd, const gpu::Pipeline& pipeline, VkPipelineLayout layout,
              const std::array<VkDescriptorSet, 3>& sets, const SceneView& view) const;
  // begin(), draw() with each variant in turn (a depth pre-pass, then shading), end().
  void render(VkCommandBuffer cmd, const DrawTargets& targets,
              std::initializer_list<const gpu::Pipeline*> variants, VkPipelineLayout layout,
              const std::array<VkDescriptorSet, 3>& sets, const SceneView& view) const;

  // render() with one variant, noting the pass's work in its timer scope: the triangles,
  // and in counting frames (Renderer::measure_work) its fragments — those that pass the
  // tests (an occlusion query around the draws) as fills of `passing`, and those rejected
  // (all it rasterizes, counted by drawing again with `counter.rasterized()`, minus the
  // passing) as fills of `rejected` — and, where the device can, the quads of the passing
  // ones (drawn first with `counter.quads()` into the same targets).
  void render_counted(PassContext& pass, const DrawTargets& targets, const gpu::Pipeline& variant,
                      const CountingPipelines& counter, VkPipelineLayout layout,
                      const std::array<VkDescriptorSet, 3>& sets, const SceneView& view,
                      const gpu::RasterFill& passing, const gpu::RasterFill& rejected) const;

  // The scope of the per-light passes after the depth (and G-buffer) pass — light volumes,
  // stencil shadow volumes: the HDR target loaded, the depth read-only (tested, and
  // sampled by G-buffer lighting), the stencil cleared for this light.
  void begin_light_scope(VkCommandBuffer cmd, VkImageView hdr, VkImageView depth,
                         VkExtent2D extent) const;

 private:
  struct Drawn {
    size_t triangles = 0, clusters = 0;
  };
  // Binds and draws `order`'s clusters; with `predicates` (one uint32 per cluster) each
  // cluster is a draw of its own, predicated on its flag.
  Drawn draw_clusters(VkCommandBuffer cmd, const gpu::Pipeline& pipeline, VkPipelineLayout layout,
                      const std::array<VkDescriptorSet, 3>& sets, const SceneView& view,
                      const std::vector<uint32_t>& order, VkBuffer predicates) const;

  const GpuScene& scene_;
  const FrameGlobals& globals_;
  OcclusionCuller* occlusion_;
};

}  // namespace illum::realtime
