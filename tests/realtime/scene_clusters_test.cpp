// Scene clusters (realtime/gpu_scene.h): each view draws only the clusters its clip volume
// can reach, front to back where it asks, and the visibility buffer's triangle ids survive
// the reordering (a cluster's first triangle goes to the shader as the draw's first instance).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <numeric>
#include <random>

#include <meshoptimizer.h>

#include "illum/core/color.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/scene_draw.h"
#include "illum/scene/load.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class SceneClusters : public test::ValidatedVulkanTest {};

// The Cornell floor as an n × n grid of quads, gently rippled (so every triangle has its own
// plane and normals: a wrong triangle id in the visibility buffer rebuilds another surface),
// its triangles stored in a shuffled order so the clustering moves nearly every one.
Scene cornell_with_fine_floor(int n) {
  Scene s = test::cornell_point_light();
  Mesh& floor = s.meshes[0];
  floor.positions.clear();
  floor.normals.clear();
  floor.indices.clear();
  const float amp = 0.02f, k = 3.0f * kPi;  // ripple amplitude (m) and wave number (1/m)
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / n, z = float(j) / n;
      floor.positions.push_back(vec3(x, amp * std::sin(k * x) * std::cos(k * z), z));
      floor.normals.push_back(
          glm::normalize(vec3(-amp * k * std::cos(k * x) * std::cos(k * z), 1.0f,
                              amp * k * std::sin(k * x) * std::sin(k * z))));
    }
  std::vector<std::array<uint32_t, 3>> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      tris.push_back({a, c, d});
      tris.push_back({a, d, b});
    }
  std::mt19937 rng(7);
  std::shuffle(tris.begin(), tris.end(), rng);
  for (const auto& t : tris) floor.indices.insert(floor.indices.end(), t.begin(), t.end());
  return s;
}

TEST_F(SceneClusters, EveryTriangleInOneCompactCluster) {
  const int n = 48;  // 4608 floor triangles: 9 clusters
  const Scene scene = cornell_with_fine_floor(n);
  const GpuScene gpu(context(), scene);
  const DrawItem& floor = gpu.draws()[0];
  ASSERT_EQ(floor.mesh, 0u);
  const uint32_t triangles = static_cast<uint32_t>(scene.meshes[0].indices.size() / 3);
  EXPECT_EQ(floor.cluster_count, (triangles + kClusterTriangles - 1) / kClusterTriangles);
  uint32_t covered = 0;
  double area = 0.0;
  for (uint32_t c = floor.first_cluster; c < floor.first_cluster + floor.cluster_count; ++c) {
    const Cluster& k = gpu.clusters()[c];
    EXPECT_EQ(k.draw, 0u);
    EXPECT_EQ(k.first_index, gpu.meshes()[0].first_index + 3 * k.first_triangle);
    EXPECT_EQ(k.first_triangle, covered) << "clusters run back to back through the mesh";
    covered += k.index_count / 3;
    area += double(k.bounds.extent().x) * k.bounds.extent().z;
  }
  EXPECT_EQ(covered, triangles);
  // Compact: the clusters' footprints add up to little more than the floor (1 m²); the
  // shuffled order taken in runs of kClusterTriangles would give each run the whole floor (9 m²).
  std::printf("floor: %u clusters, footprints %.3f m²\n", floor.cluster_count, area);
  EXPECT_LT(area, 1.5);
}

