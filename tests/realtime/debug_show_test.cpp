// On the device, validation layers on: a change a technique raises re-runs exactly the
// passes whose schedules name it, at the next frame; `-p debug.show=RESOURCE` puts the
// resource's values into the output (colour as is, depth linearised, a layer of a cube
// array) and refuses an unknown name with the declared ones listed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 64;

class DebugShowTest : public test::ValidatedVulkanTest {};
class RaisedChangeTest : public test::ValidatedVulkanTest {};

// What the probe technique shares with the test: the change to raise at its next update(),
// and how often its on-geometry-change pass recorded.
Changes g_raise_next = 0;
int g_runs = 0;

class RaiseProbe final : public Technique {
 public:
  using Technique::Technique;
  void declare(FrameGraph& graph) override {
    ResourceDesc r;
    r.name = "raise_probe";
    r.kind = ResourceDesc::Kind::kBuffer;
    r.bytes = 16;
    graph.add_resource(r);
    PassDesc p;
    p.name = "raise_probe";
    p.technique = name();
    p.phase = Phase::kGeometry;
    p.schedule = Schedule::on_change(kGeometryChanged);
    p.accesses = {{"raise_probe", kStorageWrite, kComputeShader}};
    p.record = [](PassContext&) { ++g_runs; };
    graph.add_pass(std::move(p));
  }
  void update() override {
    if (g_raise_next) raise(g_raise_next);
    g_raise_next = 0;
  }
};

TEST_F(RaisedChangeTest, AnOnChangePassRerunsExactlyAfterTheRaise) {
  TechniqueDecl d;
  d.name = "raise_probe";
  d.kind = TechniqueKind::kAddOn;
  d.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<RaiseProbe>(ctx, *find_technique("raise_probe"));
  };
  TechniqueRegistration registration(d);
  const Scene scene = test::cornell_point_light();
  RenderSettings o;
  o.width = o.height = kSize;
  o.enable("raise_probe");
  g_runs = 0;
  g_raise_next = 0;
  {
    Renderer r(context(), scene, o);
    // Frame 0 runs every pass; then the pass waits for a geometry change. Another change
    // (lights) leaves it alone; a raised kGeometryChanged re-runs it once, at that frame.
    const Changes raises[] = {0,
                              0,
                              kLightsChanged,
                              kCameraChanged,
                              kGeometryChanged,
                              0,
                              0,
                              kGeometryChanged | kLightsChanged,
                              0};
    const int expected[] = {1, 1, 1, 1, 2, 2, 2, 3, 3};
    for (size_t f = 0; f < std::size(raises); ++f) {
      g_raise_next = raises[f];
      r.render(*scene.camera);
      EXPECT_EQ(g_runs, expected[f]) << "frame " << f;
    }
  }
}

RenderSettings showing(const std::string& what) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.shadows = "map";
  o.set_param("debug.show", what);
  return o;
}

// The 8-bit output holds sRGB codes: half a code at the top of the curve is 0.0045 in linear.
constexpr float kCode = 0.006f;

TEST_F(DebugShowTest, TheHdrTargetAsIs) {
  const Scene scene = test::cornell_point_light();
  Renderer r(context(), scene, showing("hdr"));
  r.render(*scene.camera);
  const Image hdr = r.hdr(), ldr = r.ldr();
  int lit = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        const float want = std::clamp(hdr.pixel(x, y)[c], 0.0f, 1.0f);
        ASSERT_NEAR(ldr.pixel(x, y)[c], want, kCode) << x << "," << y << " channel " << c;
        lit += c == 0 && want > 0.05f;
      }
  EXPECT_GT(lit, kSize * kSize / 4);  // the box is there, not a black frame
}

TEST_F(DebugShowTest, DepthLinearisedWithTheCameraPlanes) {
  const Scene scene = test::cornell_point_light();
  Renderer r(context(), scene, showing("depth"));
  r.render(*scene.camera);
  const Image depth = r.read_resource("depth");
  const Image ldr = r.ldr();
  // The renderer puts the near plane at 1e-3 of the far one (renderer.cpp, update_view): view
  // depth ÷ far = r / (1 − d (1 − r)).
  const float ratio = 1e-3f;
  float lo = 1.0f, hi = 0.0f;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float d = depth.pixel(x, y)[0];
      const float want = ratio / (1.0f - d * (1.0f - ratio));
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(ldr.pixel(x, y)[c], want, kCode) << x << "," << y;
      lo = std::min(lo, want);
      hi = std::max(hi, want);
    }
  EXPECT_GT(hi - lo, 0.1f);  // walls at several depths, not one grey
}

