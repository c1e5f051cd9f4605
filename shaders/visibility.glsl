// The visibility pipeline's set 2 (realtime/techniques/visibility.cpp), shared by the
// classification and the resolve.
#ifndef ILLUM_VISIBILITY_GLSL
#define ILLUM_VISIBILITY_GLSL
#include "common.glsl"

layout(set = 2, binding = 0) uniform usampler2D vis_ids;
layout(set = 2, binding = 1, rgba16f) uniform writeonly image2D hdr_image;
layout(std430, set = 2, binding = 2) readonly buffer Vertices { float vertex_data[]; };
layout(std430, set = 2, binding = 3) readonly buffer Indices { uint index_data[]; };
struct DrawData {
  mat4 model;
  ivec4 info;  // x: material (clamped like the draws'), y: first index, z: vertex offset,
               // w: the material's slot (its place among the materials in use)
};
layout(std430, set = 2, binding = 4) readonly buffer Draws { DrawData draws[]; };
// Per slot: the dispatch of its tiles (x: tiles, y = z = 1), then its tile list.
layout(std430, set = 2, binding = 5) buffer TileArgs { uvec4 tile_args[]; };
layout(std430, set = 2, binding = 6) buffer Tiles { uint tiles[]; };

const uint kNoId = 0xffffffffu;

// 8×8 tiles over the frame; each slot's list has room for all of them.
uint tiles_x() { return (uint(frame.extent.x) + 7u) / 8u; }
uint tile_count() { return tiles_x() * ((uint(frame.extent.y) + 7u) / 8u); }

#endif
