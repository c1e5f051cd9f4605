// Light sampling: next-event estimates against analytic irradiance, pdf consistency, and
// emission (photon) sampling that carries each light's power. Statistical checks use kZ
// standard errors from the sample variance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "illum/core/sampling.h"
#include "illum/render/light_sampler.h"
#include "illum/scene/environment.h"
#include "render_test_scenes.h"
#include "running_stat.h"

namespace illum {
namespace {

using test::kZ;
using Stat = test::RunningStat;

Scene base_scene() {
  Scene s;
  s.name = "lights";
  const int m = test::add_material(s, Material{});
  test::add_triangles(s, test::floor_quad(2.0f), m, "floor");
  return s;
}

Light point_light(vec3 p, float intensity) {
  Light l;
  l.type = LightType::kPoint;
  l.position = p;
  l.intensity = Color(intensity);
  return l;
}

Light spot_light(vec3 p, vec3 dir, float flux, float half_angle) {
  Light l;
  l.type = LightType::kSpot;
  l.position = p;
  l.direction = glm::normalize(dir);
  l.cone_half_angle = half_angle;
  l.intensity = Color(flux / l.cone_solid_angle());  // S004: I = Φ/Ω
  return l;
}

TEST(LightSampler, PointLightInverseSquare) {
  Scene s = base_scene();
  s.lights.push_back(point_light({0.3f, 2.0f, -0.1f}, 5.0f));
  const LightSampler ls(s);
  const vec3 p(1.0f, 0.0f, 0.5f);
  const auto sample = ls.sample_li(0, p, {0.5f, 0.5f});
  ASSERT_TRUE(sample);
  const float r2 = glm::dot(s.lights[0].position - p, s.lights[0].position - p);
  EXPECT_NEAR(sample->li.g, 5.0f / r2, 1e-5f);
  EXPECT_TRUE(sample->delta);
  EXPECT_NEAR(sample->distance, std::sqrt(r2), 1e-5f);
  EXPECT_NEAR(ls.power(0).g, 4.0f * kPi * 5.0f, 1e-4f);
}

TEST(LightSampler, SpotLightHardConeWithFluxOverSolidAngle) {
  Scene s = base_scene();
  const float half = radians(25.0f);
  s.lights.push_back(spot_light({0, 1.5f, 0}, {0, -1, 0}, 100.0f, half));
  const LightSampler ls(s);
  // Inside the cone: E = Φ/(Ω r²) at normal incidence (S004).
  const float omega = 2.0f * kPi * (1.0f - std::cos(half));
  const vec3 inside(0.5f * std::tan(half) * 1.5f, 0.0f, 0.0f);
  const auto a = ls.sample_li(0, inside, {0.5f, 0.5f});
  ASSERT_TRUE(a);
  const float r2 = glm::dot(inside - s.lights[0].position, inside - s.lights[0].position);
  EXPECT_NEAR(a->li.g, 100.0f / (omega * r2), 1e-4f);
  // Just outside the cone: nothing.
  const vec3 outside(1.01f * std::tan(half) * 1.5f, 0.0f, 0.0f);
  EXPECT_FALSE(ls.sample_li(0, outside, {0.5f, 0.5f}));
  EXPECT_NEAR(ls.power(0).g, 100.0f, 1e-3f);
}

// Point straight below the centre of a parallel a×b rectangle at distance c: irradiance
// π·L·F with F the sum of four corner form factors (standard closed form).
double rect_form_factor_corner(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * std::numbers::pi);
}

TEST(LightSampler, AreaLightIrradianceMatchesClosedForm) {
  Scene s = base_scene();
  Material emitter;
  emitter.albedo = Color(0.0f);
  emitter.emission = Color(3.0f);
  const int m = test::add_material(s, emitter);
  std::vector<vec3> quad;
  const float a = 0.8f, b = 0.5f, h = 0.7f;
  // Facing down (−y): counter-clockwise seen from below.
  test::push_quad(quad, {-a / 2, h, -b / 2}, {a / 2, h, -b / 2}, {a / 2, h, b / 2},
                  {-a / 2, h, b / 2});
  const int inst = test::add_triangles(s, quad, m, "light");
  s.lights.push_back(test::area_light(inst));
  const LightSampler ls(s);
  EXPECT_NEAR(ls.power(0).g, kPi * a * b * 3.0f, 1e-4f);

  std::mt19937 gen(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  Stat e;
  const vec3 p(0.0f);
  for (int i = 0; i < 100000; ++i) {
    const auto sample = ls.sample_li(0, p, {u01(gen), u01(gen)});
    ASSERT_TRUE(sample);  // every point of the light faces p
    e.add(sample->li.g * sample->wi.y / sample->pdf);
  }
  const double expected = std::numbers::pi * 3.0 * 4.0 * rect_form_factor_corner(a / 2, b / 2, h);
  EXPECT_NEAR(e.mean(), expected, kZ * e.standard_error() + 1e-6 * expected);
  // From above the light sees only its back: no light.
  EXPECT_FALSE(ls.sample_li(0, vec3(0, 2 * h, 0), {0.3f, 0.3f}));
}

TEST(LightSampler, EmissionSelectionFollowsPower) {
  Scene s = base_scene();
  s.lights.push_back(point_light({0, 1, 0}, 1.0f));
  s.lights.push_back(point_light({0, 1, 1}, 3.0f));
  const LightSampler ls(s);
  float pmf = 0.0f;
  EXPECT_EQ(ls.choose_by_power(0.1f, &pmf), 0);
  EXPECT_NEAR(pmf, 0.25f, 1e-6f);
  EXPECT_EQ(ls.choose_by_power(0.9f, &pmf), 1);
  EXPECT_NEAR(pmf, 0.75f, 1e-6f);
}

TEST(LightSampler, NextEventSelectionMixesPowerAndUniform) {
  Scene s = base_scene();
  s.lights.push_back(point_light({0, 1, 0}, 1.0f));
  s.lights.push_back(point_light({0, 1, 1}, 3.0f));
  const LightSampler ls(s);
  // 0.5 * power share + 0.5 * uniform share.
  EXPECT_NEAR(ls.pmf(0), 0.5f * 0.25f + 0.25f, 1e-6f);
  EXPECT_NEAR(ls.pmf(1), 0.5f * 0.75f + 0.25f, 1e-6f);
  float pmf = 0.0f;
  EXPECT_EQ(ls.choose(0.1f, &pmf), 0);
  EXPECT_NEAR(pmf, 0.375f, 1e-6f);
  EXPECT_EQ(ls.choose(0.9f, &pmf), 1);
  EXPECT_NEAR(pmf, 0.625f, 1e-6f);
  // A light a million times weaker still gets at least a quarter of the samples.
  Scene t = base_scene();
  t.lights.push_back(point_light({0, 1, 0}, 1e-6f));
  t.lights.push_back(point_light({0, 1, 1}, 1.0f));
  EXPECT_GT(LightSampler(t).pmf(0), 0.25f);
}

TEST(LightSampler, SelectionAtPointDropsOnlySpotsThatCannotReachIt) {
  // A point light, a spot aimed down at the origin (30° cone) and a sun. Inside the cone
  // the point selection is the global one; outside it the spot gets nothing (sample_li
  // confirms it contributes nothing there, which is what keeps this unbiased) and the other
  // two share its probability in proportion. choose() must return each light exactly as
  // often as pmf(light, p) says: with 4096 evenly spaced u the counts can differ from
  // 4096 · pmf only by the one boundary cell each side.
  Scene s = base_scene();
  s.lights.push_back(point_light({1, 1, 0}, 2.0f));
  s.lights.push_back(spot_light({0, 3, 0}, {0, -1, 0}, 50.0f, radians(30.0f)));
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.irradiance = Color(1.0f);
  s.lights.push_back(sun);
  const LightSampler ls(s);
  const vec3 inside(0.2f, 0, 0.1f), outside(2.5f, 0, 0);
  ASSERT_TRUE(ls.sample_li(1, inside, {0.5f, 0.5f}));
  ASSERT_FALSE(ls.sample_li(1, outside, {0.5f, 0.5f}));
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(ls.pmf(i, inside), ls.pmf(i));
  EXPECT_EQ(ls.pmf(1, outside), 0.0f);
  const float rest = ls.pmf(0) + ls.pmf(2);
  EXPECT_FLOAT_EQ(ls.pmf(0, outside), ls.pmf(0) / rest);
  EXPECT_FLOAT_EQ(ls.pmf(2, outside), ls.pmf(2) / rest);
  for (const vec3& p : {inside, outside}) {
    const int n = 4096;
    int count[3] = {0, 0, 0};
    for (int k = 0; k < n; ++k) {
      float pmf = -1.0f;
      const int light = ls.choose((static_cast<float>(k) + 0.5f) / n, p, &pmf);
      ASSERT_GE(light, 0);
      ASSERT_LT(light, 3);
      ASSERT_FLOAT_EQ(pmf, ls.pmf(light, p));
      ++count[light];
    }
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(count[i], n * ls.pmf(i, p), 1.0) << i;
  }
}

Scene env_scene() {
  Scene s = base_scene();
  Environment env;
  env.radiance = Image(32, 16, 3, 0.2f);
  // A bright patch (a "sun") near the horizon and a dimmer band.
  for (int y = 5; y < 7; ++y)
    for (int x = 20; x < 23; ++x) env.radiance.set_rgb(x, y, Color(50.0f, 40.0f, 30.0f));
  for (int x = 0; x < 32; ++x) env.radiance.set_rgb(x, 2, Color(2.0f));
  env.scale = 1.5f;
  env.rotation_y = 0.4f;
  s.environment = env;
  return s;
}

TEST(LightSampler, EnvironmentImportanceSamplingIsConsistent) {
  const Scene s = env_scene();
  const LightSampler ls(s);
  ASSERT_EQ(ls.environment_light(), static_cast<int>(s.lights.size()));  // implicit light
  std::mt19937 gen(9);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  // The largest error of the uv → direction → uv round trip over the map (worst near the
  // poles, where u is ill-conditioned): a direction the sampler drew in one texel can read
  // back in the next one only this close to their shared edge.
  const float rotation = s.environment->rotation_y;
  const int w = s.environment->radiance.width(), h = s.environment->radiance.height();
  double delta = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const vec2 uv(u01(gen), u01(gen));
    const vec2 back =
        equirect_uv_from_direction(equirect_direction_from_uv(uv, rotation), rotation);
    const double du = std::abs(double(back.x) - uv.x);
    delta = std::max({delta, std::min(du, 1.0 - du), std::abs(double(back.y) - uv.y)});
  }
  // ∫ L dω two ways: uniform sphere sampling and the importance sampler.
  Stat uniform, importance, pdf_integral;
  int edge_mismatches = 0, pole_mismatches = 0, other_mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    const vec3 d = sample_uniform_sphere({u01(gen), u01(gen)});
    uniform.add(ls.environment_radiance(d).g / pdf_uniform_sphere());
    pdf_integral.add(ls.pdf_environment(d) / pdf_uniform_sphere());
    const auto sample = ls.sample_li(ls.environment_light(), vec3(0.0f), {u01(gen), u01(gen)});
    ASSERT_TRUE(sample);
    // The pdf the sampler reports is the one pdf_environment() gives for its direction, to
    // float rounding (1e-3 of it), except where the direction cannot carry its texel or its
    // sin θ that precisely: within delta of a texel edge, and near the poles, where the
    // pdf's 1/sin θ turns the float error of ω_y = cos θ (a few units of 2⁻²⁴) into a
    // relative error ≈ 2⁻²⁴/θ² — above 1e-3 for θ < θ_c = √(8·2⁻²⁴/1e-3) (8 units).
    if (std::abs(ls.pdf_environment(sample->wi) - sample->pdf) > 1e-3f * sample->pdf) {
      const vec2 uv = equirect_uv_from_direction(sample->wi, rotation);
      const double theta_c = std::sqrt(8.0 * 0x1p-24 / 1e-3);
      const double to_edge = std::min(std::abs(uv.x * w - std::round(uv.x * w)) / w,
                                      std::abs(uv.y * h - std::round(uv.y * h)) / h);
      if (std::min(uv.y, 1.0f - uv.y) * kPi <= theta_c) {
        ++pole_mismatches;
      } else {
        ++(to_edge <= delta ? edge_mismatches : other_mismatches);
      }
    }
    importance.add(sample->li.g / sample->pdf);
  }
  std::printf("pdf mismatches: %d near a pole, %d within %.2g of a texel edge, %d elsewhere\n",
              pole_mismatches, edge_mismatches, delta, other_mismatches);
  EXPECT_EQ(other_mismatches, 0);
  EXPECT_NEAR(pdf_integral.mean(), 1.0, kZ * pdf_integral.standard_error());
  EXPECT_NEAR(uniform.mean(), importance.mean(),
              kZ * std::hypot(uniform.standard_error(), importance.standard_error()));
  EXPECT_LT(importance.standard_error(),
            uniform.standard_error());  // importance sampling helps on a sunny map
}

