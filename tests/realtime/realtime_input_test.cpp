// Bad input to the real-time renderer, built in code so it reaches the renderer without a
// scene loader's checks: each case must throw illum::Error naming what is wrong, before
// any GPU work (no validation message), and a refused change must leave the renderer as
// it was.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfinity = std::numeric_limits<float>::infinity();

class RealtimeInput : public test::ValidatedVulkanTest {};

RenderSettings small() {
  RenderSettings o;
  o.width = o.height = 16;
  o.set("map.resolution", 16);
  return o;
}

// `make` must throw illum::Error whose message contains `needle`.
void expect_refused(const std::function<void()>& make, const std::string& needle,
                    const std::string& label) {
  try {
    make();
    ADD_FAILURE() << label << ": accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << label << ": '" << e.what() << "' does not name " << needle;
  }
}

void expect_scene_refused(const Scene& scene, const std::string& needle, const std::string& label,
                          const RenderSettings& o = small()) {
  expect_refused([&] { Renderer r(context(), scene, o); }, needle, label);
}

TEST_F(RealtimeInput, OptionsOutOfRange) {
  const Scene scene = test::cornell_point_light();
  struct Case {
    const char* needle;
    std::function<void(RenderSettings&)> set;
  };
  // Every value outside its declared range is refused where it is set (RenderSettings checks
  // against the declaration), the size and the light index where the renderer starts.
  const Case cases[] = {
      {"width", [](RenderSettings& o) { o.width = 0; }},
      {"height", [](RenderSettings& o) { o.height = 0; }},
      {"width", [](RenderSettings& o) { o.width = -3; }},
      {"height", [](RenderSettings& o) { o.height = 1 << 20; }},
      {"map.resolution", [](RenderSettings& o) { o.set("map.resolution", 0); }},
      {"map.pcf_taps", [](RenderSettings& o) { o.set("map.pcf_taps", 0); }},
      {"map.pcf_radius", [](RenderSettings& o) { o.set("map.pcf_radius", kNaN); }},
      {"map.bias", [](RenderSettings& o) { o.set("map.bias", -1.0f); }},
      {"tonemap.exposure", [](RenderSettings& o) { o.set("tonemap.exposure", kNaN); }},
      {"tonemap.exposure", [](RenderSettings& o) { o.set("tonemap.exposure", kInfinity); }},
      {"bloom.strength", [](RenderSettings& o) { o.set("bloom.strength", -1.0f); }},
      {"lighting.ambient", [](RenderSettings& o) { o.set("lighting.ambient", Color(kNaN, 0, 0)); }},
      {"lighting.ambient", [](RenderSettings& o) { o.set("lighting.ambient", Color(-1.0f)); }},
      {"single_light", [](RenderSettings& o) { o.set("lighting.single_light", 1); }},  // one light
      {"single_light", [](RenderSettings& o) { o.set("lighting.single_light", -2); }},
      {"frame pipeline", [](RenderSettings& o) { o.pipeline = "raytraced"; }},
      {"shadow method", [](RenderSettings& o) { o.shadows = "soft"; }},
      {"add-on", [](RenderSettings& o) { o.add_ons.insert("sparkles"); }},
  };
  for (const Case& c : cases)
    expect_refused(
        [&] {
          RenderSettings o = small();
          c.set(o);
          Renderer r(context(), scene, o);
        },
        c.needle, c.needle);
  // Parameters from --param: the same ranges, and the origin is named.
  RenderSettings s;
  expect_refused([&] { s.set_param("map.resolution", nlohmann::json(0)); }, "--param", "set_param");
}

TEST_F(RealtimeInput, LightsWithNonFiniteOrNegativeValues) {
  struct Case {
    const char* label;
    const char* needle;
    std::function<void(Light&)> set;
  };
  const Case cases[] = {
      {"NaN position", "position", [](Light& l) { l.position.y = kNaN; }},
      {"Inf position", "position", [](Light& l) { l.position.x = kInfinity; }},
      {"NaN intensity", "intensity", [](Light& l) { l.intensity.g = kNaN; }},
      {"Inf intensity", "intensity", [](Light& l) { l.intensity = Color(kInfinity); }},
      {"negative intensity (a negative flux)", "intensity",
       [](Light& l) { l.intensity = Color(-1.0f); }},
      {"negative range", "range", [](Light& l) { l.range = -0.5f; }},
      {"NaN range", "range", [](Light& l) { l.range = kNaN; }},
      {"zero spot direction", "direction",
       [](Light& l) {
         l.type = LightType::kSpot;
         l.direction = vec3(0.0f);
       }},
      {"NaN spot direction", "direction",
       [](Light& l) {
         l.type = LightType::kSpot;
         l.direction = vec3(kNaN, -1.0f, 0.0f);
       }},
      {"spot cone of 0", "cone",
       [](Light& l) {
         l.type = LightType::kSpot;
         l.cone_half_angle = 0.0f;
       }},
      {"spot cone past 90°", "cone",
       [](Light& l) {
         l.type = LightType::kSpot;
         l.cone_half_angle = radians(120.0f);
       }},
      {"Inf sun irradiance", "irradiance",
       [](Light& l) {
         l.type = LightType::kDirectional;
         l.irradiance = Color(1.0f, kInfinity, 1.0f);
       }},
      {"negative sun irradiance", "irradiance",
       [](Light& l) {
         l.type = LightType::kDirectional;
         l.irradiance = Color(-2.0f);
       }},
      {"NaN sun direction", "direction",
       [](Light& l) {
         l.type = LightType::kDirectional;
         l.irradiance = Color(1.0f);
         l.direction = vec3(0.0f, kNaN, 0.0f);
       }},
  };
  for (const Case& c : cases) {
    Scene scene = test::cornell_point_light();
    scene.lights[0].name = "lamp";
    c.set(scene.lights[0]);
    expect_scene_refused(scene, c.needle, c.label);
    expect_scene_refused(scene, "lamp", std::string(c.label) + " (names the light)");
  }

  // The same through update_lights: refused, and the renderer keeps its lights.
  const Scene scene = test::cornell_point_light();
  Renderer renderer(context(), scene, small());
  renderer.render(*scene.camera);
  const Image before = renderer.hdr();
  std::vector<Light> bad = scene.lights;
  bad[0].position.z = kNaN;
  expect_refused([&] { renderer.update_lights(bad); }, "position", "update_lights");
  renderer.render(*scene.camera);
  EXPECT_EQ(renderer.hdr().data(), before.data()) << "a refused update changed the frame";
}

