// The SSAO add-on's set (slot 2 of its compute and apply layouts, realtime/techniques/
// ssao.cpp): parameters, the depth buffer, the normals (the G-buffer's, or the SSAO normal
// pass's, same octahedral RGBA16F layout: xy shading, zw geometric), and a source texture
// (the raw AO for the blur, the blurred AO for the apply and show passes). Storage images
// are declared by the shaders that write them.
#ifndef ILLUM_SSAO_SET_GLSL
#define ILLUM_SSAO_SET_GLSL
#include "common.glsl"

layout(std140, set = 2, binding = 0) uniform Ssao {
  vec4 shape;  // radius R, bias b, intensity k, falloff s (scene units)
  ivec4 info;  // directions N, blur radius (pixels), march steps, unused
} ssao;
layout(set = 2, binding = 1) uniform sampler2D ssao_depth;
layout(set = 2, binding = 2) uniform sampler2D ssao_normals;
layout(set = 2, binding = 3) uniform sampler2D ssao_source;

// The surface point at a pixel (its centre) from the depth buffer, as gbuffer.glsl does.
vec3 ssao_position(vec2 frag, float depth) {
  vec2 ndc = frag * frame.extent.zw * 2.0 - 1.0;
  vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
  return h.xyz / h.w;
}

vec3 ssao_geometric_normal(ivec2 pixel) {
  return oct_decode(texelFetch(ssao_normals, pixel, 0).zw);
}

#endif