// Within each cluster the triangles go in an order for vertex reuse: the average cache miss
// ratio (vertex shader runs a triangle) of meshoptimizer's FIFO-16 model stays below 1 in
// every cluster of a regular grid — a 256-triangle patch of it has about 150 vertices, so
// about 0.6 is the floor — where the spatial split alone leaves the shuffled order's ≈ 2.
// Every triangle survives with its winding (a rotation of its three indices at most).
TEST(SceneClustersOrder, TrianglesInAClusterAreOrderedForVertexReuse) {
  const Scene scene = cornell_with_fine_floor(48);
  const Mesh& floor = scene.meshes[0];
  const std::vector<uint32_t> ordered = clustered_indices(floor, kClusterTriangles).vertices;
  ASSERT_EQ(ordered.size(), floor.indices.size());
  auto canonical = [](const uint32_t* t) {  // the rotation starting at the smallest index
    const int k = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
    return std::array<uint32_t, 3>{t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
  };
  std::vector<std::array<uint32_t, 3>> before, after;
  for (size_t i = 0; i < ordered.size(); i += 3) {
    before.push_back(canonical(&floor.indices[i]));
    after.push_back(canonical(&ordered[i]));
  }
  std::sort(before.begin(), before.end());
  std::sort(after.begin(), after.end());
  EXPECT_EQ(before, after) << "a triangle lost, duplicated or turned over";
  const size_t run = 3 * size_t(kClusterTriangles);
  double worst = 0.0;
  for (size_t first = 0; first < ordered.size(); first += run) {
    const size_t count = std::min(run, ordered.size() - first);
    const meshopt_VertexCacheStatistics s =
        meshopt_analyzeVertexCache(ordered.data() + first, count, floor.positions.size(), 16, 0, 0);
    worst = std::max(worst, double(s.acmr));
  }
  std::printf("worst cluster: %.3f vertices a triangle (FIFO of 16)\n", worst);
  EXPECT_LT(worst, 1.0);
}

// Depth-like passes draw the same triangles on welded positions: the floor's grid with every
// triangle on three vertices of its own (split corners, as flat shading or texture seams
// leave them) — each welded corner holds the bit-identical position of its split one, the
// triangles keep their order, and the welded clusters run under 1 vertex a triangle in
// meshoptimizer's FIFO-16 model where the split ones must run 3.
TEST(SceneClustersOrder, DepthPassesDrawWeldedPositionsInTheSameOrder) {
  Scene scene = cornell_with_fine_floor(48);
  Mesh& floor = scene.meshes[0];
  Mesh split = floor;
  split.positions.clear();
  split.normals.clear();
  split.indices.clear();
  for (uint32_t i : floor.indices) {
    split.indices.push_back(static_cast<uint32_t>(split.positions.size()));
    split.positions.push_back(floor.positions[i]);
    split.normals.push_back(floor.normals[i]);
  }
  const ClusteredIndices ordered = clustered_indices(split, kClusterTriangles);
  ASSERT_EQ(ordered.vertices.size(), split.indices.size());
  ASSERT_EQ(ordered.positions.size(), split.indices.size());
  for (size_t i = 0; i < ordered.vertices.size(); ++i)
    ASSERT_EQ(split.positions[ordered.positions[i]], split.positions[ordered.vertices[i]])
        << "corner " << i << " welded to another position";
  const size_t run = 3 * size_t(kClusterTriangles);
  double worst = 0.0, split_best = 3.0;
  for (size_t first = 0; first < ordered.positions.size(); first += run) {
    const size_t count = std::min(run, ordered.positions.size() - first);
    worst =
        std::max(worst, double(meshopt_analyzeVertexCache(ordered.positions.data() + first, count,
                                                          split.positions.size(), 16, 0, 0)
                                   .acmr));
    split_best = std::min(split_best,
                          double(meshopt_analyzeVertexCache(ordered.vertices.data() + first, count,
                                                            split.positions.size(), 16, 0, 0)
                                     .acmr));
  }
  std::printf("welded: worst cluster %.3f vertices a triangle; split: best %.3f\n", worst,
              split_best);
  EXPECT_LT(worst, 1.0);
  EXPECT_EQ(split_best, 3.0);
}

// The cascades draw only the clusters that can cast into the texels their lookups read
// (SceneView::receivers, map.caster_culling): Sibenik from its camera, a step forward and
// turned round — every frame's HDR image holds the same bits as without the culling, with PCF
// and VSM at their defaults (where the culling drops clusters) and with coarse 32² cascades and
// an 8-texel PCF radius, which make the lookup's reach wide enough to matter (with no margin
// for it, that image changes).
TEST_F(SceneClusters, CascadeCasterCullingLeavesEveryPixelAsItWas) {
  const Scene scene = load_scene("sibenik");
  const Camera start = *scene.camera;
  Camera ahead = start, back = start;
  const vec3 forward = glm::normalize(start.look_at - start.position);
  ahead.position += 2.0f * forward;
  ahead.look_at += 2.0f * forward;
  back.look_at = start.position - forward;
  struct Case {
    std::string method;
    bool coarse;
  };
  for (const Case& k : {Case{"map", false}, Case{"vsm", false}, Case{"map", true}}) {
    auto renderer = [&](bool culling) {
      RenderSettings o;
      o.width = 96;
      o.height = 64;
      o.pipeline = "deferred";
      o.shadows = k.method;
      o.set(k.method + ".caster_culling", culling);
      if (k.coarse) {
        o.set("map.resolution", 32);
        o.set("map.pcf_radius", 8.0f);
      }
      return std::make_unique<Renderer>(context(), scene, o);
    };
    std::unique_ptr<Renderer> culled = renderer(true), plain = renderer(false);
    double drawn = 0.0, all = 0.0;
    for (const Camera& c : {start, ahead, back}) {
      culled->render(c);
      plain->render(c);
      EXPECT_TRUE(test::identical(culled->hdr(), plain->hdr()))
          << k.method << (k.coarse ? " (coarse)" : "") << ": a pixel moved";
      for (const gpu::PassTime& t : culled->pass_times())
        if (t.name == "cascades" && t.depth == 0) drawn += t.triangles;
      for (const gpu::PassTime& t : plain->pass_times())
        if (t.name == "cascades" && t.depth == 0) all += t.triangles;
    }
    std::printf("%s%s: cascades drew %.0f of %.0f triangles over 3 frames\n", k.method.c_str(),
                k.coarse ? " (coarse)" : "", drawn, all);
    if (!k.coarse) {
      EXPECT_LT(drawn, 0.95 * all) << "the culling dropped nothing";
    }
  }
}

// The PCF cascades in d16 (map.cascade_depth, the default) hold the depth the d32 ones hold
// to one step of 16 bits (1/65535 of the cascade's depth range: an orthographic depth is
// linear and a depth test keeps the nearest whichever the format), at every texel of every
// cascade of Sibenik's camera; the frame's image changes on few pixels.
TEST_F(SceneClusters, CascadesInD16HoldTheD32DepthToAStep) {
  const Scene scene = load_scene("sibenik");
  auto renderer = [&](const char* depth) {
    RenderSettings o;
    o.width = 96;
    o.height = 64;
    o.pipeline = "deferred";
    o.shadows = "map";
    o.set("map.cascade_depth", std::string(depth));
    auto r = std::make_unique<Renderer>(context(), scene, o);
    r->render(*scene.camera);
    return r;
  };
  std::unique_ptr<Renderer> d16 = renderer("d16"), d32 = renderer("d32");
  const double step = 1.0 / 65535.0;
  for (uint32_t layer = 0; layer < 4; ++layer) {
    const Image a = d16->read_resource("shadow.cascades", layer);
    const Image b = d32->read_resource("shadow.cascades", layer);
    ASSERT_EQ(a.pixel_count(), b.pixel_count());
    double worst = 0.0;
    size_t covered = 0;
    for (size_t i = 0; i < a.pixel_count(); ++i) {
      worst = std::max(worst, std::abs(double(a.data()[i]) - double(b.data()[i])));
      covered += b.data()[i] < 1.0f;
    }
    std::printf("cascade %u: %zu of %zu texels covered, d16 - d32 at most %.3f steps\n", layer,
                covered, a.pixel_count(), worst / step);
    EXPECT_GT(covered, a.pixel_count() / 10) << "cascade " << layer << " holds no casters";
    EXPECT_LE(worst, step * 1.001) << "cascade " << layer;
  }
  EXPECT_THROW(d16->read_resource("shadow.cascades", 4), Error) << "a layer past the last";
  EXPECT_THROW(d16->read_resource("no such image"), Error);
  const Image x = d16->hdr(), y = d32->hdr();
  size_t differ = 0;
  for (int j = 0; j < x.height(); ++j)
    for (int i = 0; i < x.width(); ++i)
      differ += std::abs(luminance(x.rgb(i, j)) - luminance(y.rgb(i, j))) >
                1e-3f * luminance(y.rgb(i, j)) + 1e-6f;
  std::printf("d16 and d32 cascades: %zu of %zu pixels differ\n", differ, x.pixel_count());
  EXPECT_LE(differ, x.pixel_count() / 1000);
}

TEST_F(SceneClusters, CullingKeepsEveryClusterTheViewCanSeeAndSortsFrontToBack) {
  const Scene scene = cornell_with_fine_floor(48);
  const GpuScene gpu(context(), scene);
  // Close to the floor's near-left corner: most of the room is outside the view.
  Camera cam;
  cam.position = vec3(0.2f, 0.25f, 1.3f);
  cam.look_at = vec3(0.1f, 0.0f, 0.8f);
  cam.fov_y = radians(35.0f);
  const mat4 clip = cam.projection_matrix(1.0f, 0.01f, 10.0f) * cam.view_matrix();
  const SceneView view = SceneView::camera(clip, /*front_to_back=*/true);
  const std::vector<uint32_t> drawn = visible_clusters(gpu, view);
  const std::vector<uint32_t> all = visible_clusters(gpu, SceneView{});
  ASSERT_EQ(all.size(), gpu.clusters().size());
  EXPECT_LT(drawn.size(), all.size() / 2) << "the view culls most clusters";
  // Every cluster with a vertex inside the clip volume is drawn.
  std::vector<uint8_t> is_drawn(gpu.clusters().size(), 0);
  for (uint32_t c : drawn) is_drawn[c] = 1;
  size_t needed = 0;
  for (uint32_t c = 0; c < gpu.clusters().size(); ++c) {
    const Cluster& k = gpu.clusters()[c];
    const DrawItem& d = gpu.draws()[k.draw];
    const Mesh& mesh = scene.meshes[d.mesh];
    // The cluster's triangles in the GPU order are the mesh's, reordered: test the vertices
    // inside its bounds (all of its own are).
    bool inside = false;
    for (const vec3& p : mesh.positions) {
      const vec3 w = vec3(d.transform * vec4(p, 1.0f));
      if (glm::any(glm::lessThan(w, k.bounds.min)) || glm::any(glm::greaterThan(w, k.bounds.max)))
        continue;
      const vec4 h = clip * vec4(w, 1.0f);
      inside |= std::abs(h.x) <= h.w && std::abs(h.y) <= h.w && h.z >= 0.0f && h.z <= h.w;
    }
    if (!inside) continue;
    ++needed;
    EXPECT_TRUE(is_drawn[c]) << "cluster " << c << " has a vertex in view but was culled";
  }
  EXPECT_GT(needed, 0u);
  // Front to back: the clip-space depth of the clusters' farthest corners never decreases.
  for (size_t i = 1; i < drawn.size(); ++i) {
    float a = -1e30f, b = -1e30f;
    for (int k = 0; k < 8; ++k) {
      auto corner = [&](const Bounds3& x) {
        return vec4((k & 1) ? x.max.x : x.min.x, (k & 2) ? x.max.y : x.min.y,
                    (k & 4) ? x.max.z : x.min.z, 1.0f);
      };
      a = std::max(a, (clip * corner(gpu.clusters()[drawn[i - 1]].bounds)).z);
      b = std::max(b, (clip * corner(gpu.clusters()[drawn[i]].bounds)).z);
    }
    EXPECT_LE(a, b) << i;
  }
  std::printf("view draws %zu of %zu clusters (%zu with a vertex in view)\n", drawn.size(),
              all.size(), needed);
}

// The visibility buffer against forward shading on the fine, shuffled floor seen in part
// (culling on), and the background around the box (the id target is not cleared: empty
// pixels are told by their depth): the same bound as VisibilityMatchesForwardAndDeferred (1 %
// for 99 % of the pixels off geometry edges, floor 1 % of the mean), no shadows so the two
// differ only by how they rebuild the surface.
TEST_F(SceneClusters, VisibilityIdsSurviveClusteringAndCulling) {
  Scene scene = cornell_with_fine_floor(48);
  Camera cam;
  cam.position = vec3(0.5f, 0.7f, 2.4f);
  cam.look_at = vec3(0.55f, 0.1f, 0.5f);
  cam.fov_y = radians(45.0f);
  scene.camera = cam;
  const int size = 96;
  auto render = [&](const std::string& pipeline) {
    RenderSettings o;
    o.width = o.height = size;
    o.pipeline = pipeline;
    o.shadows = "none";
    Renderer r(context(), scene, o);
    r.render(*scene.camera);
    return r.hdr();
  };
  const Image forward = render("forward");
  const Image visibility = render("visibility");
  const test::Reference ref = test::direct_lighting_reference(scene, size, size);
  const std::vector<uint8_t> edge = test::edge_mask(ref, size, size, 1);
  double mean = 0.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) mean += luminance(forward.rgb(x, y)) / (size * size);
  ASSERT_GT(mean, 0.0);
  size_t compared = 0, within = 0, floor_pixels = 0, background = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const size_t i = static_cast<size_t>(y) * size + x;
      if (edge[i]) continue;
      floor_pixels += ref.surface[i] == 0;
      background += ref.surface[i] < 0;
      const Color a = visibility.rgb(x, y), b = forward.rgb(x, y);
      bool ok = true;
      for (int k = 0; k < 3; ++k)
        ok &= std::abs(a[k] - b[k]) <= 0.01f * std::max(b[k], static_cast<float>(mean));
      ++compared;
      within += ok;
    }
  ASSERT_GT(floor_pixels, compared / 20) << "the floor shows";
  ASSERT_GT(background, compared / 20) << "the background shows around the box";
  const double fraction = double(within) / double(compared);
  std::printf(
      "visibility vs forward on a clustered floor: %.4f of %zu pixels within 1%% (%zu floor, "
      "%zu background)\n",
      fraction, compared, floor_pixels, background);
  EXPECT_GE(fraction, 0.99);
}

}  // namespace
}  // namespace illum::realtime
