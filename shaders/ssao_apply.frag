#version 450
// Applies SSAO to the indirect terms only: the scene drawn again with depth EQUAL over the
// frame's HDR target, adding (a − 1)·indirect with a = the combined AO factor and indirect =
// the ambient term (constant, light-map, ambient cube or PRT) — exactly what the pipelines'
// shaders added, so the frame becomes emission + a·indirect + direct. Direct light is never
// touched, nor PRT-lit surfaces (their transfer holds the visibility). A stencil count lets only
// the first of coplanar duplicate surfaces apply.
#include "lighting.glsl"
#include "ambient_occlusion.glsl"
layout(set = 2, binding = 3) uniform sampler2D ao_map;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_color;

void main() {
  vec3 v = normalize(frame.camera_pos.xyz - in_world);
  vec3 n = normalize(in_normal);
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, dot(n, v) >= 0.0);
  s.prt_vertex = in_prt;
  vec3 indirect = ambient_term(s);
  float screen = texelFetch(ao_map, ivec2(gl_FragCoord.xy), 0).r;
  float a = combine_ambient_occlusion(screen, baked_ambient_occlusion());
  // PRT transfer already holds the visibility SSAO estimates: darkening it again would count
  // every occluder twice, so such surfaces keep their frame (a = 1 adds nothing).
  if (ambient_term_includes_visibility(push.view_index)) a = 1.0;
  out_color = vec4((a - 1.0) * indirect, 0.0);
}
