// CPU mirrors of the structures in shaders/common.glsl (set 0), shadow_set.glsl (set 3) and
// the lighting inputs (set 4, shaders/inputs/): vec4-aligned, std140/std430 alike.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace illum::realtime {

struct GpuMaterial {
  glm::vec4 albedo;     // rgb, opacity
  glm::vec4 specular;   // rgb ks, exponent
  glm::vec4 emission;   // rgb, normal_scale
  glm::ivec4 textures;  // albedo, normal, emission, specular map
  glm::ivec4 info;      // x: MaterialType
};

struct GpuLight {
  glm::vec4 position_range;
  glm::vec4 direction_cos;
  glm::vec4 color_type;
};

struct FrameUniforms {
  glm::mat4 view;
  glm::mat4 proj;
  glm::mat4 view_proj;
  glm::mat4 inv_view_proj;
  glm::vec4 camera_pos;
  glm::vec4 ambient;
  glm::ivec4 counts;  // lights, half-Lambert, single light (−1 all)
  glm::vec4 extent;
};

// One view of the camera block (set 0, binding 3: common.glsl `views`): view 0 is the
// frame's camera; techniques add further ones (FrameGlobals::add_views).
struct GpuView {
  glm::mat4 view;
  glm::mat4 proj;
  glm::mat4 view_proj;
  glm::mat4 inv_view_proj;
  glm::vec4 camera_pos;  // xyz
  glm::vec4 extent;      // width, height, 1/width, 1/height
  glm::vec4 planes;      // near, far
};

// Set 3, the shadow method's: shadow_set.glsl.
enum class ShadowLookup : int { kNone = 0, kMap = 1, kVsm = 2 };
struct ShadowUniforms {
  glm::ivec4 config;  // mode (ShadowLookup), PCF taps
  glm::vec4 params;   // bias, PCF radius (texels), VSM τ, min variance
  glm::vec4 cascade_splits;
};
struct GpuShadowLight {
  glm::ivec4 slot;   // map slot (−1 none), first view, views, 1 = 2-D spot map
  glm::vec4 params;  // far distance (cascades: 4 half-widths), spot tan(half fov)
};

// Set 4, the lighting inputs' blocks: shaders/inputs/*.glsl.
inline constexpr int kMaxPrtCoefficients = 64;  // 8 bands
inline constexpr int kProbeLookupPixel = 1;     // size.w: the per-pixel volume lookup
struct ProbesInputUniforms {                    // inputs/probes.glsl
  glm::ivec4 size;    // probe grid nx, ny, nz; w: kProbeLookupPixel or 0 (ambient cubes)
  glm::vec4 origin;   // xyz: probe (0, 0, 0)
  glm::vec4 spacing;  // xyz
  glm::ivec4 info;    // entries of draw_cubes
};
struct PrtInputUniforms {  // inputs/prt.glsl
  glm::ivec4 info;         // PRT lookup (PrtLookup), bands²
  glm::ivec4 size;         // atlas width, height; halves per point (3·bands² rounded up to even)
  glm::vec4 light[kMaxPrtCoefficients];
};
struct LightmapInputUniforms {  // inputs/lightmap.glsl
  glm::ivec4 info;              // light-map kind
  glm::vec4 intensity;
};

struct PushConstants {
  glm::mat4 model;
  int32_t material = 0;
  int32_t view = 0;  // the camera block's view the draw is seen from
  int32_t draw = 0;  // the draw item's index (colour passes; 0 in depth-like ones)
  int32_t light_index = 0;
  int32_t mode = 0;  // the variant's switch (forward.frag's lights; visibility's id bits)
};
static_assert(sizeof(PushConstants) == 84);

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec4 tangent;
  glm::vec2 uv0;
  glm::vec2 uv1;
};
static_assert(sizeof(Vertex) == 56);

inline constexpr int kMaxShadowCubes = 8;
inline constexpr int kMaxSpotMaps = 16;
// Spot lights up to this cone half-angle get a 2-D perspective shadow map; wider ones
// (e.g. area lights as hemispherical spots) keep a cube map.
inline constexpr float kMaxSpotMapHalfAngle = 1.0471976f;  // 60°

}  // namespace illum::realtime
