// Shared declarations of the real-time renderer: must match realtime/gpu_types.h (std430 /
// std140 layouts with vec4-aligned members only).
#ifndef ILLUM_COMMON_GLSL
#define ILLUM_COMMON_GLSL

const float kPi = 3.14159265358979;

const int kLightPoint = 0;
const int kLightSpot = 1;
const int kLightDirectional = 2;
const int kLightLambertian = 3;  // a spot whose intensity falls off as cos θ (area light)

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
};

// Set 0: the frame globals. A technique's own data lives in its own set (shadows.glsl: the
// shadow method's, set 3; lighting_inputs.glsl: the lighting inputs, set 4; gbuffer.glsl: the deferred
// pipeline's, set 2). The camera fields of `frame` are view 0's (the frame's camera): the
// screen-space passes over the frame's images read them; scene draws read `views[push.view]`.
layout(std140, set = 0, binding = 0) uniform Frame {
  mat4 view;
  mat4 proj;
  mat4 view_proj;
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz, w: time
  vec4 ambient;        // rgb constant ambient (where no baked lighting applies)
  ivec4 counts;        // x: lights, y: half-Lambert, z: single light index (−1 = all)
  vec4 extent;         // width, height, 1/width, 1/height
} frame;

layout(std430, set = 0, binding = 1) readonly buffer Materials { Material materials[]; };
layout(std430, set = 0, binding = 2) readonly buffer Lights { Light lights[]; };

// The camera block: every view a scene draw can be seen from (FrameGlobals::add_views), view 0
// the frame's camera. Scene-draw variants take theirs by push.view, so a technique can draw
// the scene with any variant from a light (shadow maps) or a capture's face.
struct View {
  mat4 view;
  mat4 proj;
  mat4 view_proj;
  mat4 inv_view_proj;
  vec4 camera_pos;  // xyz
  vec4 extent;      // width, height, 1/width, 1/height
  vec4 planes;      // near, far
};
layout(std430, set = 0, binding = 3) readonly buffer Views { View views[]; };

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
  int view;         // views[view]: the camera the draw is seen from
  int draw;         // the draw item's index (colour passes; 0 in depth-like ones)
  int light_index;  // shadow / per-light passes
  int mode;         // the variant's switch (forward.frag: which lights; visibility: id bits)
} push;

#endif
