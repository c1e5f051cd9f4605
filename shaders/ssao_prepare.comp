#version 450
// SSAO plane pyramid (ssao_set.glsl), every level in one dispatch: a group computes the
// level-0 planes of a 32×32 block of pixels — per pixel its surface as a plane, with its
// geometric normal (the G-buffer's, or from the depth buffer in pipelines without one, so no
// separate normal pass runs) and shading normal — into shared memory, and writes the block's
// texels of every coarser level from there. A coarse texel is a copy of one level-0 pixel of
// its own 2^m × 2^m block (ssao_child applied m times), so the block holds every source and
// the levels need neither further dispatches nor barriers between them.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 7, rgba32ui) uniform writeonly uimage2D planes_out[kSsaoMaxLevels];

const int kBlock = 1 << (kSsaoMaxLevels - 1);  // the coarsest level's texel, in pixels
shared uvec4 block_planes[kBlock][kBlock];

// Constant indices: the device need not index storage-image arrays dynamically.
void store(int level, ivec2 texel, uvec4 v) {
  switch (level) {
    case 0: imageStore(planes_out[0], texel, v); break;
    case 1: imageStore(planes_out[1], texel, v); break;
    case 2: imageStore(planes_out[2], texel, v); break;
    case 3: imageStore(planes_out[3], texel, v); break;
    case 4: imageStore(planes_out[4], texel, v); break;
    default: imageStore(planes_out[5], texel, v); break;
  }
}

uvec4 plane(ivec2 pixel) {
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  if (depth >= 1.0) return uvec4(floatBitsToUint(-1.0), 0u, 0u, 0u);
  vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 n = ssao_geometric_normal(pixel, p, depth);
  vec3 shading = ssao.info.w != 0 ? oct_decode(texelFetch(ssao_normals, pixel, 0).xy) : n;
  vec3 ps = p - frame.camera_pos.xyz;
  uint packed = ssao_pack_plane_normal(n);
  return uvec4(floatBitsToUint(length(ps)),
               floatBitsToUint(dot(ps, ssao_unpack_plane_normal(packed))), packed,
               ssao_pack_normal(shading));
}

void main() {
  ivec2 size = ivec2(frame.extent.xy);
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * kBlock;
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  const int threads = int(gl_WorkGroupSize.x);
  [[unroll]] for (int j = 0; j < kBlock / threads; ++j)
    [[unroll]] for (int i = 0; i < kBlock / threads; ++i) {
      ivec2 at = local + threads * ivec2(i, j);  // neighbouring threads, neighbouring pixels
      ivec2 pixel = origin + at;
      if (any(greaterThanEqual(pixel, size))) continue;
      uvec4 v = plane(pixel);
      block_planes[at.y][at.x] = v;
      store(0, pixel, v);
    }
  memoryBarrierShared();
  barrier();
  // Level m has (kBlock >> m)² texels in the block, at most one per invocation.
  [[unroll]] for (int m = 1; m < kSsaoMaxLevels; ++m) {
    if (m >= ssao.grid.y) break;
    int side = kBlock >> m;
    ivec2 texel = (origin >> m) + local;
    if (any(greaterThanEqual(local, ivec2(side))) ||
        any(greaterThanEqual(texel, max(size >> m, ivec2(1)))))
      continue;
    ivec2 c = texel;
    for (int k = m - 1; k >= 0; --k) c = ssao_child(c, max(size >> k, ivec2(1)));
    store(m, texel, block_planes[c.y - origin.y][c.x - origin.x]);
  }
}
