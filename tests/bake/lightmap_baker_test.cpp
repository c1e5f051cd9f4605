// The path-traced light-map baker (bake/lightmap_baker.h) on scenes with known answers:
// point lights over a plane (exact: a deterministic estimator), a constant sky over an
// open plane in all three bases (analytic hemisphere integrals), an environment map's SH
// projection (quadrature), the white furnace with emission for several bounce limits
// (closed forms), and the Cornell box against the path tracer itself.
//
// Statistical checks: every texel has its own scrambled Sobol' sequence, so texels are
// independent estimates; where all texels share one expected value the check is
// |mean − expected| ≤ kZ · (standard error of the mean over texels), kZ = 5 (a false
// failure below 1e-6 per check for a normal mean). Exact estimators are checked to float
// rounding (1e-5 relative: a few dozen float operations of 6e-8 each).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "../render/pixel_statistics.h"
#include "../render/render_test_scenes.h"
#include "bake_test_scenes.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/render/light_sampler.h"
#include "illum/scene/environment.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

using bake::LightmapBake;
using bake::LightmapBakeOptions;
using bake::LightmapBasis;
using bake::LightmapContent;

constexpr double kZ = 5.0;
constexpr double kRounding = 1e-5;
constexpr double kPiD = std::numbers::pi;
// Real SH constants of bands 0 and 1.
constexpr double kY0 = 0.28209479177387814;
constexpr double kY1 = 0.4886025119029199;

LightmapBakeOptions options(LightmapBasis basis, int spp, int max_bounces = 4) {
  LightmapBakeOptions o;
  o.basis = basis;
  o.spp = spp;
  o.max_bounces = max_bounces;
  o.seed = 1;
  o.progress = false;
  o.denoise = false;  // the estimator itself is under test (also the struct's default)
  return o;
}

LightmapBake bake_scene(const Scene& scene, int size, const LightmapBakeOptions& o,
                        atlas::TexelRaster* raster_out = nullptr) {
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, size, size);
  LightmapBake b = bake::bake_lightmap(scene, tracer, raster, o);
  if (raster_out) *raster_out = raster;
  return b;
}

struct MeanSe {
  double mean = 0, se = 0;
};
// Mean over the covered texels of one channel of one layer, and its standard error.
MeanSe texel_stats(const Image& layer, const atlas::TexelRaster& raster, int channel) {
  double s = 0, s2 = 0;
  const double n = static_cast<double>(raster.covered());
  for (const atlas::TexelSample& t : raster.samples) {
    const double v = layer.pixel(t.x, t.y)[channel];
    s += v;
    s2 += v * v;
  }
  const double m = s / n;
  return {m, std::sqrt(std::max(s2 / n - m * m, 0.0) / (n - 1.0))};
}

void expect_mean(const Image& layer, const atlas::TexelRaster& raster, const Color& expected,
                 const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    const MeanSe st = texel_stats(layer, raster, c);
    EXPECT_NEAR(st.mean, expected[c], kZ * st.se + kRounding * std::abs(expected[c]))
        << what << " channel " << c << " (se " << st.se << ")";
  }
}

Light point_light(vec3 position, Color intensity) {
  Light l;
  l.type = LightType::kPoint;
  l.position = position;
  l.intensity = intensity;
  return l;
}

// E/π of a point light at a point with normal +y (zero behind the surface).
Color point_irradiance_over_pi(const Light& l, const vec3& p) {
  const vec3 d = l.position - p;
  const float r2 = glm::dot(d, d);
  const float cos_theta = std::max(0.0f, d.y / std::sqrt(r2));
  return l.intensity * (cos_theta / (kPi * r2));
}