TEST_F(DebugShowTest, ALayerOfTheShadowCubes) {
  const Scene scene = test::cornell_point_light();
  RenderSettings o = showing("shadow.cubes:2");
  o.set("map.resolution", 128);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  const Image face = r.read_resource("shadow.cubes", 2);
  const Image ldr = r.ldr();
  // Nearest texel under each pixel centre; one channel as grey.
  int differ = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int tx = (2 * x + 1) * face.width() / (2 * kSize);
      const int ty = (2 * y + 1) * face.height() / (2 * kSize);
      const float want = std::clamp(face.pixel(tx, ty)[0], 0.0f, 1.0f);
      ASSERT_NEAR(ldr.pixel(x, y)[0], want, kCode) << x << "," << y;
      ASSERT_NEAR(ldr.pixel(x, y)[2], want, kCode) << x << "," << y;
      differ += std::abs(want - face.pixel(0, 0)[0]) > 0.02f;
    }
  EXPECT_GT(differ, 0);  // the face holds distances, not one value
}

// A slice of a 3-D image that keeps a history copy (the light_volume example): "NAME" and
// "NAME.previous" each show the copy the graph gives that name (they differ: a light changed
// between the two frames).
TEST_F(DebugShowTest, ASliceOfAVolumeAndItsPreviousCopy) {
  const Scene scene = test::cornell_point_light();
  Image shown[2];
  int k = 0;
  for (const std::string name : {"light_volume", "light_volume.previous"}) {
    RenderSettings o = showing(name + ":5");
    o.enable("light_volume");
    o.set("light_volume.cells", 8);
    o.set("light_volume.blend", 0.5f);
    Renderer r(context(), scene, o);
    r.render(*scene.camera);
    // A brighter light: the blend leaves the two copies different.
    std::vector<Light> lights = realtime_lights(scene);
    lights[0].intensity = lights[0].intensity * 3.0f;
    r.update_lights(lights);
    r.render(*scene.camera);
    const Image slice = r.read_resource(name, 5);
    const Image ldr = r.ldr();
    shown[k++] = ldr;
    int inside = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const int tx = (2 * x + 1) * slice.width() / (2 * kSize);
        const int ty = (2 * y + 1) * slice.height() / (2 * kSize);
        for (int c = 0; c < 3; ++c) {
          const float want = std::clamp(slice.pixel(tx, ty)[c], 0.0f, 1.0f);
          ASSERT_NEAR(ldr.pixel(x, y)[c], want, kCode) << name << " " << x << "," << y;
          inside += want > 0.02f && want < 0.98f;
        }
      }
    EXPECT_GT(inside, 0) << name << ": every texel clamped, the comparison shows nothing";
  }
  // The two names show different images.
  EXPECT_FALSE(test::identical(shown[0], shown[1]));
}

// The visibility buffer's ids as hashed colours: each pixel's colour is the documented hash
// (PCG, shaders/debug_show.glsl) of the id under it.
TEST_F(DebugShowTest, UnsignedIdsAsHashedColours) {
  const Scene scene = test::cornell_point_light();
  RenderSettings o = showing("visibility.ids");
  o.pipeline = "visibility";
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  const Image ids = r.read_resource("visibility.ids");
  const Image ldr = r.ldr();
  std::set<uint32_t> seen;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      uint32_t id = 0;
      std::memcpy(&id, ids.pixel(x, y), sizeof(id));  // the texel's bits, as read back
      seen.insert(id);
      const uint32_t s = id * 747796405u + 2891336453u;
      uint32_t w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
      w = (w >> 22u) ^ w;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(ldr.pixel(x, y)[c], static_cast<float>((w >> (8 * c)) & 255u) / 255.0f, kCode)
            << x << "," << y << " id " << id;
    }
  EXPECT_GT(seen.size(), 10u);  // many triangles, not one colour
}

TEST_F(DebugShowTest, AnUnknownNameListsTheDeclaredOnes) {
  const Scene scene = test::cornell_point_light();
  for (const std::string what : {"nosuch", "hdr:1", "depth:mip=3", "luminance"}) {
    std::string message;
    try {
      Renderer r(context(), scene, showing(what));
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find("-p debug.show=" + what + ": "), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    if (what == "nosuch") {
      EXPECT_NE(message.find("no image 'nosuch'"), std::string::npos) << message;
      for (const char* name : {"hdr", "depth", "ldr", "shadow.cubes"})
        EXPECT_NE(message.find(name), std::string::npos) << name << " not listed: " << message;
    }
  }
}

}  // namespace
}  // namespace illum::realtime
