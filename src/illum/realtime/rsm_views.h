// The reflective shadow maps' light table, "rsm.views" (techniques/rsm.cpp), written so that C++
// and GLSL both include this file and cannot drift apart. The maps "rsm.position",
// "rsm.normal" and "rsm.flux" are 2-D arrays with one layer per light view; the table says,
// per layer, which light it belongs to, how it was seen and how big its texels are.
//
// std430 buffer: an RsmHeader, then RsmView[header.counts.x]. Layer k of every map is
// views[k]. A light's views are consecutive: a spot up to kRsmMaxSpotHalfAngle one perspective
// view of its cone; a point light or a wider spot six cube faces (+x, −x, +y, −y, +z, −z, the
// OpenGL face order); a directional light one orthographic view.
//
// Texels: position (RGBA32F) xyz world position, w 1 where a surface was seen, 0 elsewhere;
// normal (RGBA16F) xyz the unit shading normal turned towards the light; flux (RGBA32F) rgb
// the flux the texel's surface reflects diffusely, Φ = I(ω)·Δω·ρ (point, spot: Δω the texel's
// exact solid angle, rsm_texel_solid_angle) or E·A·ρ (directional: A the texel's area on the
// light's plane, views[k].direction.w).
#ifndef ILLUM_RSM_VIEWS_H
#define ILLUM_RSM_VIEWS_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#define ILLUM_RSM_CONST inline constexpr
namespace illum::realtime::rsm {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
inline constexpr const char* kPosition = "rsm.position";
inline constexpr const char* kNormal = "rsm.normal";
inline constexpr const char* kFlux = "rsm.flux";
inline constexpr const char* kDepth = "rsm.depth";  // D32, one layer per view
inline constexpr const char* kViews = "rsm.views";  // storage buffer: this layout
#else
#define ILLUM_RSM_CONST const
#endif

ILLUM_RSM_CONST int kRsmMaxLayers = 48;  // lights whose views do not fit are left out
// Degrees: a spot up to this half angle gets one perspective view, a wider one a cube.
ILLUM_RSM_CONST float kRsmMaxSpotHalfAngle = 60.0f;
ILLUM_RSM_CONST int kRsmViewPerspective = 0;  // RsmView.info.w
ILLUM_RSM_CONST int kRsmViewCubeFace = 1;
ILLUM_RSM_CONST int kRsmViewOrthographic = 2;

struct RsmHeader {
  ivec4 counts;  // x: views (layers), y: resolution (texels per side), z: lights with views
  ivec4 pad;
};

struct RsmView {
  mat4 view_proj;      // world → clip of this layer (Vulkan depth 0..1)
  mat4 inv_view_proj;  // clip → world
  // xyz: the light's position (point, spot) or the orthographic box's centre (directional);
  // w: the light type (common.glsl kLight*)
  vec4 position_type;
  // xyz: the unit direction the view looks along (spot axis, cube face axis, light
  // direction); w: directional: a texel's area on the light's plane (m²); point, spot: tan of
  // the view's half field of view (1 for a cube face)
  vec4 direction;
  // x: the light's index in the frame's light list, y: its first layer, z: its layer count
  // (1 or 6), w: the view kind (kRsmView*)
  ivec4 info;
};

#ifdef __cplusplus
static_assert(sizeof(RsmHeader) == 32 && sizeof(RsmView) == 176);
}  // namespace illum::realtime::rsm
#else
// The exact solid angle of texel (x, y) of an n×n perspective view whose half field of view has
// tangent t: on the plane at distance 1 the texel is the rectangle [x0, x1] × [y0, y1]
// (x0 = t·(2x/n − 1), …), and a rectangle with a corner at the foot of the axis subtends
// F(x, y) = atan(x·y / √(1 + x² + y²)), so Δω = F(x1, y1) − F(x0, y1) − F(x1, y0) + F(x0, y0).
float rsm_corner(float x, float y) {
  return atan(x * y, sqrt(1.0 + x * x + y * y));
}
float rsm_texel_solid_angle(ivec2 texel, int n, float t) {
  float s = 2.0 * t / float(n);
  float x0 = -t + s * float(texel.x), x1 = x0 + s;
  float y0 = -t + s * float(texel.y), y1 = y0 + s;
  return rsm_corner(x1, y1) - rsm_corner(x0, y1) - rsm_corner(x1, y0) + rsm_corner(x0, y0);
}
#endif
#undef ILLUM_RSM_CONST

#endif