TEST(LightmapBaker, PointLightOverPlaneIsExact) {
  // One point light and nothing else to hit: every sample's next-event estimate is the
  // exact E/π (light chosen with probability 1, no visibility noise) and every hemisphere
  // ray escapes into black, so the map equals I·cosθ/(π r²) to float rounding.
  Scene s;
  test::add_instance(s, test::uv_plane(2.0f, test::add_lambert(s, Color(0.5f))));
  s.lights.push_back(point_light({0.3f, 1.5f, -0.2f}, Color(2.0f, 3.0f, 4.0f)));
  atlas::TexelRaster raster;
  const LightmapBake b = bake_scene(s, 16, options(LightmapBasis::kPlain, 16), &raster);
  ASSERT_EQ(b.layers.size(), 1u);
  ASSERT_EQ(raster.covered(), 256u);
  EXPECT_EQ(b.texels, 256u);
  EXPECT_GE(b.rays, 256 * 16 * 2);  // a shadow ray and a hemisphere ray per sample
  for (const atlas::TexelSample& t : raster.samples) {
    const Color expected = point_irradiance_over_pi(s.lights[0], t.position);
    const Color got = b.layers[0].rgb(t.x, t.y);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], expected[c], kRounding * expected[c]) << t.x << "," << t.y;
  }

  // Content "indirect": the point light's direct light is left to the real-time renderer
  // and there is nothing to bounce from, so the map is black.
  LightmapBakeOptions o = options(LightmapBasis::kPlain, 16);
  o.content = LightmapContent::kIndirect;
  const LightmapBake indirect = bake_scene(s, 16, o);
  for (const float v : indirect.layers[0].data()) ASSERT_EQ(v, 0.0f);

  // A light below the plane reaches none of its (upward-facing) texels.
  s.lights[0].position.y = -1.0f;
  const LightmapBake below = bake_scene(s, 16, options(LightmapBasis::kPlain, 16));
  for (const float v : below.layers[0].data()) ASSERT_EQ(v, 0.0f);
}

// The texel's tangent frame as the bakers and shaders use it (lightmap_baker.h).
vec3 to_tangent(const atlas::TexelSample& t, const vec3& w) {
  const vec3 b = glm::cross(t.normal, t.tangent) * t.tangent_sign;
  return vec3(glm::dot(w, t.tangent), glm::dot(w, b), glm::dot(w, t.normal));
}

// Dominant-direction maps (lightmap_basis.h) from both bakers under one point light over a
// plane. Every estimate there is exact (the light's next-event estimate is deterministic
// and every hemisphere ray escapes into black; the radiosity baker's direct light is one
// exact shadow ray), so: the direction is the texel's direction to the light, all of the
// light is directional (r = 1: ambient 0), and A + C·d_z, the display on the baked normal,
// equals the plain map of the same baker — each to float rounding.
TEST(LightmapBaker, DominantPointsAtAPointLightAndMatchesPlain) {
  Scene s;
  test::add_instance(
      s, test::uv_plane(2.0f, test::add_lambert(s, Color(0.0f)), vec4(0.6f, 0.0f, 0.8f, -1.0f)));
  s.lights.push_back(point_light({0.3f, 1.5f, -0.2f}, Color(2.0f, 3.0f, 4.0f)));
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 16, 16);
  for (const bool radiosity : {false, true}) {
    const auto bake = [&](LightmapBasis basis) {
      if (!radiosity) return bake::bake_lightmap(s, tracer, raster, options(basis, 8)).layers;
      bake::RadiosityBakeOptions o;
      o.basis = basis;
      o.progress = false;
      return bake::bake_radiosity(s, tracer, raster, o).layers;
    };
    const std::vector<Image> plain = bake(LightmapBasis::kPlain);
    const std::vector<Image> dominant = bake(LightmapBasis::kDominant);
    ASSERT_EQ(dominant.size(), 3u);
    for (const atlas::TexelSample& t : raster.samples) {
      const vec3 to_light = to_tangent(t, glm::normalize(s.lights[0].position - t.position));
      const Color a = dominant[0].rgb(t.x, t.y), c = dominant[1].rgb(t.x, t.y);
      const vec3 d = dominant[2].rgb(t.x, t.y);
      const Color p = plain[0].rgb(t.x, t.y);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(d[k], to_light[k], kRounding) << (radiosity ? "radiosity " : "path ") << k;
        EXPECT_NEAR(a[k], 0.0, kRounding * p[k]) << "ambient";
        EXPECT_NEAR(a[k] + c[k] * d.z, p[k], kRounding * p[k]) << "A + C·d_z vs plain";
      }
    }
  }
}

