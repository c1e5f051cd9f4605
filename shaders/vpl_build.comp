#version 450
// The virtual point lights from the reflective shadow maps (techniques/vpl.cpp): one per block
// of b×b texels of each layer, b = resolution / side. The block's texels are one light each
// (rsm_views.h: Φ_k the flux texel k reflects); the VPL is texel j drawn with probability
// p_j = L_j / ΣL (L = r + g + b of the flux, so empty texels are never drawn) with flux
// Φ_j / p_j — a one-sample estimator of the block's sum Σ_k Φ_k f(x_k) whose expectation is
// that sum for any f, and whose flux is exactly ΣΦ where the block is one colour. The draw
// is a hash of (layer, block, seed): the same VPLs every frame while the maps stay the same.
layout(local_size_x = 8, local_size_y = 8) in;
#include "vpl_common.glsl"

layout(std140, set = 0, binding = 0) uniform VplBuild {
  ivec4 info;  // x: VPLs per side of a layer, y: texels per side, z: layers, w: seed
} build;
layout(set = 0, binding = 1) uniform sampler2DArray source_position;
layout(set = 0, binding = 2) uniform sampler2DArray source_normal;
layout(set = 0, binding = 3) uniform sampler2DArray source_flux;
layout(std430, set = 0, binding = 4) writeonly buffer Vpls { Vpl vpls[]; };

// An integer hash (lowbias32) of a block's index and the seed.
uint vpl_hash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

void main() {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  int side = build.info.x;
  if (id.x >= side || id.y >= side || id.z >= build.info.z) return;
  int b = build.info.y / side;
  ivec2 origin = id.xy * b;
  float total = 0.0;
  for (int k = 0; k < b * b; ++k) {
    vec3 f = texelFetch(source_flux, ivec3(origin + ivec2(k % b, k / b), id.z), 0).rgb;
    total += f.r + f.g + f.b;
  }
  uint index = uint((id.z * side + id.y) * side + id.x);
  Vpl v;
  v.position = vec4(0.0);
  v.normal = vec4(0.0);
  v.flux = vec4(0.0);
  if (total > 0.0) {
    float u = float(vpl_hash(index ^ vpl_hash(uint(build.info.w))) >> 8) * (1.0 / 16777216.0);
    float target = u * total, below = 0.0, chosen = 0.0;
    ivec3 texel = ivec3(origin, id.z);
    // The first texel whose running sum passes the target; rounding can leave the target
    // unreached, and then the last texel with flux is the one drawn.
    for (int k = 0; k < b * b; ++k) {
      ivec3 t = ivec3(origin + ivec2(k % b, k / b), id.z);
      vec3 f = texelFetch(source_flux, t, 0).rgb;
      float l = f.r + f.g + f.b;
      if (l <= 0.0) continue;
      texel = t;
      chosen = l;
      below += l;
      if (below > target) break;
    }
    v.position = vec4(texelFetch(source_position, texel, 0).xyz, 1.0);
    v.normal = vec4(normalize(texelFetch(source_normal, texel, 0).xyz), 0.0);
    v.flux = vec4(texelFetch(source_flux, texel, 0).rgb * (total / chosen), 0.0);
  }
  vpls[index] = v;
}
