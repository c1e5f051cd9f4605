#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/scene/mesh_processing.h"
#include "test_util.h"

namespace illum {
namespace {

// Unit square in the xy plane, two triangles sharing the diagonal (shared vertices).
Mesh square(bool with_uv) {
  Mesh m;
  m.name = "square";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  if (with_uv) m.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  return m;
}

TEST(MeshProcessing, SmoothNormalsOnSharedVertices) {
  // A "roof": two faces meeting at the ridge, sharing the ridge vertices.
  Mesh m;
  m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 1, 0}, {1, 1, 1}, {2, 0, 0}, {2, 0, 1}};
  // Each ridge vertex is in as many triangles of equal area on both sides, so the
  // area-weighted average is symmetric.
  m.indices = {0, 1, 3, 0, 3, 2, 3, 5, 4, 3, 4, 2};
  compute_normals(m);
  // Ridge vertices average the two faces' normals (−1,1,0)/√2 and (1,1,0)/√2 → +y.
  EXPECT_NEAR(m.normals[2].y, 1.0f, 1e-5f);
  EXPECT_NEAR(m.normals[3].y, 1.0f, 1e-5f);
  // Eave vertices belong to one face only: its flat normal.
  EXPECT_NEAR(m.normals[0].x, -std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(m.normals[4].x, std::sqrt(0.5f), 1e-5f);
}

TEST(MeshProcessing, FlatNormalsWithoutSharingAndGivenNormalsKept) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
  m.indices = {0, 1, 2, 3, 4, 5};
  m.normals = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 5, 0}, {0, 5, 0}, {0, 5, 0}};
  compute_normals(m);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(m.normals[i], vec3(0, 0, 1));  // computed (zero = missing)
  for (int i = 3; i < 6; ++i) EXPECT_EQ(m.normals[i], vec3(0, 1, 0));  // given, normalized
}

TEST(MeshProcessing, TangentsAndHandedness) {
  Mesh m = square(true);
  compute_normals(m);
  compute_tangents(m);
  ASSERT_EQ(m.tangents.size(), 4u);
  for (const vec4& t : m.tangents) {
    EXPECT_NEAR(t.x, 1.0f, 1e-5f);
    EXPECT_EQ(t.w, 1.0f);  // bitangent (+v = +y) = cross(n, t) = cross(z, x)
  }
  // Mirrored v: the bitangent flips, the handedness turns negative.
  Mesh mirrored = square(true);
  for (vec2& uv : mirrored.uv0) uv.y = 1.0f - uv.y;
  compute_normals(mirrored);
  compute_tangents(mirrored);
  for (const vec4& t : mirrored.tangents) EXPECT_EQ(t.w, -1.0f);
  // No uvs: no tangents.
  Mesh plain = square(false);
  compute_normals(plain);
  compute_tangents(plain);
  EXPECT_TRUE(plain.tangents.empty());
}

TEST(MeshProcessing, TransformAndMirroring) {
  Mesh m = square(true);
  compute_normals(m);
  compute_tangents(m);
  transform_mesh(
      m, glm::scale(mat4(1.0f), vec3(1, 1, -3)) * glm::translate(mat4(1.0f), vec3(0, 0, 1)));
  EXPECT_EQ(m.positions[2], vec3(1, 1, -3));
  // Normal through the inverse transpose: +z → −z; the winding reverses with the mirror so
  // the geometric normal agrees with it.
  EXPECT_NEAR(m.normals[0].z, -1.0f, 1e-6f);
  const vec3 ng = glm::cross(m.positions[m.indices[1]] - m.positions[m.indices[0]],
                             m.positions[m.indices[2]] - m.positions[m.indices[0]]);
  EXPECT_LT(ng.z, 0.0f);
  EXPECT_EQ(m.tangents[0].w, -1.0f);
}

TEST(MeshProcessing, ValidateAndDegenerates) {
  Mesh m = square(false);
  EXPECT_NO_THROW(validate_mesh(m, "file.obj", 1));
  Mesh bad_material = m;
  bad_material.material = 3;
  EXPECT_THROW(validate_mesh(bad_material, "file.obj", 1), Error);
  Mesh bad_index = m;
  bad_index.indices[4] = 4;
  const std::string e1 = test::error_of([&] { validate_mesh(bad_index, "file.obj", 1); });
  EXPECT_TRUE(test::contains(e1, "file.obj: mesh 'square' triangle 1 uses vertex 4")) << e1;
  Mesh nan = m;
  nan.positions[3].y = std::nanf("");
  const std::string e2 = test::error_of([&] { validate_mesh(nan, "file.obj", 1); });
  EXPECT_EQ(e2, "file.obj: mesh 'square' has non-finite vertex 3");
  Mesh nan_uv = square(true);
  nan_uv.uv0[1].x = kInf;
  EXPECT_THROW(validate_mesh(nan_uv, "file.obj", 1), Error);

  // Scale-relative area: the same thin triangle is kept in a 1 km mesh and in a 1 mm one.
  for (float scale : {1e-3f, 1.0f, 1e3f}) {
    Mesh t;
    t.positions = {vec3(0), vec3(scale, 0, 0), vec3(0.5f * scale, 1e-4f * scale, 0),
                   vec3(2 * scale, 0, 0)};
    t.indices = {0, 1, 2, 0, 1, 3};  // the second is collinear
    EXPECT_EQ(drop_degenerate_triangles(t), 1u) << scale;
    EXPECT_EQ(t.triangle_count(), 1u);
  }
}

TEST(MeshProcessing, FinalizeRemovesEmptyMeshesAndRemapsLights) {
  Scene scene;
  scene.materials.resize(2);
  scene.materials[1].emission = Color(1.0f);
  Mesh empty = square(false);
  empty.indices = {0, 0, 1};  // only a degenerate triangle
  Mesh lamp = square(false);
  lamp.material = 1;
  scene.meshes = {empty, lamp};
  scene.instances = {Instance{"gone", 0, mat4(1.0f)}, Instance{"lamp", 1, mat4(1.0f)}};
  finalize_scene(scene, "x.obj");
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].mesh, 0);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].type, LightType::kArea);
  EXPECT_EQ(scene.lights[0].instance, 0);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(scene.warnings[0], "x.obj: dropped 1 degenerate"));
}

}  // namespace
}  // namespace illum