// A small area light (a square of side 2h at height H, emitting one-sided downward, black)
// over a black plane: every sample direction of a texel — next-event points on the square,
// hemisphere rays that hit it — lies in the square's cone, and the baked mean direction is
// a sum of them with non-negative weights (luminance × sample weight), so it lies in that
// cone too, whatever the noise: the angle to the square's centre is at most the cone's
// half-angle at the texel, atan(√2·h/distance) bounding it (rounding aside). The sampling
// variance cannot widen it; what it does is checked next: A + C·d_z against the plain map,
// two independent estimates of the same E/π, in the mean over texels within kZ standard
// errors of the per-texel differences.
TEST(LightmapBaker, DominantDirectionOfASmallAreaLight) {
  Scene s;
  test::add_instance(s, test::uv_plane(2.0f, test::add_lambert(s, Color(0.0f))));
  const float h = 0.05f, height = 1.0f;
  Mesh quad = test::uv_plane(h, test::add_lambert(s, Color(0.0f), Color(40.0f, 30.0f, 20.0f)));
  quad.uv1.clear();
  // Turned over (half a turn about x) to face down.
  const int light = test::add_instance(s, std::move(quad),
                                       glm::translate(mat4(1.0f), vec3(0.2f, height, 0.1f)) *
                                           glm::rotate(mat4(1.0f), kPi, vec3(1.0f, 0.0f, 0.0f)));
  s.lights.push_back(test::area_light(light));
  atlas::TexelRaster raster;
  const LightmapBake dominant = bake_scene(s, 16, options(LightmapBasis::kDominant, 64), &raster);
  const LightmapBake plain = bake_scene(s, 16, options(LightmapBasis::kPlain, 64));
  const vec3 centre(0.2f, height, 0.1f);
  double sum = 0, sum2 = 0;
  for (const atlas::TexelSample& t : raster.samples) {
    const vec3 to_centre = centre - t.position;
    const float cone =
        std::atan(std::sqrt(2.0f) * h / (glm::length(to_centre) - std::sqrt(2.0f) * h));
    const vec3 d = dominant.layers[2].rgb(t.x, t.y);
    const vec3 expected = to_tangent(t, glm::normalize(to_centre));
    const float angle = std::acos(std::clamp(glm::dot(glm::normalize(d), expected), -1.0f, 1.0f));
    EXPECT_LE(angle, cone + 1e-3f) << "texel " << t.x << "," << t.y;
    const double e0 =
        luminance(dominant.layers[0].rgb(t.x, t.y) + dominant.layers[1].rgb(t.x, t.y) * d.z);
    const double diff = e0 - luminance(plain.layers[0].rgb(t.x, t.y));
    sum += diff;
    sum2 += diff * diff;
  }
  const double n = double(raster.covered());
  const double mean = sum / n, se = std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / (n - 1));
  EXPECT_GT(se, 0.0);  // two different estimators: their difference is noisy, not zero
  EXPECT_LE(std::abs(mean), kZ * se) << "mean of A + C·d_z − plain over texels";
}

