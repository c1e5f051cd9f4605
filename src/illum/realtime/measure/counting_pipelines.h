// Counting frames (Renderer::measure_work, for illum-bench raster): the pipelines a scene
// pass is drawn with again to count its fragments (SceneDrawer::render_counted).
#pragma once

#include "illum/gpu/pipeline.h"

namespace illum::realtime {

struct DrawTargets;  // scene_draw.h

// The counting variant of a scene-draw pipeline (SceneDrawer::render_counted): the same
// vertex stage and attachments, no test, no fragment shader, nothing written.
gpu::GraphicsPipelineDesc counting_variant(gpu::GraphicsPipelineDesc desc);

// What a counting frame draws a scene pass with besides the pass's own pipeline:
// `rasterized()` (counting_variant: all it rasterizes, untested) and `quads()` — the pass's
// vertex stage and depth and stencil state with shaders/quad_count.frag, which counts the
// 2×2 quads holding its passing samples (built on first use: only counting frames on a
// device with Context::quad_counting draw it).
class CountingPipelines {
 public:
  CountingPipelines() = default;
  CountingPipelines(gpu::Context& context, VkPipelineLayout layout,
                    const gpu::GraphicsPipelineDesc& pass);
  const gpu::Pipeline& rasterized() const { return rasterized_; }
  const gpu::Pipeline& quads(VkPipelineLayout quad_count_layout) const;
  // Drawing the pass again over its own result passes the same fragments only when the
  // depth starts cleared or the pass does not write it.
  bool replays(const DrawTargets& targets) const;

 private:
  gpu::Context* context_ = nullptr;
  gpu::GraphicsPipelineDesc pass_;
  gpu::Pipeline rasterized_;
  mutable gpu::Pipeline quads_;
};

}  // namespace illum::realtime
