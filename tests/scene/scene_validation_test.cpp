// The value rules every format shares (scene/scene_validation.h), on scenes built in code:
// finalize_scene accepts a valid scene, and refuses each broken value with one line naming the
// origin and the element. The loaders' own tests (load_errors_test, gltf_errors_test) show the
// same rules reached from MTL, scene files and glTF.
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/scene/mesh_processing.h"
#include "test_util.h"

namespace illum {
namespace {

using test::contains;
using test::error_of;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfinity = std::numeric_limits<float>::infinity();

Scene valid_scene() {
  Scene s;
  s.materials.resize(1);
  s.materials[0].name = "m";
  Mesh tri;
  tri.name = "tri";
  tri.positions = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};
  tri.indices = {0, 1, 2};
  s.meshes = {tri};
  s.instances = {Instance{"i", 0, mat4(1.0f)}};
  Light point;
  point.name = "p";
  point.position = vec3(0, 2, 0);
  point.intensity = Color(1.0f);
  Light spot = point;
  spot.name = "s";
  spot.type = LightType::kSpot;
  spot.direction = vec3(0, -1, 0);
  Light sky;
  sky.name = "sky";
  sky.type = LightType::kEnvironment;
  s.lights = {point, spot, sky};
  Camera c;
  c.position = vec3(0, 0, 5);
  c.look_at = vec3(0);
  c.up = vec3(0, 1, 0);
  c.fov_y = 0.8f;
  s.camera = c;
  Environment e;
  e.constant = Color(0.1f);
  s.environment = e;
  return s;
}

TEST(SceneValidation, ValidSceneFinalizes) {
  Scene s = valid_scene();
  EXPECT_NO_THROW(finalize_scene(s, "x.obj"));
}

TEST(SceneValidation, EveryRuleRefusesItsValue) {
  struct Case {
    const char* name;
    std::function<void(Scene&)> mutate;
    std::string expect;
  };
  auto material = [](Scene& s) -> Material& { return s.materials[0]; };
  const std::vector<Case> cases = {
      {"albedo_negative", [&](Scene& s) { material(s).albedo.g = -0.1f; },
       "x.obj: material 0 'm' albedo = (0.8, -0.1, 0.8) is negative"},
      {"albedo_above_one", [&](Scene& s) { material(s).albedo.r = 1.1f; },
       "material 0 'm' albedo = (1.1, 0.8, 0.8) exceeds 1"},
      {"specular_nan", [&](Scene& s) { material(s).specular.b = kNaN; },
       "material 0 'm' specular = (0, 0, nan) is not finite"},
      {"transmittance_above_one", [&](Scene& s) { material(s).transmittance = Color(2.0f); },
       "material 0 'm' transmittance = (2, 2, 2) exceeds 1"},
      {"emission_negative", [&](Scene& s) { material(s).emission.r = -1.0f; },
       "material 0 'm' emission = (-1, 0, 0) is negative"},
      {"emission_infinite", [&](Scene& s) { material(s).emission.r = kInfinity; },
       "material 0 'm' emission = (inf, 0, 0) is not finite"},
      {"eta_negative", [&](Scene& s) { material(s).eta.r = -0.2f; }, "material 0 'm' eta"},
      {"k_negative", [&](Scene& s) { material(s).k.g = -1.0f; }, "material 0 'm' k"},
      {"exponent", [&](Scene& s) { material(s).exponent = -1.0f; },
       "material 0 'm' exponent = -1 is outside [0, 1000000]"},
      {"roughness", [&](Scene& s) { material(s).roughness = 1.5f; },
       "material 0 'm' roughness = 1.5 is outside [0, 1]"},
      {"ior", [&](Scene& s) { material(s).ior = 0.5f; },
       "material 0 'm' ior = 0.5 is outside [1, 10]"},
      {"opacity", [&](Scene& s) { material(s).opacity = -0.5f; },
       "material 0 'm' opacity = -0.5 is outside [0, 1]"},
      {"normal_scale", [&](Scene& s) { material(s).normal_scale = kNaN; },
       "material 0 'm' normal_scale = nan is not finite"},
      {"texture", [&](Scene& s) { material(s).albedo_texture = 3; },
       "material 0 'm' albedo_texture refers to texture 3, but there are 0 textures"},
      {"light_position", [](Scene& s) { s.lights[0].position.x = kNaN; },
       "x.obj: light 0 'p' position = (nan, 2, 0) is not finite"},
      {"light_intensity", [](Scene& s) { s.lights[0].intensity.b = -1.0f; },
       "light 0 'p' intensity = (1, 1, -1) is negative"},
      {"light_range", [](Scene& s) { s.lights[0].range = -1.0f; },
       "light 0 'p' range = -1 must not be negative"},
      {"spot_direction", [](Scene& s) { s.lights[1].direction = vec3(0.0f); },
       "light 1 's' direction is a zero vector"},
      {"spot_cone", [](Scene& s) { s.lights[1].cone_half_angle = 2.0f; },
       "light 1 's' cone half-angle 2 rad is outside (0, π/2]"},
      {"directional_irradiance",
       [](Scene& s) {
         s.lights[1].type = LightType::kDirectional;
         s.lights[1].irradiance = Color(kInfinity);
       },
       "light 1 's' irradiance = (inf, inf, inf) is not finite"},
      {"area_instance",
       [](Scene& s) {
         s.lights[0].type = LightType::kArea;
         s.lights[0].instance = 5;
       },
       "light 0 'p' refers to instance 5, but there are 1 instances"},
      {"environment_light_alone", [](Scene& s) { s.environment.reset(); },
       "light 2 'sky' is an environment light, but the scene has no environment"},
      {"camera_fov", [](Scene& s) { s.camera->fov_y = 0.0f; },
       "x.obj: camera vertical field of view 0 rad is outside (0, π)"},
      {"camera_collapsed", [](Scene& s) { s.camera->look_at = s.camera->position; },
       "camera: position, look_at and up do not span a view"},
      {"camera_up_along_view", [](Scene& s) { s.camera->up = vec3(0, 0, -2); },
       "camera: position, look_at and up do not span a view"},
      {"camera_infinite", [](Scene& s) { s.camera->position.y = kInfinity; },
       "camera position = (0, inf, 5) is not finite"},
      {"environment_scale", [](Scene& s) { s.environment->scale = -1.0f; },
       "x.obj: environment scale = -1 must not be negative"},
      {"environment_rotation", [](Scene& s) { s.environment->rotation_y = kNaN; },
       "environment rotation = nan is not finite"},
      {"environment_constant", [](Scene& s) { s.environment->constant.g = -0.1f; },
       "environment constant = (0.1, -0.1, 0.1) is negative"},
      {"ambient", [](Scene& s) { s.settings.ambient.r = -0.1f; },
       "x.obj: settings ambient = (-0.1, 0, 0) is negative"},
      {"instance_singular", [](Scene& s) { s.instances[0].transform[1] = vec4(0.0f); },
       "x.obj: instance 0 'i' has a singular transform"},
      {"instance_projective", [](Scene& s) { s.instances[0].transform[2].w = 0.5f; },
       "instance 0 'i' has a projective transform"},
      {"instance_nan", [](Scene& s) { s.instances[0].transform[3].x = kNaN; },
       "instance 0 'i' has a non-finite transform"},
      {"instance_mesh", [](Scene& s) { s.instances[0].mesh = 7; },
       "instance 0 'i' refers to mesh 7, but there are 1 meshes"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Scene s = valid_scene();
    c.mutate(s);
    const std::string message = error_of([&] { finalize_scene(s, "x.obj"); });
    EXPECT_TRUE(contains(message, c.expect)) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace illum
