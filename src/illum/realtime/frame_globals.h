// The frame's globals every technique shares: set 0 (frame uniforms, materials, lights, the
// camera block of views: shaders/common.glsl), set 1 (per-material textures), the layouts of the
// shading slots a technique fills with its own set (2: the frame pipeline's, 3: the shadow
// method's, shaders/shadow_set.glsl; 4: the lighting inputs, lighting_inputs.h) with a neutral set
// for each when no technique fills it, the samplers and the 1×1 dummy textures that keep
// descriptors valid when a feature is off.
#pragma once

#include <utility>
#include <vector>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/render_settings.h"
#include "illum/realtime/technique_context.h"

namespace illum::realtime {

// Descriptor set slots of the shading pipeline layout (must match the shaders).
inline constexpr uint32_t kFrameSet = 0;
inline constexpr uint32_t kMaterialSet = 1;
inline constexpr uint32_t kPipelineSet = 2;
inline constexpr uint32_t kShadowSet = 3;
// kInputsSet = 4: the lighting inputs (lighting_inputs_bindings.h).
inline constexpr uint32_t kShadingSets = 5;
// Views the camera block holds (view 0 included): the shadow maps take up to 6 × 8 cube faces,
// 16 spot maps and 4 cascades.
inline constexpr uint32_t kMaxViews = 256;

class FrameGlobals;

// The view a frame is drawn with from `camera` (view 0 of the camera block; a technique may
// add another camera's the same way): the far plane just beyond the scene's `bounds`, the near
// one 1e-3 of it, the aspect of `width` × `height`.
FrameView camera_view(const Camera& camera, const Bounds3& bounds, uint32_t width, uint32_t height);

// A view from a light's matrices (shadow maps, reflective shadow maps): `eye` is the light's
// position (or the box's centre for an orthographic view).
FrameView light_view(const mat4& view, const mat4& proj, const vec3& eye, float near_plane,
                     float far_plane);
// The view matrix of cube face `face` (+x, −x, +y, −y, +z, −z) seen from `eye`: the OpenGL
// cube-map axes and up vectors, as the shaders' cube lookups expect.
mat4 cube_face_view(const vec3& eye, int face);
vec3 cube_face_axis(int face);

// Views of the camera block a technique holds (FrameGlobals::add_views), given back when
// destroyed.
class ViewSlots {
 public:
  ViewSlots() = default;
  ViewSlots(ViewSlots&& o) noexcept { *this = std::move(o); }
  ViewSlots& operator=(ViewSlots&& o) noexcept;
  ViewSlots(const ViewSlots&) = delete;
  ViewSlots& operator=(const ViewSlots&) = delete;
  ~ViewSlots() { release(); }

  uint32_t size() const { return count_; }
  // The block index of this holder's view k (push.view, SceneView::view).
  uint32_t operator[](uint32_t k) const;

 private:
  friend class FrameGlobals;
  void release();
  FrameGlobals* owner_ = nullptr;
  uint32_t first_ = 0, count_ = 0;
};

class FrameGlobals {
 public:
  FrameGlobals(gpu::Context& context, const GpuScene& scene, size_t light_count);
  FrameGlobals(const FrameGlobals&) = delete;
  FrameGlobals& operator=(const FrameGlobals&) = delete;

  const gpu::Sampler& linear() const { return linear_; }  // repeat, mipmapped (materials)
  const gpu::Sampler& nearest() const { return nearest_; }
  const gpu::Sampler& clamp_linear() const { return clamp_linear_; }
  const gpu::GpuImage& dummy_cube() const { return dummy_cube_; }    // RG32F cube array (1, 1)
  const gpu::GpuImage& dummy_array() const { return dummy_array_; }  // RG32F 2-D array (1, 1)
  const gpu::GpuImage& dummy_2d() const { return dummy_2d_; }        // RG32F (0, 0)
  const gpu::GpuImage& dummy_3d() const { return dummy_3d_; }        // RG32F 1×1×2, zeros
  const gpu::Buffer& dummy_buffer() const { return dummy_buffer_; }  // 256 zero bytes

