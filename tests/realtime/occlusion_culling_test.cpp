// Two-phase occlusion culling of clusters (realtime/occlusion_culling.h): the image is the
// unculled one, bit for bit, frame after frame with a moving camera — including a jump that
// shows clusters the previous frame found hidden (the second half must draw them) — in
// every frame pipeline with shadow maps (spot maps, cascades, cube faces); the clusters and
// triangles drawn behind a big occluder drop, counted on the GPU; the first frame draws all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "illum/realtime/renderer.h"
#include "illum/scene/load.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class OcclusionCulling : public test::ValidatedVulkanTest {};

RenderSettings settings(const std::string& pipeline, int width, int height, bool culling) {
  RenderSettings o;
  o.width = width;
  o.height = height;
  o.pipeline = pipeline;
  o.shadows = "map";
  o.set("scene_draw.occlusion_culling", culling);
  o.set("map.update_period", 1);  // every shadow view re-rendered (and culled) each frame
  return o;
}

Camera look(vec3 position, vec3 at, float fov_degrees) {
  Camera c;
  c.position = position;
  c.look_at = at;
  c.fov_y = radians(fov_degrees);
  return c;
}

// A wall at z = 0 hiding a 6 × 6 grid of blocks behind it (each block five quads: five
// clusters), lit by a point light in front (cube faces) and a spot light above.
Scene wall_and_blocks() {
  Scene s = test::cornell_point_light();
  s.name = "wall-and-blocks";
  s.meshes.clear();
  s.instances.clear();
  test::add_quad(s, {-3, 0, -8}, {-3, 0, 2}, {3, 0, 2}, {3, 0, -8}, 0);  // floor
  test::add_quad(s, {-2, 0, 0}, {2, 0, 0}, {2, 2, 0}, {-2, 2, 0}, 1);    // the wall
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i)
      test::add_block(s, {-1.5f + 0.6f * i, 0.3f, -1.0f - 0.8f * j}, {0.2f, 0.3f, 0.2f}, 0.2f * i,
                      2);
  s.lights[0].position = vec3(0.3f, 1.5f, 1.5f);
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(0.0f, 4.0f, -3.0f);
  spot.direction = vec3(0.0f, -1.0f, 0.0f);
  spot.cone_half_angle = radians(40.0f);
  spot.intensity = Color(20.0f);
  s.lights.push_back(spot);
  s.camera = look({0.0f, 1.0f, 3.0f}, {0.0f, 0.8f, -2.0f}, 45.0f);
  return s;
}

// Renders `cameras` in turn with culling on and off and expects identical images; returns
// the culled renderer's pass times of each frame.
std::vector<std::vector<gpu::PassTime>> expect_identical(const Scene& scene,
                                                         const std::string& pipeline,
                                                         const std::vector<Camera>& cameras,
                                                         int width, int height) {
  Renderer culled(context(), scene, settings(pipeline, width, height, true));
  Renderer plain(context(), scene, settings(pipeline, width, height, false));
  std::vector<std::vector<gpu::PassTime>> times;
  for (size_t f = 0; f < cameras.size(); ++f) {
    culled.render(cameras[f]);
    plain.render(cameras[f]);
    times.push_back(culled.pass_times());
    // The culled frame draws every fragment the unculled one keeps: identical bits.
    EXPECT_TRUE(test::identical(culled.hdr(), plain.hdr()))
        << scene.name << " " << pipeline << ": frame " << f << " differs from the unculled one";
  }
  return times;
}

// In front of the wall (the blocks hidden), then a jump over it (the blocks in view: the
// previous frame found them hidden, so only the second half draws them), back, and over it
// twice (hidden two frames ago, visible one frame ago: the first half must read last
// frame's flags, not the other buffer's).
std::vector<Camera> wall_path() {
  const Camera front = look({0.0f, 1.0f, 3.0f}, {0.0f, 0.8f, -2.0f}, 45.0f);
  const Camera over = look({0.0f, 5.0f, 2.0f}, {0.0f, 0.0f, -3.0f}, 50.0f);
  return {front, look({0.1f, 1.0f, 2.9f}, {0.0f, 0.8f, -2.0f}, 45.0f), over, front, over, over};
}