TEST(LightSampler, EmissionCarriesEachLightsPower) {
  Scene s = env_scene();
  s.lights.push_back(point_light({0, 1, 0}, 2.0f));
  s.lights.push_back(spot_light({0, 1.5f, 0}, {0.2f, -1, 0}, 40.0f, radians(30.0f)));
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.irradiance = Color(4.0f);
  s.lights.push_back(sun);
  Material emitter;
  emitter.emission = Color(2.0f);
  const int m = test::add_material(s, emitter);
  std::vector<vec3> quad;
  test::push_quad(quad, {-0.2f, 1, -0.2f}, {0.2f, 1, -0.2f}, {0.2f, 1, 0.2f}, {-0.2f, 1, 0.2f});
  s.lights.push_back(test::area_light(test::add_triangles(s, quad, m, "light")));
  const LightSampler ls(s);
  ASSERT_EQ(ls.light_count(), 5);  // 4 explicit + the implicit environment

  std::mt19937 gen(13);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int light = 0; light < ls.light_count(); ++light) {
    Stat flux;
    for (int i = 0; i < 100000; ++i) {
      const auto em = ls.sample_emission(light, {u01(gen), u01(gen)}, {u01(gen), u01(gen)});
      if (!em) {
        flux.add(0.0);
        continue;
      }
      ASSERT_NEAR(glm::length(em->ray.direction), 1.0f, 1e-4f);
      const Light* l = light < 4 ? &s.lights[light] : nullptr;
      if (l && l->type == LightType::kSpot) {
        ASSERT_GE(glm::dot(em->ray.direction, l->direction), l->cos_cutoff() - 1e-5f);
      }
      if (l && l->type == LightType::kArea) {
        ASSERT_GE(glm::dot(em->ray.direction, em->normal), 0.0f);
      }
      if (!l || l->type == LightType::kDirectional) {
        // Distant lights start outside the scene's bounding sphere.
        ASSERT_GE(glm::length(em->ray.origin - ls.scene_center()), ls.scene_radius() * 0.999f);
      }
      flux.add(em->flux.g);
    }
    const double power = ls.power(light).g;
    // 1e-4 of the power: float rounding, for the lights whose every photon carries the same
    // flux (point, spot, sun: a zero standard error).
    EXPECT_NEAR(flux.mean(), power, kZ * flux.standard_error() + 1e-4 * power) << "light " << light;
  }
  // Choosing by power: the mean flux is the total power.
  Stat total;
  for (int i = 0; i < 200000; ++i) {
    const auto em = ls.sample_emission(u01(gen), {u01(gen), u01(gen)}, {u01(gen), u01(gen)});
    total.add(em ? em->flux.g : 0.0);
  }
  EXPECT_NEAR(total.mean(), ls.total_power().g,
              kZ * total.standard_error() + 1e-4 * ls.total_power().g);
}

