// The work a counting frame measures (Renderer::measure_work): the 2×2 quads a scene pass
// shades (shaders/quad_count.frag), on a case counted by hand.
#include <gtest/gtest.h>

#include "illum/realtime/renderer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class RasterWorkTest : public test::ValidatedVulkanTest {};

// One square, larger than the view, faces a camera on its axis: its two triangles cover a
// square viewport of W × W pixels (W even), split along a screen diagonal. Every pixel is a
// passing sample once; every 2×2 quad is shaded once, except the W/2 quads the diagonal
// crosses — they hold pixels strictly on both sides (the pixels beside the diagonal lie
// 1/√2 pixel from it, whichever way the pixels on it are given), so both triangles shade
// them: W²/4 + W/2 quads.
TEST_F(RasterWorkTest, QuadsOfTwoTrianglesSplitAlongTheDiagonal) {
  if (!context().quad_counting() || !context().timestamps())
    GTEST_FAIL() << "the device cannot count quads (subgroup quad operations and fragment "
                    "stores) or time passes";
  Scene scene;
  scene.name = "one-square";
  scene.materials = {Material{}};
  test::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  Camera camera;
  camera.position = {0, 0, 5};
  camera.look_at = {0, 0, 0};
  scene.camera = camera;
  for (const int w : {64, 90}) {
    RenderSettings o;
    o.width = o.height = w;
    o.shadows = "none";
    Renderer renderer(context(), scene, o);
    int counted = 0;
    for (const gpu::PassTime& t : renderer.measure_work(camera)) {
      if (t.name != "depth_prepass" && t.name != "forward") continue;
      ++counted;
      EXPECT_EQ(t.quad_samples, static_cast<double>(w) * w) << t.name << " at " << w;
      EXPECT_EQ(t.quads, static_cast<double>(w) * w / 4 + w / 2) << t.name << " at " << w;
    }
    EXPECT_EQ(counted, 2) << "the forward pipeline's depth pre-pass and shading pass";
  }
}

// Depth-like passes draw welded positions (GpuScene::position_indices): a 32 × 32 grid of
// quads whose triangles each hold three vertices of their own (split corners, as flat
// shading leaves them) fills the view. The G-buffer pass, on the split vertices, must shade
// 3 vertices a triangle; the depth pre-pass before it, the same triangles on the welded
// corners, shares them — under 1.5 a triangle whatever the device's reuse window beyond one
// triangle (a grid has 0.5 vertices a triangle).
TEST_F(RasterWorkTest, DepthPrepassShadesWeldedVerticesOnce) {
  if (!context().pipeline_statistics())
    GTEST_FAIL() << "the device cannot count vertex shader invocations";
  Scene scene;
  scene.name = "split-grid";
  scene.materials = {Material{}};
  Mesh m;
  const int n = 32;
  auto corner = [&](int i, int j) { return vec3(float(i) / n - 0.5f, float(j) / n - 0.5f, 0.0f); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (const vec3 p : {corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j),
                           corner(i + 1, j + 1), corner(i, j + 1)}) {
        m.indices.push_back(static_cast<uint32_t>(m.positions.size()));
        m.positions.push_back(p);
        m.normals.push_back(vec3(0, 0, 1));
      }
  scene.meshes.push_back(m);
  scene.instances.push_back({"", 0, mat4(1.0f)});
  Camera camera;
  camera.position = {0, 0, 1.5f};
  camera.look_at = {0, 0, 0};
  scene.camera = camera;
  RenderSettings o;
  o.width = o.height = 64;
  o.pipeline = "deferred";
  o.shadows = "none";
  Renderer renderer(context(), scene, o);
  double prepass = -1.0, gbuffer = -1.0, triangles = 0.0;
  for (const gpu::PassTime& t : renderer.measure_work(camera)) {
    if (t.name == "depth_prepass") prepass = t.vertices / t.rasterized;
    if (t.name == "gbuffer") {
      gbuffer = t.vertices / t.rasterized;
      triangles = t.rasterized;
    }
  }
  std::printf("vertices a triangle: pre-pass %.3f, G-buffer %.3f (%g triangles)\n", prepass,
              gbuffer, triangles);
  EXPECT_EQ(triangles, 2.0 * n * n);
  EXPECT_EQ(gbuffer, 3.0);
  EXPECT_GT(prepass, 0.0);
  EXPECT_LT(prepass, 1.5);
}

}  // namespace
}  // namespace illum::realtime