TEST(LightmapBaker, TwoPointLightsWithinTheSelectionVariance) {
  // With two lights each sample picks light i with probability p_i and returns E_i/(π p_i):
  // per-sample variance σ² = Σ (E_i/π)²/p_i − (Σ E_i/π)². Owen-scrambled points never do
  // worse than independent ones in this one-dimensional choice, so each texel lies within
  // kZ·σ/√spp, and the texels' standardized errors average to zero (z-test on their sum).
  Scene s;
  test::add_instance(s, test::uv_plane(2.0f, test::add_lambert(s, Color(0.5f))));
  s.lights.push_back(point_light({0.3f, 1.5f, -0.2f}, Color(2.0f, 3.0f, 4.0f)));
  s.lights.push_back(point_light({-1.5f, 0.6f, 1.0f}, Color(1.0f, 0.5f, 0.2f)));
  const LightSampler lights(s);
  const double p0 = lights.pmf(0), p1 = lights.pmf(1);
  ASSERT_NEAR(p0 + p1, 1.0, 1e-6);
  const int spp = 32;
  atlas::TexelRaster raster;
  const LightmapBake b = bake_scene(s, 16, options(LightmapBasis::kPlain, spp), &raster);
  double z_sum = 0;
  int z_count = 0;
  for (const atlas::TexelSample& t : raster.samples) {
    const Color e0 = point_irradiance_over_pi(s.lights[0], t.position);
    const Color e1 = point_irradiance_over_pi(s.lights[1], t.position);
    for (int c = 0; c < 3; ++c) {
      const double expected = e0[c] + e1[c];
      const double var = e0[c] * e0[c] / p0 + e1[c] * e1[c] / p1 - expected * expected;
      const double sigma = std::sqrt(std::max(var, 0.0) / spp);
      const double got = b.layers[0].rgb(t.x, t.y)[c];
      EXPECT_NEAR(got, expected, kZ * sigma + kRounding * expected) << t.x << "," << t.y;
      if (sigma > 1e-6 * expected) {
        z_sum += (got - expected) / sigma;
        ++z_count;
      }
    }
  }
  ASSERT_GT(z_count, 500);
  EXPECT_LT(std::abs(z_sum / std::sqrt(z_count)), kZ);
}

Scene sky_plane(const Color& sky, const vec4& tangent = vec4(1, 0, 0, 1)) {
  Scene s;
  test::add_instance(s, test::uv_plane(2.0f, test::add_lambert(s, Color(0.5f)), tangent));
  Environment env;
  env.constant = sky;
  s.environment = env;
  return s;
}

TEST(LightmapBaker, ConstantSkyInEveryBasis) {
  // An open plane under a uniform sky L: every texel sees L over its whole hemisphere.
  //   plain  (1/π)∫_H L cosθ dω = L
  //   sh     c0 = L·Y00·2π, c_z = L·Y1·∫_H cosθ dω = L·Y1·π, c_x = c_y = 0
  //   rnm    (1/π)∫_H L max(b·ω, 0) dω = L·(1 + b_z)/2 for a unit b at angle α from the
  //          normal (b_z = cos α = 1/√3): the classic irradiance of a plane tilted by α under
  //          a uniform sky, πL(1 + cos α)/2 — checked against a quadrature below.
  const Color sky(0.5f, 1.0f, 2.0f);
  const Scene s = sky_plane(sky);
  atlas::TexelRaster raster;
  const LightmapBake plain = bake_scene(s, 16, options(LightmapBasis::kPlain, 32), &raster);
  expect_mean(plain.layers[0], raster, sky, "plain");

  const LightmapBake sh = bake_scene(s, 16, options(LightmapBasis::kShL1, 32));
  ASSERT_EQ(sh.layers.size(), 4u);
  expect_mean(sh.layers[0], raster, sky * static_cast<float>(kY0 * 2.0 * kPiD), "sh c0");
  expect_mean(sh.layers[1], raster, Color(0.0f), "sh c1-1 (y)");
  expect_mean(sh.layers[2], raster, sky * static_cast<float>(kY1 * kPiD), "sh c10 (z)");
  expect_mean(sh.layers[3], raster, Color(0.0f), "sh c11 (x)");

  // Midpoint quadrature of (1/π)∫_H max(b·ω, 0) dω over (cos θ, φ), uniform in solid angle.
  const double bz = 1.0 / std::sqrt(3.0), bx = std::sqrt(2.0 / 3.0);
  double q = 0;
  const int nz = 1000, nphi = 2000;
  for (int i = 0; i < nz; ++i) {
    const double z = (i + 0.5) / nz, r = std::sqrt(1 - z * z);
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2 * kPiD * (j + 0.5) / nphi;
      q += std::max(0.0, bx * r * std::cos(phi) + bz * z);
    }
  }
  q *= 2 * kPiD / (nz * nphi) / kPiD;
  const double analytic = 0.5 * (1.0 + bz);
  EXPECT_NEAR(q, analytic, 1e-4);
  const LightmapBake rnm = bake_scene(s, 16, options(LightmapBasis::kRnm, 32));
  ASSERT_EQ(rnm.layers.size(), 3u);
  for (int i = 0; i < 3; ++i)
    expect_mean(rnm.layers[static_cast<size_t>(i)], raster, sky * static_cast<float>(analytic),
                "rnm " + std::to_string(i));
}

