#include "illum/realtime/shadow_volume_builder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <unordered_map>

namespace illum::realtime {

namespace {

struct Key {
  int64_t x, y, z;
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};

}  // namespace

ShadowVolumeBuilder::ShadowVolumeBuilder(const Scene& scene) {
  const Bounds3 b = scene.bounds();
  // Positions closer than 1e-6 of the scene size are the same vertex (OBJ files often
  // duplicate vertices per face; adjacency needs them shared).
  const float cell = std::max(b.diagonal(), 1e-6f) * 1e-6f;
  std::unordered_map<Key, uint32_t, KeyHash> ids;
  auto weld = [&](const vec3& p) {
    const Key k{std::llround(p.x / cell), std::llround(p.y / cell), std::llround(p.z / cell)};
    auto [it, inserted] = ids.emplace(k, static_cast<uint32_t>(ids.size()));
    return it->second;
  };
  std::vector<std::pair<size_t, size_t>> instance_ranges;
  for (const Instance& inst : scene.instances) {
    const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
    instance_ranges.emplace_back(triangles_.size(), triangles_.size());
    if (scene.materials.size() > static_cast<size_t>(m.material) &&
        scene.materials[static_cast<size_t>(m.material)].is_emissive())
      continue;  // emitters do not cast (the light sits in their fixture)
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        tri.p[k] = vec3(inst.transform * vec4(m.positions[m.indices[t + k]], 1.0f));
        tri.v[k] = weld(tri.p[k]);
        tri.neighbour[k] = -1;
      }
      if (tri.v[0] == tri.v[1] || tri.v[1] == tri.v[2] || tri.v[0] == tri.v[2]) continue;
      triangles_.push_back(tri);
    }
    instance_ranges.back().second = triangles_.size();
  }
  // Undirected edge → (triangle, edge slot); a third user makes the edge non-manifold.
  std::map<std::pair<uint32_t, uint32_t>, std::pair<int32_t, int>> first;
  for (size_t t = 0; t < triangles_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = triangles_[t].v[k], c = triangles_[t].v[(k + 1) % 3];
      const auto key = std::minmax(a, c);
      auto it = first.find(key);
      if (it == first.end()) {
        first.emplace(key, std::make_pair(static_cast<int32_t>(t), k));
        continue;
      }
      auto& [other, slot] = it->second;
      if (other < 0) {  // already non-manifold
        triangles_[t].neighbour[k] = -2;
        continue;
      }
      Triangle& o = triangles_[static_cast<size_t>(other)];
      if (o.neighbour[slot] == -1) {
        o.neighbour[slot] = static_cast<int32_t>(t);
        triangles_[t].neighbour[k] = other;
      } else {  // third triangle on this edge: every user treats it as a silhouette
        const int32_t second = o.neighbour[slot];
        o.neighbour[slot] = -2;
        Triangle& s = triangles_[static_cast<size_t>(second)];
        for (int j = 0; j < 3; ++j)
          if (s.neighbour[j] == other) s.neighbour[j] = -2;
        triangles_[t].neighbour[k] = -2;
        other = -1;
      }
    }
  for (Triangle& tri : triangles_)
    for (int k = 0; k < 3; ++k) {
      if (tri.neighbour[k] < 0) continue;
      const Triangle& o = triangles_[static_cast<size_t>(tri.neighbour[k])];
      for (int j = 0; j < 3; ++j)
        tri.same_direction[k] =
            tri.same_direction[k] || (o.v[j] == tri.v[k] && o.v[(j + 1) % 3] == tri.v[(k + 1) % 3]);
    }
  for (const auto& [begin, end] : instance_ranges) {
    bool open = false;
    for (size_t t = begin; t < end && !open; ++t)
      for (int k = 0; k < 3; ++k) open = open || triangles_[t].neighbour[k] < 0;
    for (size_t t = begin; t < end; ++t) triangles_[t].open = open;
  }
}

