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
// The id target is not cleared (its clear was 0.15 ms of a 1080p frame on the H200): a pixel
// shows geometry where the depth is below 1, and only there is its id defined.
layout(set = 2, binding = 7) uniform sampler2D vis_depth;

bool empty_pixel(ivec2 pixel) { return texelFetch(vis_depth, pixel, 0).r >= 1.0; }

// 8×8 tiles over the frame; each slot's list has room for all of them.
uint tiles_x() { return (uint(frame.extent.x) + 7u) / 8u; }
uint tile_count() { return tiles_x() * ((uint(frame.extent.y) + 7u) / 8u); }

#endif
