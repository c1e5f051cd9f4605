// Atlas building on small synthetic scenes with known answers: charts, welding, projection
// density, overlap repair, degenerate triangles, packing limits, options, apply_atlas.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../scene/test_util.h"  // error_of, contains
#include "atlas_check.h"
#include "illum/atlas/atlas.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"

namespace illum::atlas {
namespace {

using test::check_atlas;
using test::make_mesh;
using test::make_scene;
using test::split_grid;

using illum::test::contains;
using illum::test::error_of;

AtlasOptions options_of(int resolution, float texel_size, int padding = 2, float angle = 45.0f) {
  AtlasOptions o;
  o.resolution = resolution;
  o.texel_size = texel_size;
  o.padding = padding;
  o.max_chart_angle = angle;
  return o;
}

// A roof: two slopes at ±slope degrees about the x axis, meeting at a ridge along x, each
// slope one quad, `width` along x and `depth` down the slope; vertices split at the ridge.
Mesh roof(float slope_deg, float width = 1.0f, float depth = 1.0f) {
  const float c = std::cos(radians(slope_deg)), s = std::sin(radians(slope_deg));
  const vec3 ridge0(0.0f, 0.0f, 0.0f), ridge1(width, 0.0f, 0.0f);
  const vec3 down_north(0.0f, -s * depth, -c * depth), down_south(0.0f, -s * depth, c * depth);
  return make_mesh("roof",
                   {ridge0, ridge1, ridge0 + down_north, ridge1 + down_north,  // north slope
                    ridge0, ridge1, ridge0 + down_south, ridge1 + down_south},
                   {0, 1, 2, 2, 1, 3, 4, 6, 5, 5, 6, 7});
}

TEST(Atlas, OptionsFromParams) {
  const AtlasOptions defaults = AtlasOptions::from_params(Params());
  EXPECT_EQ(defaults.resolution, 512);
  EXPECT_EQ(defaults.texel_size, 0.0f);
  EXPECT_EQ(defaults.padding, 2);
  EXPECT_EQ(defaults.max_chart_angle, 45.0f);

  const Params p(
      nlohmann::json{
          {"resolution", 1024}, {"texel_size", 0.05}, {"padding", 3}, {"max_chart_angle", 30}},
      "test.json");
  const AtlasOptions o = AtlasOptions::from_params(p);
  EXPECT_EQ(o.resolution, 1024);
  EXPECT_FLOAT_EQ(o.texel_size, 0.05f);
  EXPECT_EQ(o.padding, 3);
  EXPECT_EQ(o.max_chart_angle, 30.0f);
  EXPECT_NO_THROW(p.check_all_used());  // every key was read

  auto message_for = [](const std::string& key, nlohmann::json value) {
    return error_of([&] {
      AtlasOptions::from_params(Params(nlohmann::json::object({{key, value}}), "opts.json"));
    });
  };
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, nlohmann::json>>{{"resolution", 8},
                                                           {"resolution", 20000},
                                                           {"texel_size", -0.1},
                                                           {"texel_size", "fine"},
                                                           {"padding", 0},
                                                           {"padding", 17},
                                                           {"max_chart_angle", 0},
                                                           {"max_chart_angle", 90}}) {
    const std::string message = message_for(key, value);
    EXPECT_TRUE(contains(message, "opts.json")) << message;
    EXPECT_TRUE(contains(message, key)) << message;
  }
  // Options built by hand are checked by build_atlas too.
  const Scene scene = make_scene({split_grid(1)});
  EXPECT_TRUE(contains(error_of([&] { build_atlas(scene, options_of(8, 0.0f)); }), "resolution"));
  EXPECT_TRUE(contains(error_of([&] { build_atlas(scene, options_of(64, NAN)); }), "texel_size"));
  EXPECT_TRUE(contains(error_of([&] { build_atlas(scene, options_of(64, 0.0f, 0)); }), "padding"));
  EXPECT_TRUE(contains(error_of([&] { build_atlas(scene, options_of(64, 0.0f, 2, 95.0f)); }),
                       "max_chart_angle"));
}

TEST(Atlas, MakeMeshesUnique) {
  Scene scene = make_scene({split_grid(2)});
  scene.instances.push_back(scene.instances[0]);
  scene.instances.push_back(scene.instances[0]);
  scene.instances[1].name = "second";
  scene.instances[1].transform = glm::translate(mat4(1.0f), vec3(5.0f, 0.0f, 0.0f));
  scene.instances[2].name = "third";
  scene.instances[2].transform = glm::translate(mat4(1.0f), vec3(10.0f, 0.0f, 0.0f));
  const std::string message = error_of([&] { build_atlas(scene, options_of(64, 0.0f)); });
  EXPECT_TRUE(contains(message, "make_meshes_unique")) << message;
  EXPECT_TRUE(contains(message, "second")) << message;

  make_meshes_unique(scene);
  ASSERT_EQ(scene.meshes.size(), 3u);
  EXPECT_EQ(scene.instances[0].mesh, 0);
  EXPECT_EQ(scene.instances[1].mesh, 1);
  EXPECT_EQ(scene.instances[2].mesh, 2);
  EXPECT_EQ(scene.meshes[2].positions, scene.meshes[0].positions);
  EXPECT_EQ(scene.meshes[2].indices, scene.meshes[0].indices);
  make_meshes_unique(scene);  // idempotent
  EXPECT_EQ(scene.meshes.size(), 3u);
  EXPECT_EQ(scene.instances[2].mesh, 2);

  const AtlasOptions options = options_of(64, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_EQ(atlas.chart_count, 3);  // one flat 2×2 grid per instance
  check_atlas(scene, atlas, options);
}

// One flat square of side L, texel size given: one chart whose rectangle is the texels the
// square can touch, floor(L/s + margin) + 1 per side, and the density is exactly 1.
TEST(Atlas, SquareAtGivenTexelSize) {
  const Scene scene = make_scene({split_grid(1, 1.0f)});
  const AtlasOptions options = options_of(64, 0.1f);
  const Atlas atlas = build_atlas(scene, options);
  ASSERT_EQ(atlas.chart_count, 1);
  EXPECT_EQ(atlas.charts[0].width, 11);  // 10 texels of side plus the one it may graze
  EXPECT_EQ(atlas.charts[0].height, 11);
  EXPECT_EQ(atlas.charts[0].x, options.padding);
  EXPECT_EQ(atlas.charts[0].y, options.padding);
  const auto report = check_atlas(scene, atlas, options);
  EXPECT_NEAR(report.min_density_ratio, 1.0, 1e-5);
  EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-5);
  // Centred in its 11 cells, the 10-texel square spans [0.5, 10.5] of them: it touches all.
  EXPECT_EQ(report.covered_texels, 11u * 11u);
}

// texel_size 0: the finest size that fits. For one square of side L in an atlas of R texels
// with padding p it is analytic: its floor(L/s + 2m) + 1 cells must fit R − 2p, i.e.
// s > L / (R − 2p − 2m) with m = 1/256 the placement margin; the search brackets it to 0.1 %.
TEST(Atlas, FinestTexelSizeOfOneSquare) {
  const float side = 3.0f;
  const Scene scene = make_scene({split_grid(1, side)});
  for (int padding : {1, 2, 4}) {
    const AtlasOptions options = options_of(128, 0.0f, padding);
    const Atlas atlas = build_atlas(scene, options);
    const double finest = side / (128.0 - 2.0 * padding - 2.0 / 256.0);
    EXPECT_GE(atlas.texel_size, finest * (1.0 - 1e-6)) << padding;
    EXPECT_LE(atlas.texel_size, finest * (1.0 + 1.01e-3)) << padding;
    EXPECT_EQ(atlas.charts[0].width, 128 - 2 * padding);
    check_atlas(scene, atlas, options);
  }
}

// Split vertices (every quad its own four) still form one chart: adjacency welds positions.
TEST(Atlas, WeldsSplitVerticesIntoOneChart) {
  const Scene scene = make_scene({split_grid(6)});
  const AtlasOptions options = options_of(128, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_EQ(atlas.chart_count, 1);
  // Vertices are split only where charts meet: none here, so the count stays 4 per quad.
  EXPECT_EQ(atlas.meshes[0].source_vertex.size(), scene.meshes[0].positions.size());
  const auto report = check_atlas(scene, atlas, options);
  EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-4);
}

// A roof of two slopes at ±20°: with a 45° limit both slopes are one chart projected along
// the mean normal (vertical), which loses cos 20° of each triangle's area; the chart is then
// scaled back to the nominal density, exact here because both slopes lose the same (before
// that scaling every triangle got cos 20° = 0.940 of its texels, as the bunny's charts did);
// with a 15° limit each slope is its own chart at exact density.
TEST(Atlas, RoofProjectionDensity) {
  const Scene scene = make_scene({roof(20.0f, 2.0f, 1.0f)});
  {
    const AtlasOptions options = options_of(128, 0.0f, 2, 45.0f);
    const Atlas atlas = build_atlas(scene, options);
    EXPECT_EQ(atlas.chart_count, 1);
    const auto report = check_atlas(scene, atlas, options);
    EXPECT_NEAR(report.min_density_ratio, 1.0, 1e-4);
    EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-4);
  }
  {
    const AtlasOptions options = options_of(128, 0.0f, 2, 15.0f);
    const Atlas atlas = build_atlas(scene, options);
    EXPECT_EQ(atlas.chart_count, 2);
    const auto report = check_atlas(scene, atlas, options);
    EXPECT_NEAR(report.min_density_ratio, 1.0, 1e-4);
    EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-4);
  }
}

