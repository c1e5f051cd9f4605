#version 450
// The visibility buffer's resolve: per pixel, the triangle its id names is read from the
// index and vertex buffers and intersected with the pixel's camera ray; the barycentrics of
// the hit interpolate what forward.vert passes on (world position, normal through the normal
// matrix, tangent, both UV sets), and the barycentrics of the rays through the next pixel
// right and below, on the same plane, give the UV derivatives for the texture LOD (the
// fragment path's are finite differences over 2×2 quads). The surface then goes through
// lighting.glsl's own load_surface, ambient_term and light_contribution with the same
// shadow lookups, into the HDR target (emission + ambient + lights, written once).
//
// One indirect dispatch per material in use (push.material, its textures bound as set 1
// like a draw's; push.light_index: its slot) over the tiles that show it
// (visibility_classify.comp); a pixel of another material is left to that one's dispatch,
// so no texture array indexed per pixel is needed (lavapipe has no descriptor indexing).
layout(local_size_x = 8, local_size_y = 8) in;
#include "visibility.glsl"

// lighting.glsl's sampling hooks: explicit gradients (no quads in a compute shader).
vec2 g_uv0_dx, g_uv0_dy, g_uv1_dx, g_uv1_dy;
#define SAMPLE_MATERIAL(map, uv) textureGrad(map, uv, g_uv0_dx, g_uv0_dy)
#define SAMPLE_LIGHTMAP(uvw) textureGrad(lightmap, uvw, g_uv1_dx, g_uv1_dy)
#include "lighting.glsl"

const int kFloats = 14;  // realtime/gpu_types.h Vertex: position, normal, tangent, uv0, uv1

vec3 vertex_vec3(uint v, int offset) {
  uint b = v * kFloats + offset;
  return vec3(vertex_data[b], vertex_data[b + 1], vertex_data[b + 2]);
}
vec4 vertex_vec4(uint v, int offset) {
  uint b = v * kFloats + offset;
  return vec4(vertex_data[b], vertex_data[b + 1], vertex_data[b + 2], vertex_data[b + 3]);
}

// The camera ray through `pixel` (a pixel-centre position in pixels) as the rasterizer sees
// it: the inverse view-projection of two depths along it.
void pixel_ray(vec2 pixel, out vec3 origin, out vec3 dir) {
  vec2 ndc = pixel * views[push.view].extent.zw * 2.0 - 1.0;
  vec4 a = views[push.view].inv_view_proj * vec4(ndc, 0.0, 1.0);
  vec4 b = views[push.view].inv_view_proj * vec4(ndc, 0.5, 1.0);
  origin = a.xyz / a.w;
  dir = b.xyz / b.w - origin;
}

// Barycentrics (b0, b1, b2) of the ray's hit with the plane of (p0, p1, p2), unclamped.
vec3 barycentrics(vec2 pixel, vec3 p0, vec3 p1, vec3 p2) {
  vec3 o, d;
  pixel_ray(pixel, o, d);
  vec3 e1 = p1 - p0, e2 = p2 - p0;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  if (abs(det) < 1e-30) return vec3(1.0, 0.0, 0.0);  // edge-on: any vertex will do
  vec3 tv = o - p0;
  float u = dot(tv, pv) / det;
  vec3 qv = cross(tv, e1);
  float v = dot(d, qv) / det;
  return vec3(1.0 - u - v, u, v);
}

