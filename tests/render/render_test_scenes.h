// Small procedural scenes for the render tests (no files needed).
#pragma once

#include <cmath>
#include <vector>

#include "illum/scene/scene.h"

namespace illum::test {

inline int add_material(Scene& scene, const Material& m) {
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

// Adds a mesh from a triangle list (3 vertices per triangle, no shared vertices: flat
// shading, ns = ng) and an instance of it; returns the instance index.
inline int add_triangles(Scene& scene, const std::vector<vec3>& tris, int material,
                         const std::string& name = "mesh") {
  Mesh mesh;
  mesh.name = name;
  mesh.positions = tris;
  for (uint32_t i = 0; i < tris.size(); ++i) mesh.indices.push_back(i);
  mesh.material = material;
  scene.meshes.push_back(std::move(mesh));
  Instance inst;
  inst.name = name;
  inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
  scene.instances.push_back(inst);
  return static_cast<int>(scene.instances.size()) - 1;
}

// Quad a, b, c, d (counter-clockwise seen from the front).
inline void push_quad(std::vector<vec3>& tris, vec3 a, vec3 b, vec3 c, vec3 d) {
  tris.insert(tris.end(), {a, b, c, a, c, d});
}

// The y = 0 plane from −half to +half in x and z, facing +y.
inline std::vector<vec3> floor_quad(float half) {
  std::vector<vec3> t;
  push_quad(t, {-half, 0, half}, {half, 0, half}, {half, 0, -half}, {-half, 0, -half});
  return t;
}

// A UV sphere of radius r around c, faces wound so the normals point inward.
inline std::vector<vec3> inward_sphere(vec3 c, float r, int rings, int segments) {
  std::vector<vec3> t;
  auto p = [&](int i, int j) {
    const float theta = kPi * static_cast<float>(i) / static_cast<float>(rings);
    const float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
    return c + r * vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                        std::sin(theta) * std::sin(phi));
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const vec3 a = p(i, j), b = p(i + 1, j), cc = p(i + 1, j + 1), d = p(i, j + 1);
      // Outward winding would be a, d, cc / a, cc, b; reverse it.
      if (i != 0) t.insert(t.end(), {a, b, d});
      if (i != rings - 1) t.insert(t.end(), {d, b, cc});
    }
  }
  // Make every triangle face the centre (robust to the parameterization's orientation).
  for (size_t k = 0; k < t.size(); k += 3) {
    const vec3 n = glm::cross(t[k + 1] - t[k], t[k + 2] - t[k]);
    const vec3 centroid = (t[k] + t[k + 1] + t[k + 2]) / 3.0f;
    if (glm::dot(n, c - centroid) < 0.0f) std::swap(t[k + 1], t[k + 2]);
  }
  return t;
}

// Closed axis-aligned box [lo, hi], faces pointing inward (or outward).
inline std::vector<vec3> inward_box(vec3 lo, vec3 hi, bool inward = true) {
  std::vector<vec3> t;
  const vec3 c = 0.5f * (lo + hi);
  const vec3 v[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                     {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                     {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  const int f[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                       {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 2, 6, 5}};
  for (const auto& q : f) push_quad(t, v[q[0]], v[q[1]], v[q[2]], v[q[3]]);
  for (size_t k = 0; k < t.size(); k += 3) {
    const vec3 n = glm::cross(t[k + 1] - t[k], t[k + 2] - t[k]);
    const vec3 centroid = (t[k] + t[k + 1] + t[k + 2]) / 3.0f;
    if ((glm::dot(n, c - centroid) < 0.0f) == inward) std::swap(t[k + 1], t[k + 2]);
  }
  return t;
}

inline Light area_light(int instance) {
  Light l;
  l.type = LightType::kArea;
  l.instance = instance;
  return l;
}

// A closed, inward-facing Lambert sphere of albedo a emitting Le = 1 everywhere: the
// radiance is Le/(1−a) at every point and in every direction (white furnace).
inline Scene furnace_sphere(float a, int rings, int segments) {
  Scene s;
  Material m;
  m.albedo = Color(a);
  m.emission = Color(1.0f);
  const int mat = add_material(s, m);
  const int inst = add_triangles(s, inward_sphere(vec3(0), 1.0f, rings, segments), mat, "sphere");
  s.lights.push_back(area_light(inst));
  return s;
}

}  // namespace illum::test