// A closed cube: faces 90° apart never share a chart at 45°; six charts, seam vertices split.
TEST(Atlas, CubeHasSixCharts) {
  std::vector<vec3> p;
  std::vector<uint32_t> idx;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = float(sign);
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = 1.0f;
      if (sign < 0) std::swap(u, v);  // keep u × v = n (outward, counter-clockwise)
      const uint32_t base = uint32_t(p.size());
      for (int k = 0; k < 4; ++k) p.push_back(n + (k & 1 ? u : -u) + (k & 2 ? v : -v));
      for (uint32_t i : {0u, 1u, 2u, 2u, 1u, 3u}) idx.push_back(base + i);
    }
  // Four vertices per face, as loaders split them at the normal seams; adjacency welds them.
  Mesh mesh = make_mesh("cube", p, idx);
  const Scene scene = make_scene({mesh});
  const AtlasOptions options = options_of(64, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_EQ(atlas.chart_count, 6);
  const auto report = check_atlas(scene, atlas, options);
  EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-4);
}

// Geometry that overlaps itself in projection although every normal is within the limit:
// a spiral ramp of two turns, and a floor with a coincident copy of one of its quads. The
// charts must be split until no triangles overlap (check_atlas tests every pair).
TEST(Atlas, SelfOverlappingChartsAreSplit) {
  Mesh ramp;
  ramp.name = "spiral";
  const int steps = 96;  // two turns
  for (int i = 0; i <= steps; ++i) {
    const float a = 2.0f * kPi * 2.0f * float(i) / steps;
    const float h = 0.5f * float(i) / steps;  // a gentle climb: normals within ~3° of +y
    ramp.positions.push_back(vec3(std::cos(a), h, -std::sin(a)));
    ramp.positions.push_back(vec3(3.0f * std::cos(a), h, -3.0f * std::sin(a)));
  }
  for (uint32_t i = 0; i < uint32_t(steps); ++i) {
    const uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3;
    for (uint32_t v : {a, b, c, c, b, d}) ramp.indices.push_back(v);
  }
  Mesh floor = split_grid(4);
  const Mesh copy = split_grid(1);  // the quad at the origin again, its own vertices
  for (uint32_t i : copy.indices) floor.indices.push_back(i + uint32_t(floor.positions.size()));
  floor.positions.insert(floor.positions.end(), copy.positions.begin(), copy.positions.end());
  const Scene scene = make_scene({ramp, floor});
  const AtlasOptions options = options_of(256, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  int ramp_charts = 0, floor_charts = 0;
  for (const AtlasChart& c : atlas.charts) (c.mesh == 0 ? ramp_charts : floor_charts)++;
  EXPECT_GE(ramp_charts, 2);   // two turns cannot lie in one plane without overlap
  EXPECT_LE(ramp_charts, 4);   // ...but the split keeps the largest injective pieces
  EXPECT_EQ(floor_charts, 2);  // the two coincident quads cannot share a chart
  check_atlas(scene, atlas, options);
}

// Zero-area triangles (collinear, repeated index, all corners equal) do not break anything:
// they share one tiny chart per mesh and survive apply_atlas.
TEST(Atlas, DegenerateTrianglesGetATinyPlace) {
  Mesh mesh = split_grid(2);
  const uint32_t n = uint32_t(mesh.positions.size());
  mesh.positions.push_back(vec3(0.0f, 0.0f, 0.0f));
  mesh.positions.push_back(vec3(1.0f, 0.0f, 0.0f));
  mesh.positions.push_back(vec3(2.0f, 0.0f, 0.0f));  // collinear with the two before
  for (uint32_t i : {n, n + 1, n + 2, 0u, 0u, 1u, n + 1, n + 1, n + 1}) mesh.indices.push_back(i);
  Scene scene =
      make_scene({mesh, make_mesh("only_degenerate", {vec3(0.0f), vec3(1.0f)}, {0, 1, 1})});
  const AtlasOptions options = options_of(64, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_EQ(atlas.chart_count, 3);  // the grid, its degenerates, the other mesh's degenerate
  const auto report = check_atlas(scene, atlas, options);
  EXPECT_EQ(report.degenerate, 4u);
  const Scene before = scene;
  apply_atlas(scene, atlas);
  EXPECT_EQ(scene.meshes[0].triangle_count(), before.meshes[0].triangle_count());
  EXPECT_EQ(scene.meshes[1].uv1.size(), scene.meshes[1].positions.size());
}

// The density is in world space: an instance scaled by 3 gets 3× the texels per side.
TEST(Atlas, InstanceTransformsSetTheDensity) {
  const mat4 scaled = glm::scale(glm::translate(mat4(1.0f), vec3(0.0f, 2.0f, 0.0f)), vec3(3.0f));
  const mat4 turned = glm::rotate(mat4(1.0f), radians(90.0f), vec3(1.0f, 0.0f, 0.0f));
  const mat4 mirrored = glm::scale(mat4(1.0f), vec3(-1.0f, 1.0f, 1.0f));
  const Scene scene = make_scene({split_grid(1), split_grid(1), split_grid(1), split_grid(1)},
                                 {mat4(1.0f), scaled, turned, mirrored});
  const AtlasOptions options = options_of(128, 0.05f);
  const Atlas atlas = build_atlas(scene, options);
  ASSERT_EQ(atlas.chart_count, 4);
  int sides[4] = {};
  for (const AtlasChart& c : atlas.charts) sides[c.mesh] = c.width;
  EXPECT_EQ(sides[0], 21);  // 1 m / 0.05 m = 20 texels, +1 it may graze
  EXPECT_EQ(sides[1], 61);  // 3 m
  EXPECT_EQ(sides[2], 21);
  EXPECT_EQ(sides[3], 21);
  const auto report = check_atlas(scene, atlas, options);
  EXPECT_NEAR(report.min_density_ratio, 1.0, 1e-4);
  EXPECT_NEAR(report.max_density_ratio, 1.0, 1e-4);
}

// An L-shaped floor wastes a quarter of its rectangle, a big right triangle half of its;
// small charts are placed there (nested rectangles), still with the padding to the floor's
// texels and to each other (check_atlas). The triangle's free half is a staircase of
// adjacent free rectangles.
TEST(Atlas, SmallChartsFillTheHolesOfLargeOnes) {
  Mesh floor = split_grid(2, 10.0f);
  floor.indices.resize(3 * 6);  // three of the four quads: an L
  const Mesh ramp =
      make_mesh("ramp", {vec3(0.0f, 5.0f, 0.0f), vec3(0.0f, 5.0f, 15.0f), vec3(15.0f, 5.0f, 0.0f)},
                {0, 1, 2});
  Mesh pieces;
  pieces.name = "pieces";
  const uint32_t count = 150;
  for (uint32_t i = 0; i < count; ++i) {  // separate triangles of 7 sizes, one chart each
    const float x = 50.0f + 4.0f * float(i % 10), z = 4.0f * float(i / 10);
    const float size = 0.3f + 0.4f * float(i % 7);
    pieces.positions.insert(pieces.positions.end(),
                            {vec3(x, 0.0f, z), vec3(x, 0.0f, z + size), vec3(x + size, 0.0f, z)});
    pieces.indices.insert(pieces.indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
  }
  for (const Mesh& host_mesh : {floor, ramp}) {
    const Scene scene = make_scene({host_mesh, pieces});
    for (int padding : {1, 2, 5}) {
      const AtlasOptions options = options_of(256, 0.0f, padding);
      const Atlas atlas = build_atlas(scene, options);
      ASSERT_EQ(atlas.chart_count, int(count) + 1);
      const AtlasChart& host = atlas.charts[0];
      ASSERT_EQ(host.mesh, 0);
      int nested = 0;
      for (const AtlasChart& c : atlas.charts)
        nested += c.mesh == 1 && c.x >= host.x && c.y >= host.y &&
                  c.x + c.width <= host.x + host.width && c.y + c.height <= host.y + host.height;
      EXPECT_GT(nested, 10) << host_mesh.name << ", padding " << padding;
      check_atlas(scene, atlas, options);
    }
  }
}

TEST(Atlas, DoesNotFitIsAnError) {
  const Scene scene = make_scene({split_grid(1, 10.0f)});
  // 10 m at 0.1 m per texel needs 101 texels; 64 has 60 inside the padding.
  std::string message = error_of([&] { build_atlas(scene, options_of(64, 0.1f)); });
  EXPECT_TRUE(contains(message, "64×64")) << message;
  EXPECT_TRUE(contains(message, "0.1")) << message;
  EXPECT_TRUE(contains(message, "finest")) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  // 30 separate triangles in a 16² atlas with padding 2: each needs 1 + 2 texels per side,
  // the 14² bin holds at most 16 of them, whatever the texel size.
  Mesh many;
  many.name = "many";
  for (uint32_t i = 0; i < 30; ++i) {
    const float x = 3.0f * float(i);
    many.positions.insert(many.positions.end(),
                          {vec3(x, 0.0f, 0.0f), vec3(x, 0.0f, 1.0f), vec3(x + 1.0f, 0.0f, 0.0f)});
    many.indices.insert(many.indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
  }
  const Scene crowded = make_scene({many});
  message = error_of([&] { build_atlas(crowded, options_of(16, 0.0f)); });
  EXPECT_TRUE(contains(message, "30 charts")) << message;
  EXPECT_TRUE(contains(message, "16×16")) << message;
  // 16 of them do fit (4×4 cells of 3 + 1 padding = 16 = 14 + 2 padding).
  many.indices.resize(16 * 3);
  const Scene sixteen = make_scene({many});
  const AtlasOptions options = options_of(16, 0.0f);
  check_atlas(sixteen, build_atlas(sixteen, options), options);
}

TEST(Atlas, MalformedScenesAreErrors) {
  Scene scene = make_scene({split_grid(1)});
  scene.meshes[0].indices[4] = 99;
  std::string message = error_of([&] { build_atlas(scene, options_of(64, 0.0f)); });
  EXPECT_TRUE(contains(message, "grid")) << message;
  EXPECT_TRUE(contains(message, "99")) << message;

  scene = make_scene({split_grid(1)});
  scene.instances[0].transform[0][0] = NAN;
  message = error_of([&] { build_atlas(scene, options_of(64, 0.0f)); });
  EXPECT_TRUE(contains(message, "non-finite")) << message;

  scene = make_scene({split_grid(1)});
  scene.instances[0].mesh = 3;
  message = error_of([&] { build_atlas(scene, options_of(64, 0.0f)); });
  EXPECT_TRUE(contains(message, "instance0")) << message;
}

// A mesh no instance uses takes no atlas space and still gets a layout apply_atlas accepts.
TEST(Atlas, MeshWithoutInstance) {
  Scene scene = make_scene({split_grid(1), split_grid(3)});
  scene.instances.pop_back();
  const AtlasOptions options = options_of(64, 0.0f);
  const Atlas atlas = build_atlas(scene, options);
  EXPECT_EQ(atlas.chart_count, 1);
  for (uint32_t c : atlas.meshes[1].triangle_chart) EXPECT_EQ(c, kNoChart);
  check_atlas(scene, atlas, options);
  apply_atlas(scene, atlas);
  EXPECT_EQ(scene.meshes[1].uv1.size(), scene.meshes[1].positions.size());
}

TEST(Atlas, Deterministic) {
  // atlas/README.md: the same scene and options give the same atlas whatever the thread
  // count (1, 2 and 4; on fewer cores, as many as there are). Meshes are charted in
  // parallel, so there are 24 of them, enough for every thread to get some.
  std::vector<Mesh> meshes;
  for (int i = 0; i < 8; ++i)
    for (Mesh m : {roof(30.0f + 5.0f * i), split_grid(5 + i), roof(60.0f, 3.0f, 2.0f)})
      meshes.push_back(std::move(m));
  const Scene scene = make_scene(std::move(meshes));
  const AtlasOptions options = options_of(512, 0.0f);
  const auto build = [&](int threads) {
    ThreadLimit limit(threads);
    return build_atlas(scene, options);
  };
  const Atlas a = build(1);
  for (const int threads : {1, 2, 4}) {
    const Atlas b = build(threads);
    EXPECT_EQ(a.texel_size, b.texel_size) << threads << " threads";
    ASSERT_EQ(a.charts.size(), b.charts.size()) << threads << " threads";
    for (size_t c = 0; c < a.charts.size(); ++c) {
      EXPECT_EQ(a.charts[c].x, b.charts[c].x) << threads << " threads";
      EXPECT_EQ(a.charts[c].y, b.charts[c].y) << threads << " threads";
    }
    for (size_t m = 0; m < a.meshes.size(); ++m) {
      EXPECT_EQ(a.meshes[m].uv1, b.meshes[m].uv1) << threads << " threads";
      EXPECT_EQ(a.meshes[m].indices, b.meshes[m].indices) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace illum::atlas