// Emissive instances become real-time lights through their area: one with none is refused,
// as is an area light naming an instance that does not exist.
TEST_F(RealtimeInput, ZeroAreaAndMissingEmitters) {
  Scene scene = test::cornell_point_light();
  Material lamp;
  lamp.emission = Color(10.0f);
  scene.materials.push_back(lamp);
  const int material = static_cast<int>(scene.materials.size() - 1);
  // Four points on one line: two triangles of zero area.
  test::add_quad(scene, {0.4f, 0.99f, 0.5f}, {0.5f, 0.99f, 0.5f}, {0.6f, 0.99f, 0.5f},
                 {0.45f, 0.99f, 0.5f}, material);
  scene.meshes.back().normals.assign(4, vec3(0, -1, 0));  // add_quad's cross product is NaN
  Light area;
  area.type = LightType::kArea;
  area.name = "flat lamp";
  area.instance = static_cast<int>(scene.instances.size() - 1);
  scene.lights.push_back(area);
  expect_scene_refused(scene, "zero area", "zero-area emitter");
  expect_scene_refused(scene, "flat lamp", "zero-area emitter (names the light)");
  scene.lights.back().instance = 99;
  expect_scene_refused(scene, "instance 99", "area light without its instance");
}

TEST_F(RealtimeInput, GeometryAndMaterials) {
  {
    Scene scene = test::cornell_point_light();
    scene.meshes[2].positions[1].x = kNaN;
    expect_scene_refused(scene, "mesh 2", "NaN vertex");
  }
  {
    Scene scene = test::cornell_point_light();
    scene.meshes[0].indices[4] = 1000;
    expect_scene_refused(scene, "vertex index 1000", "index past the vertices");
  }
  {
    Scene scene = test::cornell_point_light();
    scene.instances[3].mesh = 77;
    expect_scene_refused(scene, "instance 3", "instance of a missing mesh");
  }
  {
    Scene scene = test::cornell_point_light();
    scene.instances[1].transform[3][0] = kInfinity;
    expect_scene_refused(scene, "instance 1", "non-finite transform");
  }
  {
    Scene scene = test::cornell_point_light();
    scene.materials[1].albedo.r = kNaN;
    expect_scene_refused(scene, "material 1", "NaN albedo");
  }
  {
    Scene scene = test::cornell_point_light();
    scene.materials[0].emission = Color(-1.0f);
    expect_scene_refused(scene, "material 0", "negative emission");
  }
}

TEST_F(RealtimeInput, CamerasAndOptionChanges) {
  const Scene scene = test::cornell_point_light();
  Renderer renderer(context(), scene, small());
  Camera nan_position = *scene.camera;
  nan_position.position.x = kNaN;
  expect_refused([&] { renderer.render(nan_position); }, "camera", "NaN camera position");
  Camera no_direction = *scene.camera;
  no_direction.look_at = no_direction.position;
  expect_refused([&] { renderer.render(no_direction); }, "look_at", "look_at at the position");
  Camera along_up = *scene.camera;
  along_up.look_at = along_up.position + vec3(0, 1, 0);
  expect_refused([&] { renderer.render(along_up); }, "look_at", "looking along up");
  Camera flat = *scene.camera;
  flat.fov_y = 0.0f;
  expect_refused([&] { renderer.render(flat); }, "field of view", "zero field of view");

  // A refused change leaves the settings as they were.
  RenderSettings bad = renderer.settings();
  bad.width = 0;
  expect_refused([&] { renderer.configure(bad); }, "width", "configure with width 0");
  EXPECT_EQ(renderer.settings(), small());
  bad = renderer.settings();
  bad.set("lighting.single_light", 3);
  expect_refused([&] { renderer.configure(bad); }, "single_light", "configure: no light 3");
  EXPECT_EQ(renderer.settings(), small());
  renderer.render(*scene.camera);  // still renders
}

}  // namespace
}  // namespace illum::realtime
