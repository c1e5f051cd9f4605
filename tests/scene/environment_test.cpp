#include <gtest/gtest.h>

#include "illum/scene/environment.h"
#include "illum/scene/scene.h"

namespace illum {
namespace {

TEST(Environment, MappingLandmarks) {
  auto uv = equirect_uv_from_direction(vec3(0, 0, -1));
  EXPECT_NEAR(uv.x, 0.5f, 1e-6f);
  EXPECT_NEAR(uv.y, 0.5f, 1e-6f);
  EXPECT_NEAR(equirect_uv_from_direction(vec3(0, 1, 0)).y, 0.0f, 1e-6f);   // zenith: top row
  EXPECT_NEAR(equirect_uv_from_direction(vec3(0, -1, 0)).y, 1.0f, 1e-6f);  // nadir: bottom
  EXPECT_NEAR(equirect_uv_from_direction(vec3(1, 0, 0)).x, 0.75f, 1e-6f);
  EXPECT_NEAR(equirect_uv_from_direction(vec3(-1, 0, 0)).x, 0.25f, 1e-6f);
  const float back = equirect_uv_from_direction(vec3(0, 0, 1)).x;
  EXPECT_TRUE(back < 1e-6f || back > 1.0f - 1e-6f);
  // Rotating the map by +90° about +y (counter-clockwise seen from above) carries its
  // centre from −z to −x; −90° carries it to +x.
  EXPECT_NEAR(equirect_uv_from_direction(vec3(-1, 0, 0), radians(90.0f)).x, 0.5f, 1e-6f);
  EXPECT_NEAR(equirect_uv_from_direction(vec3(1, 0, 0), radians(-90.0f)).x, 0.5f, 1e-6f);
}

TEST(Environment, RoundTrip) {
  for (int i = 0; i < 200; ++i) {
    const float a = 0.37f * i, b = 0.11f * i;
    const vec3 d =
        glm::normalize(vec3(std::sin(a) * std::cos(b), std::cos(1.3f * a), std::sin(b + 0.2f)));
    for (float rot : {0.0f, 0.7f, -2.0f}) {
      const vec3 back = equirect_direction_from_uv(equirect_uv_from_direction(d, rot), rot);
      EXPECT_NEAR(glm::distance(back, d), 0.0f, 1e-4f) << i;
    }
  }
}

TEST(Environment, RadianceLookup) {
  Environment env;
  env.constant = Color(0.5f, 1.0f, 2.0f);
  env.scale = 2.0f;
  EXPECT_EQ(environment_radiance(env, vec3(0, 1, 0)), Color(1.0f, 2.0f, 4.0f));

  // 4×2 map: each texel a different value; a direction through a texel centre reads it
  // exactly, the seam blends the first and last columns.
  env.radiance = Image(4, 2, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) env.radiance.set_rgb(x, y, Color(float(x + 4 * y)));
  env.scale = 1.0f;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const vec3 d = equirect_direction_from_uv(vec2((x + 0.5f) / 4, (y + 0.5f) / 2));
      EXPECT_NEAR(environment_radiance(env, d).r, float(x + 4 * y), 1e-4f) << x << "," << y;
    }
  // u = 0 (toward +z) on the upper row, v = 0.25: halfway between columns 3 and 0.
  const vec3 seam = equirect_direction_from_uv(vec2(0.0f, 0.25f));
  EXPECT_NEAR(environment_radiance(env, seam).r, 1.5f, 1e-4f);
  // The zenith clamps to the top row (mean over u of its bilinear blend: bounded by row 0).
  const float top = environment_radiance(env, vec3(0, 1, 0)).r;
  EXPECT_GE(top, 0.0f);
  EXPECT_LE(top, 3.0f);
}

}  // namespace
}  // namespace illum
