// The shadow method's set (set 3, realtime/frame_globals.h kShadowSet): what the lighting
// passes look shadows up in, and what the shadow-map passes render from. Must match
// ShadowUniforms / GpuShadowLight in realtime/gpu_types.h. Without shadow maps (none,
// volume) the renderer binds a neutral set with mode 0.
#ifndef ILLUM_SHADOW_SET_GLSL
#define ILLUM_SHADOW_SET_GLSL
#include "common.glsl"

const int kShadowNone = 0;
const int kShadowMap = 1;  // PCF with rotated Poisson taps
const int kShadowVsm = 2;  // variance shadow maps with light-bleeding threshold τ

struct ShadowLight {
  ivec4 slot;    // x: map slot (−1 = none), y: first view, z: views, w: 1 = 2-D spot map
  vec4 params;   // x: far distance (cascades: the 4 ortho half-widths), y: spot tan(half fov)
};

layout(std140, set = 3, binding = 0) uniform Shadows {
  ivec4 config;          // x: mode, y: PCF taps
  vec4 params;           // x: depth bias (relative), y: PCF radius (texels), z: VSM τ, w: min variance
  vec4 cascade_splits;   // view-space far distance of each cascade
} shadow;
layout(std430, set = 3, binding = 1) readonly buffer ShadowViews { mat4 shadow_views[]; };
// Cube maps of all shadowed point/spot lights in one array (lavapipe has no descriptor
// indexing, so no arrays of samplers): layer = slot.
layout(set = 3, binding = 2) uniform samplerCubeArray shadow_cubes;
layout(set = 3, binding = 3) uniform sampler2DArray cascade_maps;
// One 2-D perspective map (frustum = the cone) per shadowed narrow spot light: layer = slot.
layout(set = 3, binding = 4) uniform sampler2DArray spot_maps;
layout(std430, set = 3, binding = 5) readonly buffer ShadowLights { ShadowLight shadow_lights[]; };

#endif
