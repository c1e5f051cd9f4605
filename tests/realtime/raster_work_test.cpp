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

}  // namespace
}  // namespace illum::realtime
