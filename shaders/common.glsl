// Shared declarations of the real-time renderer: must match realtime/gpu_types.h (std430 /
// std140 layouts with vec4-aligned members only).
#ifndef ILLUM_COMMON_GLSL
#define ILLUM_COMMON_GLSL

const float kPi = 3.14159265358979;

const int kLightPoint = 0;
const int kLightSpot = 1;
const int kLightDirectional = 2;
const int kLightLambertian = 3;  // a spot whose intensity falls off as cos θ (area light)

const int kShadowNone = 0;
const int kShadowMap = 1;      // PCF with rotated Poisson taps
const int kShadowVsm = 2;      // variance shadow maps with light-bleeding threshold τ
const int kShadowVolume = 3;   // stencil shadow volumes (lighting pass per light)

struct Material {
  vec4 albedo;     // rgb, opacity
  vec4 specular;   // rgb ks, exponent n
  vec4 emission;   // rgb L_e, normal_scale
  ivec4 textures;  // albedo, normal, emission, specular map (−1 = none)
  ivec4 info;      // x: MaterialType
};

struct Light {
  vec4 position_range;  // xyz position, w: culling radius r (0 = none)
  vec4 direction_cos;   // xyz unit direction the light travels, w: cos of spot cutoff
  vec4 color_type;      // rgb: I (point/spot, W/sr) or E (directional, W/m²), w: type
  ivec4 shadow;         // x: shadow slot (−1 = none), y: first cascade/face view, z: views, w: 1 = 2-D spot map
  vec4 shadow_params;   // x: far distance of the shadow map, y: spot map tan(half field of view)
};

layout(std140, set = 0, binding = 0) uniform Frame {
  mat4 view;
  mat4 proj;
  mat4 view_proj;
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz, w: time
  vec4 ambient;        // rgb constant ambient (when no light-map), w: light-map intensity
  ivec4 counts;        // x: lights, y: half-Lambert, z: shadow mode, w: PCF taps
  vec4 shadow_config;  // x: depth bias (relative), y: PCF radius (texels), z: VSM τ, w: min variance
  vec4 cascade_splits; // view-space far distance of each cascade
  ivec4 options;       // x: single light index (−1 = all), y: light-map kind (0 none, 1 plain, 2 RNM, 3 SH-L1), z: PRT on
  vec4 extent;         // width, height, 1/width, 1/height
  vec4 prt_light[4];   // PRT: the lights' SH-L1 radiance (Y00, Y1−1, Y10, Y11), RGB
} frame;

layout(std430, set = 0, binding = 1) readonly buffer Materials { Material materials[]; };
layout(std430, set = 0, binding = 2) readonly buffer Lights { Light lights[]; };
layout(std430, set = 0, binding = 3) readonly buffer ShadowViews { mat4 shadow_views[]; };
// Cube maps of all shadowed point/spot lights in one array (lavapipe has no descriptor
// indexing, so no arrays of samplers): layer = slot.
layout(set = 0, binding = 4) uniform samplerCubeArray shadow_cubes;
layout(set = 0, binding = 5) uniform sampler2DArray cascade_maps;
// Light-map layers (uv1): 1 = plain, 3 = RNM basis 0..2, 4 = SH-L1 coefficients 0..3.
layout(set = 0, binding = 6) uniform sampler2DArray lightmap;
// Ambient cubes (Source engine): 6 RGB values (+x, −x, +y, −y, +z, −z) per probed draw,
// interpolated on the CPU from the probe grid at the instance's centre.
layout(std430, set = 0, binding = 7) readonly buffer AmbientCubes { vec4 ambient_cubes[]; };

// PRT: per-vertex SH-L1 transfer vectors (Y00, Y1−1, Y10, Y11), indexed by gl_VertexIndex.
layout(std430, set = 0, binding = 8) readonly buffer Transfer { vec4 prt_transfer[]; };

// One 2-D perspective map (frustum = the cone) per shadowed narrow spot light: layer = slot.
layout(set = 0, binding = 9) uniform sampler2DArray spot_maps;

// Octahedral unit-vector encoding (both components in [−1, 1]) for the compact G-buffer.
vec2 oct_encode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return n.xy;
}
vec3 oct_decode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

// Per-material textures (set 1); a white 1×1 texture where the material has none.
layout(set = 1, binding = 0) uniform sampler2D albedo_map;
layout(set = 1, binding = 1) uniform sampler2D normal_map;
layout(set = 1, binding = 2) uniform sampler2D emission_map;
layout(set = 1, binding = 3) uniform sampler2D specular_map;

layout(push_constant) uniform Push {
  mat4 model;
  int material;
  int view_index;   // shadow passes: which shadow view; colour passes: ambient cube + 1 (0: none)
  int light_index;  // shadow / per-light passes
  int pad;
} push;

#endif