TEST(LightmapBaker, EnvironmentMapShFollowsTheTangentFrame) {
  // A lopsided environment map: the SH-L1 coefficients in the texel's tangent frame are
  // all non-zero. The plane's mesh tangent is +z with sign −1, so the frame is t = +z,
  // b = −cross(n, t) = −x, n = +y; the expected coefficients come from a midpoint
  // quadrature of L(ω)·Y_i over the hemisphere (its error is far below the bake's).
  Scene s = sky_plane(Color(0.0f), vec4(0, 0, 1, -1));
  Environment env;
  env.radiance = Image(32, 16, 3, 0.2f);
  for (int y = 2; y < 6; ++y)
    for (int x = 20; x < 26; ++x) env.radiance.set_rgb(x, y, Color(6.0f, 4.0f, 2.0f));
  env.rotation_y = 0.4f;
  s.environment = env;
  const vec3 t(0, 0, 1), b(-1, 0, 0), n(0, 1, 0);
  double c[4][3] = {};
  const int nz = 600, nphi = 1200;
  for (int i = 0; i < nz; ++i) {
    const float z = (static_cast<float>(i) + 0.5f) / nz, r = std::sqrt(1.0f - z * z);
    for (int j = 0; j < nphi; ++j) {
      const float phi = 2.0f * kPi * (static_cast<float>(j) + 0.5f) / nphi;
      const vec3 w = r * std::cos(phi) * t + r * std::sin(phi) * b + z * n;
      const Color l = environment_radiance(*s.environment, w);
      const double y[4] = {kY0, kY1 * glm::dot(w, b), kY1 * glm::dot(w, n), kY1 * glm::dot(w, t)};
      for (int k = 0; k < 4; ++k)
        for (int ch = 0; ch < 3; ++ch) c[k][ch] += l[ch] * y[k];
    }
  }
  atlas::TexelRaster raster;
  const LightmapBake sh = bake_scene(s, 24, options(LightmapBasis::kShL1, 64), &raster);
  for (int k = 0; k < 4; ++k) {
    Color expected;
    for (int ch = 0; ch < 3; ++ch)
      expected[ch] = static_cast<float>(c[k][ch] * 2.0 * kPiD / (nz * nphi));
    // Non-trivial: the x and y coefficients are far from zero for this map.
    EXPECT_GT(std::abs(expected.r), 0.1f) << "coefficient " << k;
    expect_mean(sh.layers[static_cast<size_t>(k)], raster, expected,
                "sh coefficient " + std::to_string(k));
  }
}

TEST(LightmapBaker, EmissiveFurnaceBox) {
  // Every point inside receives L = Le·Σ_{k≤N} a^k from every direction after at most N
  // bounces (N = max_bounces: 0 is direct light only), so E/π is that sum; the floor's own
  // emission is not part of the light arriving at it.
  const float a = 0.5f;
  const Scene s = test::furnace_box(a, 1.0f);
  for (const int bounces : {0, 1, 1000}) {
    double expected = 0, ak = 1;
    for (int k = 0; k <= std::min(bounces, 60); ++k, ak *= a) expected += ak;
    atlas::TexelRaster raster;
    const LightmapBake b = bake_scene(s, 12, options(LightmapBasis::kPlain, 32, bounces), &raster);
    expect_mean(b.layers[0], raster, Color(static_cast<float>(expected)),
                "max_bounces " + std::to_string(bounces));
    if (bounces == 1000) {
      // No delta lights: content "indirect" keeps everything, sample for sample.
      LightmapBakeOptions o = options(LightmapBasis::kPlain, 32, bounces);
      o.content = LightmapContent::kIndirect;
      EXPECT_EQ(bake_scene(s, 12, o).layers[0].data(), b.layers[0].data());
    }
  }
}

