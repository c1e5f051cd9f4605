// Stencil shadow volumes (S002 §4.3, ALGORITHMS.md 23) for the renderer, forward and
// deferred alike: the volumes of every light, and the z-fail stencil pass that counts them.
// The volumes come from a compute shader (shaders/silhouettes.comp: one invocation per
// triangle, output reserved with an atomic add on the light's VkDrawIndirectCommand, drawn
// with vkCmdDrawIndirect, nothing read back) or from ShadowVolumeBuilder on the CPU, the
// simple reference (one host-visible vertex buffer). Both use the same position-welded
// adjacency, computed once on the CPU, and the same caster and silhouette rules.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/shadow_volume_builder.h"

namespace illum::realtime {

// Where stencil shadow volumes are built: a compute pass drawn indirectly (GPU), or
// ShadowVolumeBuilder on the CPU (the simple reference, uploaded each rebuild).
enum class SilhouetteSource { kCpu, kGpu };

// One face's stencil state as every stencil pass here uses it: keep the value on a
// stencil-test failure, compare all 8 bits against reference 0.
VkStencilOpState stencil_op(VkStencilOp pass, VkStencilOp depth_fail, VkCompareOp compare,
                            uint32_t write_mask = 0xff);
// Two-sided z-fail counting (Carmack's reverse): faces behind the visible surface count,
// back faces +1, front faces −1, wrapping; both faces drawn. Shadow volumes and the light
// volumes' stencil trick (S001 §4.1) share it.
void use_z_fail_count(gpu::GraphicsPipelineDesc* desc);
// Draw only where the count is 0 (lit), leaving it unchanged.
void use_stencil_zero_test(gpu::GraphicsPipelineDesc* desc);

// The pixels that can see a spot light's cone within `scene_bounds` (and its range): the
// screen box of the apex and the cone's cross-section at the farthest reach. Elsewhere the
// light adds nothing, so its volumes and lighting need no pixels there. Full screen for
// other lights, wide spots, or when the cone reaches behind the camera.
VkRect2D light_scissor(const Light& light, const Bounds3& scene_bounds, const mat4& view_proj,
                       uint32_t width, uint32_t height);

// Bytes of one light's vertex buffer for GPU silhouettes: the worst case, 24 vertices (two
// caps, three side quads) a triangle, since no readback tells the real size. Throws Error
// naming silhouettes=cpu when that exceeds one storage buffer (or one dispatch) of `limits`.
VkDeviceSize gpu_volume_bytes(size_t triangles, const VkPhysicalDeviceLimits& limits,
                              const std::string& device);

class StencilShadows {
 public:
  // `pipeline_layout` starts with the frame set (shaders/common.glsl, set 0); the stencil
  // pass runs inside rendering scopes with `color_format` and a `depth_format` that has
  // stencil. Throws Error when the GPU volumes of one light cannot fit a storage buffer.
  StencilShadows(gpu::Context& context, const GpuScene& scene, size_t light_count,
                 SilhouetteSource source, VkPipelineLayout pipeline_layout, VkFormat color_format,
                 VkFormat depth_format);
  ~StencilShadows();
  StencilShadows(const StencilShadows&) = delete;
  StencilShadows& operator=(const StencilShadows&) = delete;

  SilhouetteSource source() const { return source_; }

  // CPU source: rebuilds every light's volumes now (waits for the GPU first when the
  // vertex buffer must grow). Returns the CPU milliseconds spent.
  double build_on_cpu(const std::vector<Light>& lights, bool back_faces);
  // GPU source, outside a rendering scope: zeroes every light's draw count (a transfer
  // write of the indirect arguments), then — after a barrier from transfer to compute that
  // the caller records — extracts every light's volumes (compute: storage writes of the
  // vertices, atomic adds on the counts). The draws that read them need a barrier too.
  void record_clear(VkCommandBuffer cmd, size_t light_count);
  void record_extraction(VkCommandBuffer cmd, const std::vector<Light>& lights, bool back_faces);
  // Inside a rendering scope with a stencil attachment: the z-fail count of light `light`'s
  // volumes against the bound depth (its own pipeline; binds `frame_set` as set 0). For
  // counting frames, kRasterized: the same draws untested, writing nothing (an occlusion
  // query around them counts every sample the z-fail pass rasterizes).
  enum class StencilDraw { kCount, kRasterized };
  void record_stencil(VkCommandBuffer cmd, VkDescriptorSet frame_set, size_t light,
                      StencilDraw what = StencilDraw::kCount) const;

 private:
  void create_gpu_resources(size_t light_count);

  gpu::Context& context_;
  SilhouetteSource source_;
  ShadowVolumeBuilder builder_;
  float cap_offset_;
  VkPipelineLayout pipeline_layout_;
  gpu::Pipeline stencil_pipeline_, count_pipeline_;
  // CPU source.
  gpu::Buffer cpu_vertices_;
  std::vector<std::pair<uint32_t, uint32_t>> cpu_ranges_;  // first vertex, count per light
  // GPU source: adjacency, one output buffer and descriptor set per light, and the lights'
  // draw commands.
  gpu::Buffer triangles_, draw_args_;
  std::vector<gpu::Buffer> outputs_;
  std::unique_ptr<gpu::DescriptorAllocator> descriptors_;
  gpu::DescriptorSetLayout extraction_set_layout_;
  std::vector<VkDescriptorSet> extraction_sets_;
  gpu::PipelineLayout extraction_layout_;
  gpu::Pipeline extraction_pipeline_;
};

}  // namespace illum::realtime
