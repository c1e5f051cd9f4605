// What a technique may use while it is built, declares its passes and records them: the
// device, the uploaded scene and lights, the settings (its parameter values), the frame
// globals (sets 0 and 1, samplers, dummies), the frame's resources once realized, the scene
// draw service and this frame's view. The renderer owns all of them.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "illum/gpu/context.h"
#include "illum/realtime/baked_data.h"
#include "illum/realtime/render_settings.h"
#include "illum/realtime/technique.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

class GpuScene;
class FrameGlobals;
class FrameResources;
class SceneDrawer;

// This frame's camera.
struct FrameView {
  Camera camera;
  mat4 view{1.0f}, proj{1.0f}, view_proj{1.0f}, inv_view_proj{1.0f};
  float near_plane = 0.0f, far_plane = 1.0f, aspect = 1.0f;
  uint64_t index = 0;  // frames rendered before this one
};

class TechniqueContext {
 public:
  gpu::Context& gpu;
  const GpuScene& scene;
  FrameGlobals& globals;
  FrameResources& resources;
  const SceneDrawer& drawer;
  VkFormat depth_format;

  TechniqueContext(gpu::Context& g, const GpuScene& s, FrameGlobals& fg, FrameResources& r,
                   const SceneDrawer& d, VkFormat depth)
      : gpu(g), scene(s), globals(fg), resources(r), drawer(d), depth_format(depth) {}

  const std::vector<Light>& lights() const { return *lights_; }
  const RenderSettings& settings() const { return *settings_; }
  const FrameView& view() const { return *view_; }
  const BakedData& baked() const { return *baked_; }
  uint32_t width() const { return static_cast<uint32_t>(settings_->width); }
  uint32_t height() const { return static_cast<uint32_t>(settings_->height); }

  // The active pipeline and shadow method (each technique is built after the shadow method
  // and, but for it, after the pipeline).
  FramePipeline& pipeline() const { return *pipeline_(); }
  ShadowMethod& shadow_method() const { return *shadow_method_(); }
  // The sets bound at slots 2, 3, 4 of the shading layout: `pipeline_set` (or the empty
  // neutral set), the active shadow method's set (or the neutral one), the lighting inputs.
  std::array<VkDescriptorSet, 3> shading_sets(VkDescriptorSet pipeline_set = VK_NULL_HANDLE) const {
    return shading_sets_(pipeline_set);
  }
  // The resources the shading passes sample through those sets, as accesses by `shaders`
  // (`inputs`: which lighting inputs' resources; the deferred G-buffer pass, before the
  // screen-space phase, reads the surface inputs only).
  std::vector<Access> shading_reads(VkPipelineStageFlags2 shaders,
                                    InputReads inputs = InputReads::kAll) const {
    return shading_reads_(shaders, inputs);
  }
  // The lighting-inputs set (which inputs are active), from declare() on.
  const LightingInputs& lighting_inputs() const { return *lighting_inputs_; }
  // The assembled frame graph, from bind() on (which optional reads stand: FrameGraph::reads).
  const FrameGraph& graph() const { return *graph_(); }
  // Changes raised while building, updating or recording: the renderer notifies the graph
  // of them before the next frame's passes run (kParametersChanged concerns `technique`).
  void raise(Changes changes, const std::string& technique = "") {
    raised_.push_back({changes, technique});
  }

 private:
  friend class Renderer;
  const std::vector<Light>* lights_ = nullptr;
  const RenderSettings* settings_ = nullptr;
  const FrameView* view_ = nullptr;
  const BakedData* baked_ = nullptr;
  std::function<FramePipeline*()> pipeline_;
  std::function<ShadowMethod*()> shadow_method_;
  std::function<std::array<VkDescriptorSet, 3>(VkDescriptorSet)> shading_sets_;
  std::function<std::vector<Access>(VkPipelineStageFlags2, InputReads)> shading_reads_;
  const LightingInputs* lighting_inputs_ = nullptr;
  std::function<const FrameGraph*()> graph_;
  std::vector<std::pair<Changes, std::string>> raised_;
};

template <typename T>
T Technique::param(const std::string& key) const {
  return ctx_.settings().get<T>(decl_.name + "." + key);
}

inline void Technique::raise(Changes changes) const {
  ctx_.raise(changes, decl_.name);
}

}  // namespace illum::realtime
