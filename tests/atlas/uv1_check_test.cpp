// Given uv1 sets (atlas/uv1_check.h): overlaps found within and across meshes, mirrored and
// touching triangles accepted, bad input named.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "illum/atlas/atlas.h"
#include "illum/atlas/uv1_check.h"
#include "illum/core/error.h"
#include "illum/scene/load.h"

namespace illum::atlas {
namespace {

// A unit square in world space as two triangles, its uv1 the square [lo, lo + size]².
Mesh square(const std::string& name, vec2 lo, float size, bool mirrored = false) {
  Mesh m;
  m.name = name;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  for (const vec3& p : m.positions) {
    const float u = mirrored ? 1.0f - p.x : p.x;
    m.uv1.push_back(lo + size * vec2(u, p.z));
  }
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

std::string error_of(const Scene& scene) {
  try {
    check_given_uv1(scene);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Uv1Check, AcceptsTouchingAndMirroredCharts) {
  Scene scene;
  scene.meshes.push_back(square("a", vec2(0.0f), 0.5f));
  scene.meshes.push_back(square("b", vec2(0.5f, 0.0f), 0.5f, true));  // shares an edge with a
  scene.meshes.push_back(square("c", vec2(0.0f, 0.5f), 0.5f));
  EXPECT_FALSE(find_uv1_overlap(scene).has_value());
  EXPECT_EQ(error_of(scene), "");
}

TEST(Uv1Check, FindsAnOverlapAcrossMeshes) {
  Scene scene;
  scene.meshes.push_back(square("a", vec2(0.0f), 0.5f));
  scene.meshes.push_back(square("b", vec2(0.25f, 0.5f), 0.5f));  // touches a along y = 0.5
  scene.meshes.push_back(square("c", vec2(0.4f, 0.1f), 0.3f));   // overlaps a's triangle 0
  const auto o = find_uv1_overlap(scene);
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(o->mesh_a, 0);
  EXPECT_EQ(o->mesh_b, 2);
  const std::string e = error_of(scene);
  EXPECT_NE(e.find("mesh 'a' triangle"), std::string::npos) << e;
  EXPECT_NE(e.find("overlaps mesh 'c'"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(Uv1Check, FindsAFoldWithinOneMesh) {
  // One mesh whose second triangle is folded back over the first (a chart overlapping
  // itself, as a careless unwrap of a spiral gives).
  Scene scene;
  Mesh m = square("folded", vec2(0.1f), 0.5f);
  m.uv1[3] = m.uv1[1] + vec2(0.0f, 0.3f);  // triangle 1 (0, 2, 3) now covers part of 0
  scene.meshes.push_back(m);
  const auto o = find_uv1_overlap(scene);
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(o->mesh_a, 0);
  EXPECT_EQ(o->triangle_a, 0);
  EXPECT_EQ(o->triangle_b, 1);
}

// Every atlas the builder makes has no overlap (atlas_check.h checks the same per chart),
// so the check passes on a charted Cornell box and fails once one chart is moved onto
// another.
TEST(Uv1Check, ChartedCornellPassesAndAShiftedChartFails) {
  Scene scene = load_scene("cornell");
  make_meshes_unique(scene);
  AtlasOptions options;
  options.resolution = 64;
  const Atlas atlas = build_atlas(scene, options);
  apply_atlas(scene, atlas);
  EXPECT_EQ(error_of(scene), "");
  // Put the last mesh's uv1 on top of the first mesh's.
  Mesh& first = scene.meshes.front();
  Mesh& last = scene.meshes.back();
  vec2 lo_first(1.0f), lo_last(1.0f);
  for (const vec2& uv : first.uv1) lo_first = glm::min(lo_first, uv);
  for (const vec2& uv : last.uv1) lo_last = glm::min(lo_last, uv);
  for (vec2& uv : last.uv1) uv += lo_first - lo_last;
  EXPECT_NE(error_of(scene), "");
}

TEST(Uv1Check, NamesBadInput) {
  Scene scene;
  Mesh m = square("broken", vec2(0.0f), 0.5f);
  m.uv1[2].x = std::numeric_limits<float>::quiet_NaN();
  scene.meshes.push_back(m);
  const std::string e = error_of(scene);
  EXPECT_NE(e.find("mesh 'broken'"), std::string::npos) << e;
  m = square("short", vec2(0.0f), 0.5f);
  m.uv1.pop_back();
  scene.meshes = {m};
  EXPECT_NE(error_of(scene).find("mesh 'short'"), std::string::npos);
}

}  // namespace
}  // namespace illum::atlas