void main() {
  uint tile = tiles[uint(push.light_index) * tile_count() + gl_WorkGroupID.x];
  ivec2 pixel = ivec2(tile % tiles_x(), tile / tiles_x()) * 8 + ivec2(gl_LocalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  if (empty_pixel(pixel)) return;  // written by the classification
  uint id = texelFetch(vis_ids, pixel, 0).r;
  int tri_bits = push.mode;
  uint draw = id >> uint(tri_bits);
  uint triangle = id & ((1u << uint(tri_bits)) - 1u);
  DrawData dd = draws[draw];
  if (dd.info.x != push.material) return;
  uint first = uint(dd.info.y) + 3u * triangle;
  uint v0 = uint(int(index_data[first]) + dd.info.z);
  uint v1 = uint(int(index_data[first + 1u]) + dd.info.z);
  uint v2 = uint(int(index_data[first + 2u]) + dd.info.z);
  vec3 p0 = (dd.model * vec4(vertex_vec3(v0, 0), 1.0)).xyz;
  vec3 p1 = (dd.model * vec4(vertex_vec3(v1, 0), 1.0)).xyz;
  vec3 p2 = (dd.model * vec4(vertex_vec3(v2, 0), 1.0)).xyz;
  vec2 centre = vec2(pixel) + 0.5;
  vec3 b = barycentrics(centre, p0, p1, p2);
  vec3 bx = barycentrics(centre + vec2(1.0, 0.0), p0, p1, p2);
  vec3 by = barycentrics(centre + vec2(0.0, 1.0), p0, p1, p2);
  vec4 uv0 = vec4(vertex_data[v0 * kFloats + 10], vertex_data[v0 * kFloats + 11],
                  vertex_data[v0 * kFloats + 12], vertex_data[v0 * kFloats + 13]);
  vec4 uv1 = vec4(vertex_data[v1 * kFloats + 10], vertex_data[v1 * kFloats + 11],
                  vertex_data[v1 * kFloats + 12], vertex_data[v1 * kFloats + 13]);
  vec4 uv2 = vec4(vertex_data[v2 * kFloats + 10], vertex_data[v2 * kFloats + 11],
                  vertex_data[v2 * kFloats + 12], vertex_data[v2 * kFloats + 13]);
  vec4 uv = b.x * uv0 + b.y * uv1 + b.z * uv2;
  vec4 uv_dx = bx.x * uv0 + bx.y * uv1 + bx.z * uv2 - uv;
  vec4 uv_dy = by.x * uv0 + by.y * uv1 + by.z * uv2 - uv;
  g_uv0_dx = uv_dx.xy;
  g_uv0_dy = uv_dy.xy;
  g_uv1_dx = uv_dx.zw;
  g_uv1_dy = uv_dy.zw;

  mat3 normal_matrix = transpose(inverse(mat3(dd.model)));
  vec3 world = b.x * p0 + b.y * p1 + b.z * p2;
  vec3 normal = normal_matrix * (b.x * vertex_vec3(v0, 3) + b.y * vertex_vec3(v1, 3) +
                                 b.z * vertex_vec3(v2, 3));
  vec4 t = b.x * vertex_vec4(v0, 6) + b.y * vertex_vec4(v1, 6) + b.z * vertex_vec4(v2, 6);
  vec4 tangent = vec4(mat3(dd.model) * t.xyz, t.w);

  vec3 v = normalize(views[push.view].camera_pos.xyz - world);
  vec3 n = normalize(normal);
  Surface s = load_surface(dd.info.x, world, n, tangent, uv, dot(n, v) >= 0.0);
  if (prt_input.info.x == kPrtVertices)  // forward.vert's per-vertex relighting, interpolated
    s.prt_vertex = b.x * prt_point_relit(v0) + b.y * prt_point_relit(v1) + b.z * prt_point_relit(v2);
  vec3 color = s.emission + ambient_term(s, int(draw), centre);
  int first_light = frame.counts.z >= 0 ? frame.counts.z : 0;
  int last_light = frame.counts.z >= 0 ? frame.counts.z + 1 : frame.counts.x;
  for (int i = first_light; i < last_light; ++i) {
    vec3 radiance, l;
    if (!light_contribution(i, s, v, radiance, l)) continue;
    color += radiance * cube_shadow(i, s.p, s.ng, centre);
  }
  imageStore(hdr_image, pixel, vec4(color, 1.0));
}