TEST(LightmapBaker, CornellFloorAgreesWithThePathTracer) {
  // The oracle, seen through its own camera: a Lambert floor point p of albedo ρ shows the
  // path tracer L_o(p) = ρ·E(p)/π, so a camera a few centimetres above p with a tiny field
  // of view (footprint ~1e-5 m) renders independent estimates of ρ × the baked texel. The
  // path tracer scatters at p with the floor's real BSDF; the baker with its basis vertex
  // (cosine sampling, its own MIS bookkeeping, ray offsets, bounce numbering: baker N ↔ path
  // tracer N + 1). Each side's standard error comes from independent repetitions (32 bake
  // seeds, 64 pixels); |difference| ≤ kZ·√(se_b² + se_p²). Two bounce limits: 1 (where the
  // numbering matters most) and 5.
  Scene s = load_scene("cornell");
  int floor = -1;
  for (size_t i = 0; i < s.instances.size(); ++i)
    if (s.meshes[static_cast<size_t>(s.instances[i].mesh)].name == "floor")
      floor = static_cast<int>(i);
  ASSERT_GE(floor, 0);
  Mesh& mesh = s.meshes[static_cast<size_t>(s.instances[static_cast<size_t>(floor)].mesh)];
  Bounds3 bounds;
  for (const vec3& p : mesh.positions) bounds.extend(p);
  mesh.uv1.clear();
  for (const vec3& p : mesh.positions)
    mesh.uv1.push_back(vec2((p.x - bounds.min.x) / (bounds.max.x - bounds.min.x),
                            (p.z - bounds.min.z) / (bounds.max.z - bounds.min.z)));
  const Color albedo = s.materials[static_cast<size_t>(mesh.material)].albedo;
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 4, 4);
  ASSERT_EQ(raster.covered(), 16u);

  for (const int bounces : {1, 5}) {
    const int seeds = 32;
    std::vector<LightmapBake> bakes;
    for (int seed = 0; seed < seeds; ++seed) {
      LightmapBakeOptions o = options(LightmapBasis::kPlain, 64, bounces);
      o.seed = static_cast<uint64_t>(seed);
      o.dilate = 0;
      bakes.push_back(bake::bake_lightmap(s, tracer, raster, o));
    }

    int checked = 0;
    for (const atlas::TexelSample& t : raster.samples) {
      if (checked == 4) break;
      // Only points the camera can see straight down (not under a block).
      const float height = 0.05f;
      const Ray down{t.position + height * t.normal, -t.normal};
      Hit hit;
      if (!tracer.intersect(down, &hit) || static_cast<int>(hit.instance) != floor ||
          std::abs(hit.t - height) > 1e-4f)
        continue;
      Camera cam;
      cam.position = t.position + height * t.normal;
      cam.look_at = t.position;
      cam.up = vec3(0, 0, 1);
      cam.fov_y = radians(0.01f);
      RenderOptions ro;
      ro.width = ro.height = 8;
      ro.spp = 64;
      ro.seed = static_cast<uint64_t>(100 + 10 * bounces + checked);
      ro.progress = false;
      const Image img = Integrator::create("path", Params({{"max_bounces", bounces + 1}}, "test"))
                            ->render(tracer, cam, ro);
      for (int c = 0; c < 3; ++c) {
        double bs = 0, bs2 = 0;
        for (const LightmapBake& b : bakes) {
          const double v = b.layers[0].rgb(t.x, t.y)[c];
          bs += v;
          bs2 += v * v;
        }
        const double bm = bs / seeds;
        const double bse = std::sqrt(std::max(bs2 / seeds - bm * bm, 0.0) / (seeds - 1));
        double ps = 0, ps2 = 0;
        const int np = ro.width * ro.height;
        for (int y = 0; y < ro.height; ++y)
          for (int x = 0; x < ro.width; ++x) {
            const double v = img.pixel(x, y)[c] / albedo[c];
            ps += v;
            ps2 += v * v;
          }
        const double pm = ps / np;
        const double pse = std::sqrt(std::max(ps2 / np - pm * pm, 0.0) / (np - 1));
        EXPECT_NEAR(bm, pm, kZ * std::sqrt(bse * bse + pse * pse))
            << "max_bounces " << bounces << " texel " << t.x << "," << t.y << " channel " << c
            << " (bake se " << bse << ", path se " << pse << ")";
        EXPECT_GT(bm, 0.0);
      }
      ++checked;
    }
    EXPECT_EQ(checked, 4);
  }
}

