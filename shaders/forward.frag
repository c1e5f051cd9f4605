#version 450
#include "lighting.glsl"

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_color;

void main() {
  vec3 v = normalize(views[push.view].camera_pos.xyz - in_world);
  vec3 n = normalize(in_normal);
  bool front = dot(n, v) >= 0.0;  // two-sided surfaces, like the offline renderers
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, front);
  s.prt_vertex = in_prt;
  // push.mode: 0 = everything; 1 = emission + ambient only (depth pass of the stencil-shadow
  // technique); 2 = only light push.light_index, no shadow-map lookup (stencil masks it).
  int mode = push.mode;
  vec3 color = mode == 2 ? vec3(0.0) : s.emission + ambient_term(s, push.draw, gl_FragCoord.xy);
  if (mode == 0) {
    color += direct_light(s, v, gl_FragCoord.xy);
  } else if (mode == 2) {
    vec3 radiance, l;
    if (light_contribution(push.light_index, s, v, radiance, l)) color += radiance;
  }
  out_color = vec4(color, 1.0);
}