TEST(LightSampler, TexturedEmitterPowerAndEmission) {
  // An emitter whose emission texture is bright on one half: its power is π·A·L_e·(texture
  // mean), photons carry it on average, and no photon leaves the black half.
  Scene s = base_scene();
  Texture tex;
  tex.image = Image(4, 2, 3, 0.0f);
  for (int y = 0; y < 2; ++y) {
    for (int x = 2; x < 4; ++x) tex.image.set_rgb(x, y, Color(1.0f));
  }
  s.textures.push_back(tex);
  Material emitter;
  emitter.emission = Color(5.0f);
  emitter.emission_texture = 0;
  const int m = test::add_material(s, emitter);
  std::vector<vec3> quad;
  test::push_quad(quad, {-0.5f, 1, -0.25f}, {0.5f, 1, -0.25f}, {0.5f, 1, 0.25f}, {-0.5f, 1, 0.25f});
  const int inst = test::add_triangles(s, quad, m, "light");
  s.meshes.back().uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
  s.lights.push_back(test::area_light(inst));
  const LightSampler ls(s);
  EXPECT_NEAR(ls.power(0).g, kPi * 0.5f * 5.0f * 0.5f, 1e-4f);
  std::mt19937 gen(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  Stat flux;
  for (int i = 0; i < 100000; ++i) {
    const auto em = ls.sample_emission(0, {u01(gen), u01(gen)}, {u01(gen), u01(gen)});
    if (!em) {
      flux.add(0.0);
      continue;
    }
    // u in [0.125, 0.375] (x in [−0.375, −0.125]) lies between two black texel centres, so
    // it stays black under bilinear filtering (which wraps around u = 0 into the bright
    // texel 3): no photon starts there.
    ASSERT_FALSE(em->ray.origin.x > -0.37f && em->ray.origin.x < -0.13f) << em->ray.origin.x;
    flux.add(em->flux.g);
  }
  EXPECT_NEAR(flux.mean(), ls.power(0).g, kZ * flux.standard_error());
}

}  // namespace
}  // namespace illum
