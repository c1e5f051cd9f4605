// The shading bound of a fragment pass whose work is per-fragment lighting (the forward
// pipeline's shading pass; illum-bench raster, docs/realtime.md "What bounds each pass"):
// the same lighting with no scene geometry. The view's surfaces are rendered once into a
// G-buffer of their own (depth pre-pass, then gbuffer.frag with depth EQUAL, as the deferred
// pipeline does), then a full-screen triangle runs shaders/shading_bound.frag — the lighting
// loop forward.frag runs (lighting.glsl's direct_light: the same lights, shadow maps and
// BRDFs) on the surface read back from that G-buffer — into an HDR target like the forward
// pass's (cleared RGBA16F, depth tested read-only: early depth testing drops the background,
// so each covered pixel is shaded exactly once). It is timed `repeats` times after two
// untimed runs, the first with an occlusion query counting the covered pixels.
//
// What it does beyond the pass: reads 32 bytes a pixel of G-buffer (input_bytes; illum-bench
// raster prints their time at the copy bandwidth). What it skips: vertex work, attribute
// interpolation, material texture fetches and the ambient term (the G-buffer pass did them),
// and the extra lanes of partly covered quads (illum-bench raster scales by the pass's quads).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "illum/core/image.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"

namespace illum::realtime {

class TechniqueContext;

struct ShadingTime {
  std::string pass;             // the pass it bounds ("forward")
  std::vector<double> runs_ms;  // the full-screen lighting pass, each run
  double pixels = 0.0;          // covered pixels it shaded (occlusion query)
  double input_bytes = 0.0;     // G-buffer bytes it read (depth included)
  uint32_t width = 0, height = 0;
};

class ShadingBound {
 public:
  explicit ShadingBound(TechniqueContext& ctx);
  ~ShadingBound();
  // After a frame of the current view (its shadow maps and frame uniforms in place): the
  // timed full-screen lighting. With `image`, also its HDR output (tests: it equals the
  // forward image).
  ShadingTime measure(int repeats, Image* image = nullptr);

 private:
  void realize();  // the targets and the set, at the frame's size

  TechniqueContext& ctx_;
  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline prepass_, gbuffer_, lighting_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  uint32_t width_ = 0, height_ = 0;
  std::vector<gpu::GpuImage> gbuffer_targets_;  // albedo, normal, specular, emission + ambient
  gpu::GpuImage depth_, output_;
};

}  // namespace illum::realtime