TEST(LightmapBaker, ByteIdenticalForOneTwoAndFourThreads) {
  // bake/README.md: a texel's value depends only on (seed, x, y, spp, scene), never on
  // threads: every basis, every layer and the variance image, byte for byte, for 1, 2 and 4
  // threads (texels are shared out in chunks of 16, so 32×32 texels keep every thread busy).
  Scene s = sky_plane(Color(0.3f, 0.4f, 0.5f));
  s.lights.push_back(point_light({0.3f, 1.5f, -0.2f}, Color(2.0f)));
  test::add_instance(s, [] {
    Mesh m;
    m.name = "occluder";
    m.positions = {{-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f}, {0.0f, 0.5f, 0.5f}};
    m.indices = {0, 2, 1};
    return m;
  }());
  for (const LightmapBasis basis :
       {LightmapBasis::kPlain, LightmapBasis::kRnm, LightmapBasis::kShL1}) {
    LightmapBakeOptions o = options(basis, 8);
    o.threads = 1;
    const LightmapBake one = bake_scene(s, 32, o);
    for (const int threads : {2, 4}) {
      o.threads = threads;
      const LightmapBake other = bake_scene(s, 32, o);
      ASSERT_EQ(one.layers.size(), other.layers.size());
      for (size_t i = 0; i < one.layers.size(); ++i)
        EXPECT_TRUE(test::identical_bytes(one.layers[i], other.layers[i]))
            << bake::to_string(basis) << " layer " << i << ", " << threads << " threads";
      EXPECT_TRUE(test::identical_bytes(one.variance, other.variance))
          << bake::to_string(basis) << ", " << threads << " threads";
    }
    o.seed = 2;
    EXPECT_FALSE(test::identical_bytes(bake_scene(s, 32, o).layers[0], one.layers[0]))
        << "another seed must give another map";
  }
}

TEST(LightmapBaker, OptionsAndNames) {
  EXPECT_EQ(bake::lightmap_basis_from_string("plain"), LightmapBasis::kPlain);
  EXPECT_EQ(bake::lightmap_basis_from_string("rnm"), LightmapBasis::kRnm);
  EXPECT_EQ(bake::lightmap_basis_from_string("sh"), LightmapBasis::kShL1);
  EXPECT_EQ(bake::lightmap_content_from_string("indirect"), LightmapContent::kIndirect);
  EXPECT_STREQ(bake::to_string(LightmapBasis::kShL1), "sh");
  EXPECT_STREQ(bake::to_string(LightmapContent::kAll), "all");
  EXPECT_EQ(bake::layer_count(LightmapBasis::kPlain), 1);
  EXPECT_EQ(bake::layer_count(LightmapBasis::kRnm), 3);
  EXPECT_EQ(bake::layer_count(LightmapBasis::kShL1), 4);
  EXPECT_EQ(bake::layer_count(LightmapBasis::kDominant), 3);
  EXPECT_EQ(bake::lightmap_basis_from_string("dominant"), LightmapBasis::kDominant);
  EXPECT_STREQ(bake::to_string(LightmapBasis::kDominant), "dominant");
  EXPECT_EQ(bake::accumulation_basis(LightmapBasis::kDominant), LightmapBasis::kShL1);
  EXPECT_THROW(bake::dominant_from_sh({Image(2, 2, 3)}), Error);
  EXPECT_THROW(bake::lightmap_basis_from_string("hl2"), Error);
  EXPECT_THROW(bake::lightmap_content_from_string("direct"), Error);

  const Params good(nlohmann::json{{"basis", "rnm"},
                                   {"content", "indirect"},
                                   {"spp", 7},
                                   {"max_bounces", 0},
                                   {"dilate", 0},
                                   {"seed", 12345678901234ull}},
                    "test");
  const LightmapBakeOptions o = LightmapBakeOptions::from_params(good);
  EXPECT_EQ(o.basis, LightmapBasis::kRnm);
  EXPECT_EQ(o.content, LightmapContent::kIndirect);
  EXPECT_EQ(o.spp, 7);
  EXPECT_EQ(o.max_bounces, 0);
  EXPECT_EQ(o.dilate, 0);
  EXPECT_EQ(o.seed, 12345678901234ull);
  EXPECT_NO_THROW(good.check_all_used());
  const LightmapBakeOptions defaults = LightmapBakeOptions::from_params(Params());
  EXPECT_EQ(defaults.spp, 256);
  EXPECT_EQ(defaults.basis, LightmapBasis::kPlain);

  const auto bad = test::bake_options_error;
  EXPECT_NE(bad({{"basis", "hl2"}}).find("basis"), std::string::npos);
  EXPECT_NE(bad({{"content", "x"}}).find("content"), std::string::npos);
  EXPECT_NE(bad({{"spp", 0}}).find("spp"), std::string::npos);
  EXPECT_NE(bad({{"spp", (1 << 20) + 1}}).find("spp"), std::string::npos);
  EXPECT_NE(bad({{"max_bounces", -1}}).find("max_bounces"), std::string::npos);
  EXPECT_NE(bad({{"dilate", 65}}).find("dilate"), std::string::npos);
  EXPECT_NE(bad({{"seed", -1}}).find("seed"), std::string::npos);
  EXPECT_NE(bad({{"seed", "one"}}).find("seed"), std::string::npos);
  EXPECT_NE(bad({{"seed", 1.5}}).find("seed"), std::string::npos);
}

