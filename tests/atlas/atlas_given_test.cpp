// What a scene may ask of the atlas: a mesh's own UV1 kept when it is valid (and charted
// anew when it is not, or when asked), and a texel size of its own (Instance::
// lightmap_texel_size, from the scene file) instead of the atlas's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "../scene/test_util.h"  // error_of, contains
#include "atlas_check.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/atlas_report.h"
#include "illum/atlas/uv1_check.h"
#include "illum/core/error.h"

namespace illum::atlas {
namespace {

using test::check_atlas;
using test::make_scene;
using test::split_grid;

using illum::test::contains;
using illum::test::error_of;

AtlasOptions options_of(int resolution, float texel_size) {
  AtlasOptions o;
  o.resolution = resolution;
  o.texel_size = texel_size;
  return o;
}

// A floor and a wall meeting at a right angle (an L, 1 m × 1 m each), with a UV1 that
// unrolls them side by side: floor [0, ½]², wall [½, 1] × [0, ½] (2 m² on ¼ of the unit
// square: 2 m per UV1 unit). Charted anew, faces 90° apart give two charts.
Mesh unrolled_l() {
  Mesh m;
  m.name = "L";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {1, 1, 0}, {1, 1, 1}};
  m.uv1 = {{0, 0}, {0.5f, 0}, {0.5f, 0.5f}, {0, 0.5f}, {1, 0}, {1, 0.5f}};
  m.indices = {0, 2, 1, 0, 3, 2, 1, 4, 5, 1, 5, 2};
  return m;
}

std::string problem_of(const Mesh& mesh) {
  return mesh_uv1_problem(mesh, mat4(1.0f)).value_or("");
}

TEST(AtlasGiven, KeepsAValidUv1AsOneChartAtTheNominalDensity) {
  const Scene scene = make_scene({unrolled_l()});
  EXPECT_EQ(problem_of(scene.meshes[0]), "");
  const AtlasOptions options = options_of(128, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_TRUE(atlas.meshes[0].reused_uv1);
  EXPECT_EQ(atlas.chart_count, 1);
  EXPECT_EQ(atlas.meshes[0].source_vertex.size(), 6u);  // one chart: no seam to split
  check_atlas(scene, atlas, options, {0});
  // The layout is the given one, turned and scaled: every distance in the atlas is the
  // given one × 2 m per unit / texel size (in texels), so the L keeps its unrolled shape.
  const MeshLayout& layout = atlas.meshes[0];
  const double s = atlas.texel_size, W = atlas.width;
  for (size_t a = 0; a < 6; ++a)
    for (size_t b = a + 1; b < 6; ++b) {
      const double given = glm::length(glm::dvec2(scene.meshes[0].uv1[layout.source_vertex[a]] -
                                                  scene.meshes[0].uv1[layout.source_vertex[b]]));
      const double texels = glm::length(glm::dvec2(layout.uv1[a] - layout.uv1[b])) * W;
      // Float uv1 rounds each end by 2⁻²⁴·W texels at most.
      EXPECT_NEAR(texels, given * 2.0 / s, 2.0 * std::ldexp(W, -24) + 1e-9 * W)
          << "vertices " << a << " and " << b;
    }
  Scene charted = scene;
  apply_atlas(charted, atlas);
  const AtlasStats stats = measure_atlas(charted, atlas);
  EXPECT_NEAR(stats.meshes[0].mean_density, 1.0, 1e-5);
}

TEST(AtlasGiven, RegeneratesWhenAsked) {
  const Scene scene = make_scene({unrolled_l()});
  AtlasOptions options = options_of(128, 0.0f);
  options.reuse_uv1 = false;
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_FALSE(atlas.meshes[0].reused_uv1);
  EXPECT_EQ(atlas.chart_count, 2);  // the floor and the wall
  check_atlas(scene, atlas, options);
}

TEST(AtlasGiven, NamesWhatMakesAUv1Unusable) {
  Mesh overlap = unrolled_l();
  overlap.uv1[4] = {0.25f, 0.0f};  // the wall folded back over the floor
  EXPECT_TRUE(contains(problem_of(overlap), "overlap")) << problem_of(overlap);
  Mesh outside = unrolled_l();
  outside.uv1[5] = {1.5f, 0.5f};
  EXPECT_TRUE(contains(problem_of(outside), "outside [0,1]")) << problem_of(outside);
  Mesh flat = unrolled_l();
  flat.uv1[4] = flat.uv1[1];
  flat.uv1[5] = flat.uv1[2];  // the wall squashed onto the shared edge: surface, no texels
  EXPECT_TRUE(contains(problem_of(flat), "no uv1 area")) << problem_of(flat);
  Mesh nan = unrolled_l();
  nan.uv1[2].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(contains(problem_of(nan), "non-finite")) << problem_of(nan);
  Mesh short_list = unrolled_l();
  short_list.uv1.pop_back();
  EXPECT_TRUE(contains(problem_of(short_list), "5 uv1 for 6 vertices")) << problem_of(short_list);
  // A mirrored UV1 (the same layout flipped) is fine.
  Mesh mirrored = unrolled_l();
  for (vec2& uv : mirrored.uv1) uv.x = 1.0f - uv.x;
  EXPECT_EQ(problem_of(mirrored), "");
}

// An unusable UV1 is no error: the mesh is charted anew (a warning says why).
TEST(AtlasGiven, ChartsAnInvalidUv1Anew) {
  Mesh overlap = unrolled_l();
  overlap.uv1[4] = {0.25f, 0.0f};
  const Scene scene =
      make_scene({overlap, unrolled_l()}, {mat4(1.0f), glm::translate(mat4(1.0f), vec3(3, 0, 0))});
  const AtlasOptions options = options_of(128, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_FALSE(atlas.meshes[0].reused_uv1);
  EXPECT_TRUE(atlas.meshes[1].reused_uv1);  // judged per mesh
  EXPECT_EQ(atlas.chart_count, 3);
  check_atlas(scene, atlas, options, {1});
}

// Two 4 m grids; the second's scene entry asks for 5 cm texels. Its chart is 4 / 0.05 = 80
// texels (+ the cell margin: 81 cells) whatever the atlas's texel size, found or given.
TEST(AtlasGiven, MeshTexelSizeOverridesTheAtlas) {
  Scene scene = make_scene({split_grid(4), split_grid(4)},
                           {mat4(1.0f), glm::translate(mat4(1.0f), vec3(9, 0, 0))});
  scene.instances[1].lightmap_texel_size = 0.05f;
  for (const float given : {0.0f, 0.1f}) {
    const AtlasOptions options = options_of(256, given);
    const Atlas atlas = build_atlas(scene, options);
    ASSERT_EQ(atlas.chart_count, 2);
    const AtlasChart& own = atlas.charts[0].mesh == 1 ? atlas.charts[0] : atlas.charts[1];
    const AtlasChart& other = atlas.charts[0].mesh == 1 ? atlas.charts[1] : atlas.charts[0];
    EXPECT_EQ(own.width, 81);
    EXPECT_EQ(own.height, 81);
    EXPECT_EQ(other.width, int(std::ceil(4.0 / atlas.texel_size + 2.0 / 256.0)));
    if (given > 0.0f) {
      EXPECT_EQ(atlas.texel_size, given);
    }
    EXPECT_NE(atlas.texel_size, 0.05f);
    check_atlas(scene, atlas, options);  // each mesh's density at its own texel size
    Scene charted = scene;
    apply_atlas(charted, atlas);
    const AtlasStats stats = measure_atlas(charted, atlas);
    EXPECT_NEAR(stats.meshes[0].mean_density, 1.0, 1e-5);
    EXPECT_NEAR(stats.meshes[1].mean_density, 1.0, 1e-5);
  }
  // Every mesh with its own size: nothing to search, the atlas reports the finest.
  scene.instances[0].lightmap_texel_size = 0.08f;
  const Atlas both = build_atlas(scene, options_of(256, 0.0f));
  EXPECT_EQ(both.texel_size, 0.05f);
  check_atlas(scene, both, options_of(256, 0.0f));
  // ... and when they cannot fit, the error says where the sizes come from.
  scene.instances[0].lightmap_texel_size = 0.01f;  // 400 texels: more than the atlas
  const std::string message = error_of([&] { build_atlas(scene, options_of(256, 0.0f)); });
  EXPECT_TRUE(contains(message, "texel sizes their scene file gives")) << message;
}

}  // namespace
}  // namespace illum::atlas
