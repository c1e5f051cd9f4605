#version 450
// The visibility buffer's material classification: per 8×8 tile, the slots of the materials
// its pixels show (a bit each in shared memory), then the tile appended to each of those
// slots' lists (an atomic add on the slot's dispatch count); the resolve then runs one
// indirect dispatch per slot over its tiles only. Empty pixels get the cleared value of the
// other pipelines here.
layout(local_size_x = 8, local_size_y = 8) in;
#include "visibility.glsl"

shared uint slots[64];  // 2048 slots (visibility.cpp refuses more materials)

void main() {
  uint local = gl_LocalInvocationIndex;
  slots[local] = 0u;
  barrier();
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (all(lessThan(pixel, ivec2(frame.extent.xy)))) {
    if (empty_pixel(pixel)) {
      imageStore(hdr_image, pixel, vec4(0.0));
    } else {
      uint id = texelFetch(vis_ids, pixel, 0).r;
      uint slot = uint(draws[id >> uint(push.mode)].info.w);
      atomicOr(slots[slot >> 5], 1u << (slot & 31u));
    }
  }
  barrier();
  uint bits = slots[local];
  uint tile = gl_WorkGroupID.y * tiles_x() + gl_WorkGroupID.x;
  while (bits != 0u) {
    int b = findLSB(bits);
    bits &= bits - 1u;
    uint slot = local * 32u + uint(b);
    uint at = atomicAdd(tile_args[slot].x, 1u);
    tiles[slot * tile_count() + at] = tile;
  }
}
