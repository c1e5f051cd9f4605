#version 450
// GPU silhouette extraction for stencil shadow volumes (S002 §4.3, ALGORITHMS.md 23): one
// invocation per triangle of one light, the same rules as the CPU reference
// (realtime/shadow_volume_builder.cpp). A caster emits its front cap (pushed cap_offset away
// from the light), its back cap at infinity (w = 0) and a side quad on every silhouette edge,
// all wound outward; it reserves room for them with one atomic add on the light's draw
// count (a VkDrawIndirectCommand), so the volumes are drawn without a CPU readback.
layout(local_size_x = 64) in;

struct VolumeTriangle {
  vec4 p[3];         // world positions; p[0].w = 1: open mesh (casts whichever way it faces)
  ivec4 neighbour;   // xyz: triangle across edge (v[k], v[k+1]), < 0 none; w: bit k = the
                     // neighbour runs edge k the same way in its own winding
};

layout(std430, set = 0, binding = 0) readonly buffer Triangles { VolumeTriangle triangles[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Volume { vec4 vertices[]; };
layout(std430, set = 0, binding = 2) buffer DrawArgs { uint draw_args[]; };  // 4 uints a light

layout(push_constant) uniform Push {
  vec4 position_range;  // point/spot position, range (0 = none)
  vec4 direction_type;  // unit direction the light travels, type (0 point, 1 spot, 2 directional)
  vec4 params;          // x: spot cone half-angle, y: cap offset, z: 1 = back-facing casters
  uvec4 counts;         // x: triangles, y: the light's slot in draw_args
} push;

const float kPi = 3.14159265358979;

bool directional() { return int(push.direction_type.w) == 2; }

// n·(to light) of the triangle's own winding; `precise` so that the triangle and its
// neighbours, which evaluate it again, always agree on its sign.
float facing(VolumeTriangle t) {
  precise vec3 n = cross(t.p[1].xyz - t.p[0].xyz, t.p[2].xyz - t.p[0].xyz);
  precise vec3 to_light =
      directional() ? -push.direction_type.xyz : push.position_range.xyz - t.p[0].xyz;
  precise float f = dot(n, to_light);
  return f;
}

// Every ray from the light through the triangle's bounding sphere misses the spot's cone or
// ends beyond the light's range: its volume could only shadow points the light does not
// reach. The cone test is the CPU's, in cosines, with 1e-3 rad to spare for GPU asin/cos.
// `precise` for the same reason as facing(): every evaluation of a triangle must agree.
bool outside_light(VolumeTriangle t) {
  if (directional()) return false;
  precise vec3 c = (t.p[0].xyz + t.p[1].xyz + t.p[2].xyz) / 3.0;
  precise float r =
      max(length(t.p[0].xyz - c), max(length(t.p[1].xyz - c), length(t.p[2].xyz - c)));
  precise vec3 to = c - push.position_range.xyz;
  precise float d = length(to);
  if (d <= r * 1.001) return false;
  float range = push.position_range.w;
  if (range > 0.0 && d - r > range) return true;
  if (int(push.direction_type.w) != 1) return false;
  precise float reach = push.params.x + asin(min(r / d, 1.0)) + 1e-3;
  precise float cosine = dot(to / d, push.direction_type.xyz);
  return reach < kPi && cosine < cos(reach);
}

bool caster(VolumeTriangle t, float f) {
  bool open = t.p[0].w != 0.0;
  bool c = open ? f != 0.0 : push.params.z != 0.0 ? f < 0.0 : f > 0.0;
  return c && !outside_light(t);
}

// Direction from the light through p (the way the shadow extends).
vec3 away(vec3 p) {
  return directional() ? push.direction_type.xyz : normalize(p - push.position_range.xyz);
}

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= push.counts.x) return;
  VolumeTriangle t = triangles[index];
  float f = facing(t);
  if (!caster(t, f)) return;
  bool flipped = f < 0.0;
  // Silhouette edges: no neighbour, a neighbour that does not cast, or one that casts but
  // is folded so that the two side quads on the edge would not cancel.
  bool side[3];
  uint count = 6u;
  for (int k = 0; k < 3; ++k) {
    side[k] = true;
    int nb = t.neighbour[k];
    if (nb >= 0) {
      VolumeTriangle o = triangles[nb];
      float fo = facing(o);
      bool same_direction = (t.neighbour.w & (1 << k)) != 0;
      if (caster(o, fo) && same_direction == (flipped != (fo < 0.0))) side[k] = false;
    }
    if (side[k]) count += 6u;
  }
  uint base = atomicAdd(draw_args[push.counts.y * 4u], count);

  vec4 near_v[3], far_v[3];
  for (int k = 0; k < 3; ++k) {
    vec3 d = away(t.p[k].xyz);
    near_v[k] = vec4(t.p[k].xyz + d * push.params.y, 1.0);
    far_v[k] = vec4(d, 0.0);
  }
  // Caps: the front cap's normal points at the light (outward: the volume lies beyond it).
  int i1 = flipped ? 2 : 1, i2 = flipped ? 1 : 2;
  vertices[base + 0u] = near_v[0];
  vertices[base + 1u] = near_v[i1];
  vertices[base + 2u] = near_v[i2];
  vertices[base + 3u] = far_v[0];
  vertices[base + 4u] = far_v[i2];
  vertices[base + 5u] = far_v[i1];
  uint next = base + 6u;
  for (int k = 0; k < 3; ++k) {
    if (!side[k]) continue;
    // Edge k in the outward winding runs a → b.
    int a = flipped ? (k + 1) % 3 : k, b = flipped ? k : (k + 1) % 3;
    vertices[next + 0u] = near_v[b];
    vertices[next + 1u] = near_v[a];
    vertices[next + 2u] = far_v[a];
    vertices[next + 3u] = near_v[b];
    vertices[next + 4u] = far_v[a];
    vertices[next + 5u] = far_v[b];
    next += 6u;
  }
}
