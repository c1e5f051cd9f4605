// --sun and --sky as the scene layer reads them (scene/lighting_overrides.h): the values
// each accepts, what each adds, and the one-line refusals.
#include <functional>

#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/scene/lighting_overrides.h"

namespace illum {
namespace {

std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(LightingOverrides, SunTravelsAlongItsDirectionWithItsIrradiance) {
  Scene scene;
  add_sun(scene, "0,-2,0");
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light& sun = scene.lights[0];
  EXPECT_EQ(sun.type, LightType::kDirectional);
  EXPECT_EQ(sun.direction, vec3(0.0f, -1.0f, 0.0f)) << "normalised, the way the light travels";
  EXPECT_EQ(sun.irradiance, Color(kPi)) << "default π: white Lambert facing it shows 1";
  add_sun(scene, "1,-1,0,5.5");
  EXPECT_EQ(scene.lights[1].irradiance, Color(5.5f));
  EXPECT_TRUE(has_any_light(scene));
}

TEST(LightingOverrides, SkyIsAUniformRadianceOrAMap) {
  Scene scene;
  EXPECT_FALSE(has_any_light(scene));
  set_sky(scene, "0.2,0.3,0.4");
  ASSERT_TRUE(scene.environment.has_value());
  EXPECT_EQ(scene.environment->constant, Color(0.2f, 0.3f, 0.4f));
  EXPECT_TRUE(scene.environment->radiance.empty());
  set_sky(scene, "2");  // replaces the first: one environment, one environment light
  EXPECT_EQ(scene.environment->constant, Color(2.0f));
  int environment_lights = 0;
  for (const Light& l : scene.lights) environment_lights += l.type == LightType::kEnvironment;
  EXPECT_EQ(environment_lights, 1);
  EXPECT_TRUE(has_any_light(scene));
}

TEST(LightingOverrides, BadValuesAreOneLineNamingTheOption) {
  Scene scene;
  for (const char* bad :
       {"", "1,2", "1,2,3,4,5", "0,0,0", "nan,-1,0", "0,-1,0,-1", "a,b,c", "0,-1,0,", "0,,-1"})
    EXPECT_NE(refusal([&] { add_sun(scene, bad); }).find("--sun"), std::string::npos) << bad;
  for (const char* bad : {"1,2", "-1", "0.5,-0.1,0.2", "inf"})
    EXPECT_NE(refusal([&] { set_sky(scene, bad); }).find("--sky"), std::string::npos) << bad;
  EXPECT_NE(refusal([&] { set_sky(scene, "no-such-sky.hdr"); }).find("no-such-sky.hdr"),
            std::string::npos);
  EXPECT_TRUE(scene.lights.empty()) << "a refused value adds nothing";
}

TEST(LightingOverrides, UnlitMessageNamesTheRemedy) {
  Scene scene;
  scene.name = "bunny";
  const std::string m = unlit_scene_message(scene, "bake");
  for (const char* part : {"bake", "'bunny'", "has no light", "--sun", "--sky"})
    EXPECT_NE(m.find(part), std::string::npos) << m;
}

}  // namespace
}  // namespace illum
