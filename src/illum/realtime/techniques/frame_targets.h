// The frame's main targets, created by the frame pipeline and read by everything after it:
// "hdr" (linear radiance, RGBA16F) and "depth" (depth + stencil). Both are read back
// (Renderer::hdr(), tests) and the HDR target is sampled by the post-processing add-ons.
#pragma once

#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/scene_draw.h"

namespace illum::realtime {

inline constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kLdrFormat = VK_FORMAT_R8G8B8A8_UNORM;

// The compact G-buffer (shaders/gbuffer.glsl): written by the deferred pipeline's raster pass,
// and by the visibility pipeline's resolve where stencil shadow volumes light over it.
inline constexpr VkFormat kAlbedoFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // albedo, exponent
inline constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // 2 octahedral normals
inline constexpr VkFormat kSpecularFormat = VK_FORMAT_R8G8B8A8_UNORM;     // ks, material type
inline constexpr const char* kGbufferTargets[3] = {"gbuffer.albedo", "gbuffer.normal",
                                                   "gbuffer.specular"};
inline constexpr VkFormat kGbufferFormats[3] = {kAlbedoFormat, kNormalFormat, kSpecularFormat};

// The G-buffer pass's pipeline (the deferred pipeline's, and the shading bound's G-buffer):
// forward.vert (so its depths are the forward pass's) and gbuffer.frag into the four targets,
// both faces (scenes are two-sided).
inline gpu::GraphicsPipelineDesc gbuffer_pass_desc(VkFormat depth_format) {
  gpu::GraphicsPipelineDesc g;
  g.vertex_shader = "forward.vert";
  g.fragment_shader = "gbuffer.frag";
  g.vertex_input = mesh_vertex_input(false);
  g.cull = VK_CULL_MODE_NONE;
  g.color_formats = {kAlbedoFormat, kNormalFormat, kSpecularFormat, kHdrFormat};
  g.depth_format = depth_format;
  g.stencil_format = depth_format;
  return g;
}

inline ResourceDesc hdr_target(uint32_t extra_usage = 0) {
  ResourceDesc r;
  r.name = "hdr";
  r.frame_divisor = 1;
  r.format = kHdrFormat;
  r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | extra_usage;
  return r;
}

inline ResourceDesc depth_target(VkFormat format) {
  ResourceDesc r;
  r.name = "depth";
  r.frame_divisor = 1;
  r.format = format;
  r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  return r;
}

}  // namespace illum::realtime
