#version 450
#include "lighting.glsl"
// Compact G-buffer (see gbuffer.glsl): the material inputs of the lighting pass, plus
// emission + ambient written straight into the HDR target (the lighting pass adds to it).
layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_albedo;    // rgb albedo, a: Phong exponent (fp16)
layout(location = 1) out vec4 out_normal;    // octahedral shading normal, geometric normal
layout(location = 2) out vec4 out_specular;  // rgb ks, a: material type / 255
layout(location = 3) out vec4 out_hdr;       // emission + ambient

void main() {
  vec3 v = normalize(frame.camera_pos.xyz - in_world);
  vec3 n = normalize(in_normal);
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, dot(n, v) >= 0.0);
  s.prt_vertex = in_prt;
  out_albedo = vec4(s.albedo, s.exponent);
  out_normal = vec4(oct_encode(s.n), oct_encode(s.ng));
  out_specular = vec4(s.specular, float(s.type) / 255.0);
  out_hdr = vec4(s.emission + ambient_term(s), 1.0);
}
