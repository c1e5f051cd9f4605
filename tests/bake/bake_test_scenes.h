// Small hand-built scenes with light-map coordinates for the raster and baker tests (no
// atlas builder involved: uv1 is set by hand).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../render/render_test_scenes.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/core/error.h"
#include "illum/scene/scene.h"

namespace illum::test {

inline int add_lambert(Scene& scene, const Color& albedo, const Color& emission = Color(0.0f)) {
  Material m;
  m.albedo = albedo;
  m.emission = emission;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

// Adds `mesh` and one instance of it with `transform`; returns the instance index.
inline int add_instance(Scene& scene, Mesh mesh, const mat4& transform = mat4(1.0f)) {
  const std::string name = mesh.name;
  scene.meshes.push_back(std::move(mesh));
  Instance inst;
  inst.name = name;
  inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
  inst.transform = transform;
  scene.instances.push_back(inst);
  return static_cast<int>(scene.instances.size()) - 1;
}

// The y = 0 square [−half, half]² facing +y (4 shared vertices, 2 triangles), with normals
// +y, tangents (tangent, sign) and uv1 = ((x + half), (z + half)) / (2·half) mapped into
// the uv1 rectangle [uv_lo, uv_hi].
inline Mesh uv_plane(float half, int material, const vec4& tangent = vec4(1, 0, 0, 1),
                     vec2 uv_lo = vec2(0.0f), vec2 uv_hi = vec2(1.0f)) {
  Mesh m;
  m.name = "plane";
  m.positions = {{-half, 0, half}, {half, 0, half}, {half, 0, -half}, {-half, 0, -half}};
  m.normals.assign(4, vec3(0, 1, 0));
  m.tangents.assign(4, tangent);
  for (const vec3& p : m.positions) {
    const vec2 t((p.x + half) / (2.0f * half), (p.z + half) / (2.0f * half));
    m.uv1.push_back(uv_lo + t * (uv_hi - uv_lo));
  }
  m.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from +y
  m.material = material;
  return m;
}

// A closed box [−1,1]³ of Lambert albedo a whose every face emits Le toward the inside; the
// floor (y = −1) is a separate instance carrying uv1. Every point inside receives
// Le·Σ_{k≤N} a^k after N bounces.
inline Scene furnace_box(float a, float le) {
  Scene s;
  const int mat = add_lambert(s, Color(a), Color(le));
  const int floor =
      add_instance(s, uv_plane(1.0f, mat), glm::translate(mat4(1.0f), vec3(0.0f, -1.0f, 0.0f)));
  std::vector<vec3> rest;
  const std::vector<vec3> box = inward_box(vec3(-1.0f), vec3(1.0f));
  for (size_t k = 0; k < box.size(); k += 3)
    if (!(box[k].y == -1.0f && box[k + 1].y == -1.0f && box[k + 2].y == -1.0f))
      rest.insert(rest.end(), {box[k], box[k + 1], box[k + 2]});
  EXPECT_EQ(rest.size(), 30u);
  const int walls = add_triangles(s, rest, mat, "walls");
  s.lights.push_back(area_light(floor));
  s.lights.push_back(area_light(walls));
  return s;
}

// The message of the Error LightmapBakeOptions::from_params throws for `options`, or "" if it
// accepts them.
inline std::string bake_options_error(const nlohmann::json& options) {
  try {
    bake::LightmapBakeOptions::from_params(Params(options, "opts.json"));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace illum::test
