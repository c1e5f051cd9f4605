#version 450
#include "common.glsl"
#include "inputs/prt.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv0;
layout(location = 4) in vec2 in_uv1;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) out vec4 out_uv;
layout(location = 4) out vec3 out_prt;  // per-vertex PRT: Σ T_i L_i (RGB), inputs/prt.glsl
// The depth pre-pass and the shading pass (depth EQUAL) must compute identical depths:
// no FMA contraction that a compiler could choose differently per pipeline. (The SPIR-V
// Invariant decoration would say more but trips the validator on block members.)
precise gl_Position;

void main() {
  vec4 world = push.model * vec4(in_position, 1.0);
  mat3 normal_matrix = transpose(inverse(mat3(push.model)));
  out_world = world.xyz;
  out_normal = normal_matrix * in_normal;
  out_tangent = vec4(mat3(push.model) * in_tangent.xyz, in_tangent.w);
  out_uv = vec4(in_uv0, in_uv1);
  // Relit here and interpolated: Σ T_i L_i is linear in T, so this equals relighting the
  // interpolated transfer (gl_VertexIndex counts from the draw's vertex offset: the scene
  // vertex buffer's index, the transfer points' order).
  out_prt = prt_input.info.x == kPrtVertices ? prt_point_relit(uint(gl_VertexIndex)) : vec3(0.0);
  gl_Position = views[push.view].view_proj * world;
}