TEST_F(OcclusionCulling, BigOccluderDropsTheClustersDrawnAndTheImageStays) {
  const Scene scene = wall_and_blocks();
  const std::vector<Camera> path = wall_path();
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    const auto times = expect_identical(scene, pipeline, path, 64, 48);
    const std::string raster = pipeline == "visibility" ? "visibility" : "depth_prepass";
    std::vector<double> clusters, triangles, shadow_clusters;
    // The pyramid and the test are timed beside the pass they cull, in a scope of their own.
    for (const std::string& scope : {raster + ".occlusion", std::string("shadow_maps.occlusion")})
      EXPECT_TRUE(std::any_of(times[1].begin(), times[1].end(),
                              [&](const gpu::PassTime& t) { return t.name == scope; }))
          << scope << " is not timed";
    for (const auto& frame : times)
      for (const gpu::PassTime& t : frame) {
        if (t.name == raster && t.depth == 0) {
          clusters.push_back(t.clusters);
          triangles.push_back(t.triangles);
        }
        if (t.name == "shadow_maps" && t.depth == 0) shadow_clusters.push_back(t.clusters);
      }
    ASSERT_EQ(clusters.size(), path.size());
    std::printf("%s: %s clusters (triangles) drawn per frame:", pipeline.c_str(), raster.c_str());
    for (size_t f = 0; f < clusters.size(); ++f)
      std::printf(" %.0f (%.0f)", clusters[f], triangles[f]);
    std::printf("; shadow_maps clusters:");
    for (double c : shadow_clusters) std::printf(" %.0f", c);
    std::printf("\n");
    // 36 blocks × 5 quads behind the wall. The first frame has no history: it draws every
    // cluster in view (the floor, the wall, every block face in the frustum). The second,
    // a step aside, keeps only what shows: the floor, the wall, and no block.
    EXPECT_GE(clusters[0], 150.0) << "the first frame draws every cluster in view";
    EXPECT_LE(clusters[1], 10.0) << "behind the wall nothing is drawn";
    // Each cluster here is one quad: two triangles, counted on the GPU.
    EXPECT_EQ(triangles[1], 2.0 * clusters[1]);
    EXPECT_EQ(triangles[0], 2.0 * clusters[0]);
    // The point light's cube faces (in front of the wall) stop drawing the blocks too.
    ASSERT_EQ(shadow_clusters.size(), path.size());
    EXPECT_LT(shadow_clusters[1], 0.6 * shadow_clusters[0]) << "shadow views cull too";
    // Over the wall the blocks show: the second half draws them.
    EXPECT_GE(clusters[2], 100.0);
  }
}

TEST_F(OcclusionCulling, CornellImagesMatchUnculledWithAMovingCamera) {
  const Scene scene = test::cornell_point_light();
  std::vector<Camera> path;
  for (int f = 0; f < 3; ++f)
    path.push_back(look({0.5f + 0.1f * f, 0.5f, 2.2f - 0.2f * f}, {0.5f, 0.4f, 0.0f}, 40.0f));
  // Into the room behind the tall block, then back out: clusters hidden a frame ago show.
  path.push_back(look({0.3f, 0.3f, 0.7f}, {0.35f, 0.3f, 0.0f}, 60.0f));
  path.push_back(look({0.9f, 0.8f, 1.8f}, {0.2f, 0.2f, 0.2f}, 40.0f));
  for (const std::string pipeline : {"forward", "deferred", "visibility"})
    expect_identical(scene, pipeline, path, 64, 64);
}

TEST_F(OcclusionCulling, SibenikImagesMatchUnculledWithAMovingCamera) {
  const Scene scene = load_scene("sibenik");
  const Camera start = *scene.camera;
  const vec3 forward = glm::normalize(start.look_at - start.position);
  std::vector<Camera> path;
  for (int f = 0; f < 2; ++f) {
    Camera c = start;
    c.position += forward * (1.5f * f);
    c.look_at += forward * (1.5f * f);
    path.push_back(c);
  }
  Camera back = start;  // a jump: turned round
  back.look_at = start.position - forward;
  path.push_back(back);
  path.push_back(start);
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    const auto times = expect_identical(scene, pipeline, path, 96, 64);
    const std::string raster = pipeline == "visibility" ? "visibility" : "depth_prepass";
    for (size_t f = 0; f < times.size(); ++f)
      for (const gpu::PassTime& t : times[f])
        if (t.depth == 0 && (t.name == raster || t.name == "shadow_maps" || t.name == "cascades"))
          std::printf("sibenik %s frame %zu: %s %.0f clusters, %.0f triangles\n", pipeline.c_str(),
                      f, t.name.c_str(), t.clusters, t.triangles);
  }
}

}  // namespace
}  // namespace illum::realtime
