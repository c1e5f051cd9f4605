#version 450
// SSAO plane pyramid, level 0 (ssao_set.glsl): per pixel its surface as a plane — its
// geometric normal (the G-buffer's, or from the depth buffer in pipelines without one, so no
// separate normal pass runs) and shading normal.
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, rgba32ui) uniform writeonly uimage2D planes_out;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, imageSize(planes_out)))) return;
  ivec2 pixel = texel;
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  if (depth >= 1.0) {
    imageStore(planes_out, texel, uvec4(floatBitsToUint(-1.0), 0u, 0u, 0u));
    return;
  }
  vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 n = ssao_geometric_normal(pixel, p, depth);
  vec3 shading = ssao.info.w != 0 ? oct_decode(texelFetch(ssao_normals, pixel, 0).xy) : n;
  vec3 ps = p - frame.camera_pos.xyz;
  uint packed = ssao_pack_plane_normal(n);
  imageStore(planes_out, texel,
             uvec4(floatBitsToUint(length(ps)),
                   floatBitsToUint(dot(ps, ssao_unpack_plane_normal(packed))), packed,
                   ssao_pack_normal(shading)));
}