  // The layout of shading slot `slot` (kPipelineSet: an empty one, for pipelines without
  // their own set).
  const gpu::DescriptorSetLayout& layout(uint32_t slot) const;
  // The set bound at `slot` when no active technique fills it (kShadowSet: no shadow
  // lookups; kInputsSet: no lighting input active; kPipelineSet: empty).
  VkDescriptorSet neutral_set(uint32_t slot) const;
  VkDescriptorSet frame_set() const { return frame_set_; }
  // Materials out of range (none in the scene) use the last (or a default) one.
  int material_index(int material) const;
  VkDescriptorSet material_set(int material) const;

  // A pipeline layout of the five shading slots (slot 2: `pipeline_set`, or the empty
  // layout) and the scene's push constants.
  gpu::PipelineLayout shading_layout(VkDescriptorSetLayout pipeline_set = VK_NULL_HANDLE) const;
  // The one with an empty slot 2 (shadow maps, forward shading, stencil volumes).
  VkPipelineLayout default_layout() const { return default_layout_.handle(); }

  // Counting frames (GpuTimer::begin_quads): the {quads, samples} counter that
  // shaders/quad_count.frag adds to, bound as slot 2 of `quad_count_layout`.
  VkBuffer quad_counter() const { return quad_counter_.handle(); }
  VkDescriptorSet quad_count_set() const { return quad_count_set_; }
  VkPipelineLayout quad_count_layout() const { return quad_count_layout_.handle(); }

  void upload_lights(const std::vector<Light>& lights);
  // The frame uniforms: the camera (also view 0 of the camera block), and the lighting globals
  // from `settings`.
  void update(const FrameView& view, const RenderSettings& settings, size_t light_count,
              uint32_t width, uint32_t height);

  // The camera block (set 0, binding 3: common.glsl `views`): every view a scene-draw variant
  // can draw from, by index (SceneView::view → push.view). View 0 is the frame's camera.
  // `count` further contiguous views, held until the returned slots are destroyed; throws
  // Error when the block has no room.
  ViewSlots add_views(uint32_t count);
  // Writes view `index` (an added one; the block is host-visible and read by the frame being
  // recorded, so write before recording it): `view`'s matrices, camera position and planes as
  // given, and the target's `extent`.
  void set_view(uint32_t index, const FrameView& view, VkExtent2D extent);

 private:
  gpu::Context& context_;
  gpu::Sampler linear_, nearest_, clamp_linear_;
  gpu::GpuImage dummy_cube_, dummy_array_, dummy_2d_, dummy_3d_, dummy_white_;
  gpu::Buffer dummy_buffer_, frame_ubo_, lights_, neutral_shadow_ubo_, neutral_inputs_;
  friend class ViewSlots;
  void write_view(uint32_t index, const FrameView& view, VkExtent2D extent);
  gpu::Buffer views_;
  std::vector<bool> view_used_;  // per view of the block
  gpu::DescriptorAllocator descriptors_;
  std::vector<gpu::DescriptorSetLayout> layouts_;  // per slot
  VkDescriptorSet frame_set_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> material_sets_;
  std::vector<VkDescriptorSet> neutral_sets_;  // per slot (0, 1: none)
  gpu::PipelineLayout default_layout_;
  gpu::Buffer quad_counter_;
  gpu::DescriptorSetLayout quad_count_set_layout_;
  VkDescriptorSet quad_count_set_ = VK_NULL_HANDLE;
  gpu::PipelineLayout quad_count_layout_;
};

// Binds the five shading sets (slot 1: material 0; the scene draw rebinds it per draw).
void bind_shading_sets(VkCommandBuffer cmd, VkPipelineBindPoint point, VkPipelineLayout layout,
                       const FrameGlobals& globals, const std::array<VkDescriptorSet, 3>& sets);

}  // namespace illum::realtime
