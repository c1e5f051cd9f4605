// scene/geometry_hash.h: each hashed field changes the hash, each field it leaves out
// does not, and the hash is the same for the same scene loaded twice.
#include <gtest/gtest.h>

#include <functional>

#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"

namespace illum {
namespace {

Scene quad() {
  Scene s;
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals.assign(4, vec3(0, 0, 1));
  m.tangents.assign(4, vec4(1, 0, 0, 1));
  m.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.uv1 = m.uv0;
  m.indices = {0, 1, 2, 0, 2, 3};
  s.meshes = {m, m};
  s.instances = {{"a", 0, mat4(1.0f)}, {"b", 1, mat4(1.0f)}};
  s.materials.resize(1);
  return s;
}

TEST(GeometryHash, EveryHashedFieldChangesIt) {
  const uint64_t base = geometry_hash(quad());
  EXPECT_EQ(geometry_hash(quad()), base);
  EXPECT_EQ(geometry_hash_hex(quad()).size(), 16u);
  const std::pair<const char*, std::function<void(Scene&)>> edits[] = {
      {"position", [](Scene& s) { s.meshes[1].positions[2].y = 1.0001f; }},
      {"normal", [](Scene& s) { s.meshes[0].normals[0] = glm::normalize(vec3(0, 0.01f, 1)); }},
      {"tangent sign", [](Scene& s) { s.meshes[0].tangents[3].w = -1.0f; }},
      {"uv1", [](Scene& s) { s.meshes[0].uv1[1].x = 0.5f; }},
      {"no uv1", [](Scene& s) { s.meshes[0].uv1.clear(); }},
      {"index order", [](Scene& s) { std::swap(s.meshes[0].indices[1], s.meshes[0].indices[2]); }},
      {"transform", [](Scene& s) { s.instances[1].transform[3].x = 0.001f; }},
      {"instance mesh", [](Scene& s) { s.instances[1].mesh = 0; }},
      {"instances swapped", [](Scene& s) { std::swap(s.instances[0].mesh, s.instances[1].mesh); }},
      {"one instance fewer", [](Scene& s) { s.instances.pop_back(); }},
  };
  for (const auto& [name, edit] : edits) {
    Scene s = quad();
    edit(s);
    EXPECT_NE(geometry_hash(s), base) << name;
  }
}

TEST(GeometryHash, WhatItLeavesOutKeepsIt) {
  const uint64_t base = geometry_hash(quad());
  Scene s = quad();
  s.name = "other";
  s.instances[0].name = "renamed";
  s.meshes[0].name = "mesh";
  s.meshes[0].uv0[2] = vec2(7, 7);
  s.meshes[0].material = 3;
  s.materials.resize(5);
  s.lights.resize(2);
  EXPECT_EQ(geometry_hash(s), base);
}

TEST(GeometryHash, SameSceneLoadedTwice) {
  const std::string cornell = ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json";
  EXPECT_EQ(geometry_hash(load_scene(cornell)), geometry_hash(load_scene(cornell)));
}

}  // namespace
}  // namespace illum