TEST(LightmapBaker, BadInputThrows) {
  const Scene s = sky_plane(Color(1.0f));
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 4, 4);
  auto with = [&](auto change) {
    LightmapBakeOptions o = options(LightmapBasis::kPlain, 4);
    change(o);
    return o;
  };
  EXPECT_NO_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto&) {})));
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) { o.spp = 0; })), Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) { o.spp = (1 << 20) + 1; })),
               Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) { o.max_bounces = -1; })),
               Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) { o.dilate = 100; })),
               Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) { o.threads = -2; })),
               Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster,
                                   with([](auto& o) { o.basis = static_cast<LightmapBasis>(7); })),
               Error);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, with([](auto& o) {
                                     o.content = static_cast<LightmapContent>(3);
                                   })),
               Error);
  EXPECT_THROW(bake::layer_count(static_cast<LightmapBasis>(7)), Error);

  // A tracer or a raster of another scene.
  const Scene other = sky_plane(Color(1.0f));
  const RayTracer other_tracer(other);
  EXPECT_THROW(bake::bake_lightmap(s, other_tracer, raster, with([](auto&) {})), Error);
  Scene two = sky_plane(Color(1.0f));
  test::add_instance(two, test::uv_plane(1.0f, 0, vec4(1, 0, 0, 1), vec2(0.5f), vec2(1.0f)));
  two.meshes[0].uv1 = {{0, 0}, {0.5f, 0}, {0.5f, 0.5f}, {0, 0.5f}};
  const atlas::TexelRaster two_raster = atlas::rasterize_texels(two, 4, 4);
  EXPECT_THROW(bake::bake_lightmap(s, tracer, two_raster, with([](auto&) {})), Error);
  atlas::TexelRaster broken = raster;
  broken.sample_of.pop_back();
  EXPECT_THROW(bake::bake_lightmap(s, tracer, broken, with([](auto&) {})), Error);
}

TEST(LightmapBaker, CtrlCStops) {
  const Scene s = sky_plane(Color(1.0f));
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 8, 8);
  request_interrupt();
  EXPECT_THROW(bake::bake_lightmap(s, tracer, raster, options(LightmapBasis::kPlain, 4)),
               Interrupted);
  clear_interrupt();
  EXPECT_NO_THROW(bake::bake_lightmap(s, tracer, raster, options(LightmapBasis::kPlain, 4)));
}

}  // namespace
}  // namespace illum