void ShadowVolumeBuilder::build(const Light& light, bool back_facing_casters, float cap_offset,
                                std::vector<glm::vec4>* out, ShadowVolumeStats* stats) const {
  const auto t0 = std::chrono::steady_clock::now();
  out->clear();
  const bool directional = light.type == LightType::kDirectional;
  const vec3 travel = glm::normalize(light.direction);
  // Direction from the light through p (the way the shadow extends).
  auto away = [&](const vec3& p) {
    return directional ? travel : glm::normalize(p - light.position);
  };
  // A triangle whose rays from the light all miss the spot's cone, or that lies beyond the
  // light's range, shadows only points the light does not reach: its volume would be pure
  // fill. Conservative through the triangle's bounding sphere.
  auto outside_light = [&](const Triangle& tri) {
    if (directional) return false;
    const vec3 c = (tri.p[0] + tri.p[1] + tri.p[2]) / 3.0f;
    float r = 0.0f;
    for (const vec3& p : tri.p) r = std::max(r, glm::length(p - c));
    const vec3 to = c - light.position;
    const float d = glm::length(to);
    if (d <= r * 1.001f) return false;
    if (light.range > 0.0f && d - r > light.range) return true;
    if (light.type != LightType::kSpot) return false;
    const float angle = std::acos(std::clamp(glm::dot(to / d, travel), -1.0f, 1.0f));
    return angle - std::asin(std::min(r / d, 1.0f)) > light.cone_half_angle;
  };
  std::vector<int8_t> caster(triangles_.size(), 0), flipped(triangles_.size(), 0);
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const vec3 n = glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
    const vec3 to_light = directional ? -travel : light.position - tri.p[0];
    const float facing = glm::dot(n, to_light);
    flipped[t] = facing < 0.0f;
    caster[t] = tri.open ? facing != 0.0f : back_facing_casters ? (facing < 0.0f) : (facing > 0.0f);
    if (caster[t] && outside_light(tri)) caster[t] = 0;
  }
  ShadowVolumeStats s;
  for (size_t t = 0; t < triangles_.size(); ++t) {
    if (!caster[t]) continue;
    ++s.caster_triangles;
    const Triangle& tri = triangles_[t];
    // Order the corners so the cap's normal points at the light (outward for the volume,
    // which lies on the far side of the caster).
    int order[3] = {0, 1, 2};
    const vec3 n = glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
    const vec3 to_light = directional ? -travel : light.position - tri.p[0];
    if (glm::dot(n, to_light) < 0.0f) std::swap(order[1], order[2]);
    vec4 near_v[3], far_v[3];
    for (int k = 0; k < 3; ++k) {
      const vec3 p = tri.p[order[k]];
      const vec3 d = away(p);
      near_v[k] = vec4(p + d * cap_offset, 1.0f);
      far_v[k] = vec4(d, 0.0f);
    }
    out->insert(out->end(), {near_v[0], near_v[1], near_v[2]});
    out->insert(out->end(), {far_v[0], far_v[2], far_v[1]});
    for (int k = 0; k < 3; ++k) {
      // Edge (order[k], order[k+1]) in the outward winding; find its slot in the triangle.
      const int a = order[k], b = order[(k + 1) % 3];
      int slot = -1;
      for (int j = 0; j < 3; ++j)
        if ((j == a && (j + 1) % 3 == b) || (j == b && (j + 1) % 3 == a)) slot = j;
      const int32_t nb = tri.neighbour[slot];
      if (nb >= 0 && caster[static_cast<size_t>(nb)]) {
        // Both casters: their side quads on this edge cancel only when the edge runs in
        // opposite directions in the two light-facing windings (a consistently wound
        // surface); a caster folded the other way needs its side to stay closed.
        const bool reversed =
            tri.same_direction[slot] == (flipped[t] != flipped[static_cast<size_t>(nb)]);
        if (reversed) continue;
      }
      ++s.silhouette_edges;
      const vec4 na = near_v[k], nb_v = near_v[(k + 1) % 3];
      const vec4 fa = far_v[k], fb = far_v[(k + 1) % 3];
      out->insert(out->end(), {nb_v, na, fa, nb_v, fa, fb});
    }
  }
  s.volume_triangles = out->size() / 3;
  s.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (stats) *stats = s;
}

}  // namespace illum::realtime
