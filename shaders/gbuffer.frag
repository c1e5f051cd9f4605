#version 450
#include "lighting.glsl"
// G-buffer: material inputs of the lighting pass, plus emission + ambient written straight
// into the HDR target (the lighting passes add to it).
layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_albedo;    // rgb albedo, a: material type / 4 (fp16)
layout(location = 1) out vec4 out_normal;    // xyz shading normal
layout(location = 2) out vec4 out_geometry;  // xyz geometric normal (facing the viewer), w: exponent
layout(location = 3) out vec4 out_specular;  // rgb ks
layout(location = 4) out vec4 out_hdr;       // emission + ambient

void main() {
  vec3 v = normalize(frame.camera_pos.xyz - in_world);
  vec3 n = normalize(in_normal);
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, dot(n, v) >= 0.0);
  out_albedo = vec4(s.albedo, float(s.type) / 4.0);
  out_normal = vec4(s.n, s.n_z);
  out_geometry = vec4(s.ng, s.exponent);
  out_specular = vec4(s.specular, 1.0);
  out_hdr = vec4(s.emission + ambient_term(s), 1.0);
}
