// Photon tracing, photon mapping and SPPM against analytic answers and the path tracer.
// Statistical tolerances: per-point Poisson standard deviations where photons are
// independent, and Student-t intervals from repeated runs with different seeds where
// pixels share photons (their correlations make per-pixel variances useless).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/render/light_sampler.h"
#include "illum/render/photon_shading.h"
#include "illum/render/photon_tracer.h"
#include "illum/scene/environment.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "pixel_statistics.h"
#include "render_test_scenes.h"
#include "running_stat.h"

namespace illum {
namespace {

Params params(const nlohmann::json& j) {
  return Params(j, "--param");
}

Image render(const std::string& name, const nlohmann::json& p, const Scene& scene,
             const Camera& cam, int size, int spp, uint64_t seed) {
  const RayTracer tracer(scene);
  RenderOptions o;
  o.width = o.height = size;
  o.spp = spp;
  o.seed = seed;
  o.progress = false;
  return Integrator::create(name, params(p))->render(tracer, cam, o);
}

double image_mean(const Image& img, int channel = 1) {
  double s = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) s += img.pixel(x, y)[channel];
  return s / static_cast<double>(img.pixel_count());
}

struct SeedStats {
  double mean = 0, sd = 0;  // over seeds; sd is the sample standard deviation
  int n = 0;
};
SeedStats seed_stats(const std::vector<double>& v) {
  SeedStats s;
  s.n = static_cast<int>(v.size());
  for (double x : v) s.mean += x;
  s.mean /= s.n;
  for (double x : v) s.sd += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(s.sd / (s.n - 1));
  return s;
}

// Two-sided 99.9 % quantile of Student's t for kSeeds − 1 = 5 degrees of freedom (6.869,
// computed); Welch–Satterthwaite degrees of freedom are at least min(n1, n2) − 1.
constexpr int kSeeds = 6;
const double kT5 = test::student_t_quantile(0.0005, kSeeds - 1);

Scene furnace_sphere(float a) {
  return test::furnace_sphere(a, 24, 48);
}

Camera inside_camera() {
  Camera cam;
  cam.position = vec3(0.1f, -0.2f, 0.05f);
  cam.look_at = vec3(1, 0.3f, 0.2f);
  cam.fov_y = radians(90.0f);
  return cam;
}

TEST(PhotonIntegrator, WhiteFurnaceFromTheGlobalMap) {
  // Emitted Le + direct (NEE) a·Le + global map a²·Le/(1−a). The k-NN estimate with the
  // radius at the k-th photon has the known bias factor 1 + w(r)/(norm·(k−1)) on the
  // global part (see PhotonEstimate.UniformDensityAllFilters; on a sphere the area within
  // chord distance r is exactly πr², so the planar analysis holds).
  const int k = 50;
  FilterSettings cone;
  const double knn_bias =
      1.0 + filter_weight(cone, 1.0f, 1.0f) / (filter_normalization(cone) * (k - 1));
  for (const float a : {0.5f, 0.8f}) {
    const Scene s = furnace_sphere(a);
    std::vector<double> means;
    for (int seed = 0; seed < kSeeds; ++seed) {
      const Image img = render("photon",
                               {{"photons", 20000},
                                {"caustic_photons", 0},
                                {"k", k},
                                {"final_gather", false},
                                {"max_depth", 1000}},
                               s, inside_camera(), 12, 2, 100 + seed);
      means.push_back(image_mean(img));
    }
    const SeedStats st = seed_stats(means);
    const double expected = 1.0 + a + a * a / (1.0 - a) * knn_bias;
    EXPECT_NEAR(st.mean, expected, kT5 * st.sd / std::sqrt(st.n))
        << "albedo " << a << " sd " << st.sd << " (unbiased answer " << 1.0 / (1.0 - a) << ")";
  }
}

TEST(SppmIntegrator, WhiteFurnace) {
  for (const float a : {0.5f, 0.8f}) {
    const Scene s = furnace_sphere(a);
    std::vector<double> means;
    for (int seed = 0; seed < kSeeds; ++seed) {
      const Image img = render("sppm",
                               {{"iterations", 6},
                                {"photons_per_iteration", 10000},
                                {"initial_radius", 0.15},
                                {"max_depth", 1000}},
                               s, inside_camera(), 12, 1, 200 + seed);
      means.push_back(image_mean(img));
    }
    const SeedStats st = seed_stats(means);
    EXPECT_NEAR(st.mean, 1.0 / (1.0 - a), kT5 * st.sd / std::sqrt(st.n))
        << "albedo " << a << " sd " << st.sd;
  }
}

// Disc average of the irradiance a point/spot light at height h above the origin gives the
// y = 0 plane, around (x0, 0, 0) with radius r: the expectation of the fixed-radius box
// estimate (midpoint quadrature in polar coordinates).
double disc_average_irradiance(float intensity, float h, float cos_cutoff, float x0, float r) {
  const int nr = 200, nphi = 200;
  double sum = 0.0, area = 0.0;
  for (int i = 0; i < nr; ++i) {
    const double rho = (i + 0.5) * r / nr;
    for (int j = 0; j < nphi; ++j) {
      const double phi = (j + 0.5) * 2.0 * kPi / nphi;
      const double x = x0 + rho * std::cos(phi), z = rho * std::sin(phi);
      const double d2 = x * x + z * z + double(h) * h;
      const double cos_t = h / std::sqrt(d2);
      const double e = cos_t >= cos_cutoff ? intensity * cos_t / d2 : 0.0;
      sum += e * rho;
      area += rho;
    }
  }
  return sum / area;
}

void check_irradiance_from_photons(const Light& light, float h, const std::vector<float>& xs) {
  Scene s;
  Material m;
  m.albedo = Color(0.5f);
  const int mat = test::add_material(s, m);
  test::add_triangles(s, test::floor_quad(6.0f), mat, "floor");
  s.lights.push_back(light);
  const RayTracer tracer(s);
  const LightSampler lights(s);
  const int64_t n = 400000;
  const float scale = 1.0f / static_cast<float>(n);
  std::vector<Photon> direct = trace_photons_parallel<Photon>(
      lights, n, 7, 1, [&](int64_t, const LightEmission& e, Rng& rng, std::vector<Photon>& sink) {
        trace_photon_path(
            tracer, e, rng, PhotonPathSettings{},
            [&](const PhotonEvent& ev) {
              if (ev.depth == 0) sink.push_back(Photon{ev.p, ev.wi, ev.power * scale, ev.ng});
              return false;
            },
            [](const PhotonEvent&) {});
      });
  ASSERT_FALSE(direct.empty());
  const float phi = direct.front().power.g;  // every direct photon carries Φ/N
  const PhotonMap map(std::move(direct));
  const float r = 0.05f;
  FilterSettings box;
  box.type = PhotonFilter::kNone;
  std::vector<PhotonNeighbor> scratch;
  for (float x : xs) {
    const double est =
        estimate_radiance(
            map, vec3(x, 0, 0), 0, r, box, [](const Photon&) { return Color(1.0f); }, &scratch)
            .g;
    const double expect = disc_average_irradiance(
        light.intensity.g, h, light.type == LightType::kSpot ? light.cos_cutoff() : -1.0f, x, r);
    // Photon count in the disc is Poisson with mean λ = E·πr²/φ: σ(E) = √(E·φ/(πr²)).
    const double sigma = std::sqrt(expect * phi / (kPi * r * r));
    // The analytic point value differs from the disc average by ≈ r²ΔE/8, reported only.
    const double point = x * x + h * h;
    const double e_point = light.intensity.g * h / (std::sqrt(point) * point);
    EXPECT_NEAR(est, expect, 4.5 * sigma + 1e-9)
        << "x = " << x << ": point value I cosθ/r² = " << e_point;
  }
}

TEST(PhotonIntegrator, ShadowPhotonsReproduceShadowsFarFromEdges) {
  // A point light 1 m above a floor (albedo 0.5) and a 0.6 m square occluder (albedo 0,
  // so nothing bounces) 0.5 m above the floor: the floor's centre lies in the umbra, the
  // far floor in full light. With shadow_photons = seed, direct light comes without shadow
  // rays and the negative-flux photons subtract it: in the umbra the expectation is the
  // unshadowed radiance times (1 − b), b the k-NN bias factor of the shadow estimate
  // (see WhiteFurnaceFromTheGlobalMap), i.e. ≈ 0; in full light nothing is subtracted.
  // `skip` must agree with `off` in both places (it only skips shadow rays).
  Scene s;
  Material floor_m, black;
  floor_m.albedo = Color(0.5f);
  black.albedo = Color(0.0f);
  test::add_triangles(s, test::floor_quad(3.0f), test::add_material(s, floor_m), "floor");
  std::vector<vec3> occ;
  test::push_quad(occ, {-0.3f, 0.5f, 0.3f}, {-0.3f, 0.5f, -0.3f}, {0.3f, 0.5f, -0.3f},
                  {0.3f, 0.5f, 0.3f});
  test::add_triangles(s, occ, test::add_material(s, black), "occluder");
  Light l;
  l.type = LightType::kPoint;
  l.position = vec3(0, 1.0f, 0);
  l.intensity = Color(10.0f);
  s.lights.push_back(l);
  auto look_down_at = [](float x) {
    Camera c;
    c.position = vec3(x, 0.25f, 0.0f);  // below the occluder
    c.look_at = vec3(x, 0.0f, 0.0f);
    c.up = vec3(0, 0, -1);
    c.fov_y = radians(40.0f);  // sees a 0.18 m wide patch
    return c;
  };
  const int k = 50;
  FilterSettings cone;
  const double b = 1.0 + filter_weight(cone, 1.0f, 1.0f) / (filter_normalization(cone) * (k - 1));
  for (const float x : {0.0f, 2.0f}) {  // umbra (edge at 0.6 m), full light
    std::vector<double> off, seed, skip;
    for (int i = 0; i < kSeeds; ++i) {
      auto run = [&](const char* mode) {
        return image_mean(render("photon",
                                 {{"photons", 100000},
                                  {"caustic_photons", 0},
                                  {"k", k},
                                  {"final_gather", false},
                                  {"shadow_photons", mode}},
                                 s, look_down_at(x), 8, 4, 500 + i));
      };
      off.push_back(run("off"));
      seed.push_back(run("seed"));
      skip.push_back(run("skip"));
    }
    const SeedStats so = seed_stats(off), ss = seed_stats(seed), sk = seed_stats(skip);
    if (x == 0.0f) {
      EXPECT_EQ(so.mean, 0.0);
      EXPECT_EQ(sk.mean, 0.0);
      // Unshadowed radiance f·I·cosθ/r² ≤ (0.5/π)·10 on the patch (r ≥ 1 m).
      const double l0 = 0.5 / kPi * 10.0;
      EXPECT_NEAR(ss.mean, 0.0, kT5 * ss.sd / std::sqrt(ss.n) + l0 * (b - 1.0) + 1e-9)
          << "seed mode in the umbra";
    } else {
      EXPECT_NEAR(ss.mean, so.mean, kT5 * std::sqrt((ss.sd * ss.sd + so.sd * so.sd) / ss.n) + 1e-9);
      EXPECT_NEAR(sk.mean, so.mean, kT5 * std::sqrt((sk.sd * sk.sd + so.sd * so.sd) / sk.n) + 1e-9);
    }
  }
}

// docs/photon-mapping.md, Estimators: "Photons whose stored normal differs from the query
// surface's by more than ~45°, or that lie on the other side, get f_r = 0 (corners, thin
// walls)". A Lambert floor point (normal +y) seen from above, and photons arriving from
// straight above (so the BRDF alone would count them) stored on surfaces turned by θ about
// x: counted up to 45° (cos θ ≥ 0.7, the rule's threshold: 45.6°), ignored from 46° on —
// a wall meeting the floor at a corner is 90°, the far side of a thin wall 180°.
TEST(PhotonShading, PhotonsStoredOnOtherSurfacesAreIgnored) {
  Material lambert;
  lambert.albedo = Color(0.5f);
  const vec3 up(0, 1, 0);
  const Bsdf bsdf(lambert, lambert.albedo, Frame::from_normal(up), up);
  SurfaceInteraction si;
  si.ng = si.ns = up;
  si.shading = Frame::from_normal(up);
  const vec3 wo = glm::normalize(vec3(0.3f, 1.0f, 0.2f));
  for (const float degrees : {0.0f, 30.0f, 45.0f, 46.0f, 60.0f, 90.0f, 135.0f, 180.0f}) {
    Photon ph;
    ph.wi = up;
    ph.power = Color(1.0f);
    const float t = radians(degrees);
    ph.normal = vec3(0.0f, std::cos(t), std::sin(t));
    const Color f = photon_brdf(bsdf, si, wo, ph);
    if (degrees <= 45.0f) {
      EXPECT_NEAR(f.g, 0.5f / kPi, 1e-6f) << degrees << "°: a photon of this surface";
    } else {
      EXPECT_EQ(f.g, 0.0f) << degrees << "°: a photon of another surface";
    }
  }
}

TEST(PhotonTracer, PointLightIrradianceOnAPlane) {
  Light l;
  l.type = LightType::kPoint;
  l.position = vec3(0, 1.0f, 0);
  l.intensity = Color(10.0f);
  check_irradiance_from_photons(l, 1.0f, {0.0f, 0.3f, 0.6f, 1.0f, 1.5f, 2.2f});
}

TEST(PhotonTracer, SpotLightIrradianceOnAPlane) {
  // S004's spot: flux spread uniformly over the cone's solid angle; zero outside.
  Light l;
  l.type = LightType::kSpot;
  l.position = vec3(0, 1.0f, 0);
  l.direction = vec3(0, -1, 0);
  l.cone_half_angle = radians(30.0f);
  l.intensity = Color(10.0f);
  // tan 30° = 0.577: inside, and well outside, the cone's footprint.
  check_irradiance_from_photons(l, 1.0f, {0.0f, 0.2f, 0.4f, 0.8f, 1.2f});
}

TEST(PhotonTracer, NeverCreatesEnergy) {
  // Point light inside a closed sphere of albedo (0.8, 0.3, 0.1): every stored photon has
  // at most the emitted photon's power per channel (roulette by the max component), and the
  // mean total power stored per emitted photon is Φ/(1−a) per channel (each bounce keeps
  // a fraction a in expectation), checked with a z-test over photons.
  Scene s;
  Material m;
  m.albedo = Color(0.8f, 0.3f, 0.1f);
  const int mat = test::add_material(s, m);
  test::add_triangles(s, test::inward_sphere(vec3(0), 1.0f, 16, 32), mat, "sphere");
  Light l;
  l.type = LightType::kPoint;
  l.intensity = Color(1.0f);
  s.lights.push_back(l);
  const RayTracer tracer(s);
  const LightSampler lights(s);
  const float emitted = 4.0f * kPi;
  const int64_t n = 100000;
  PhotonPathSettings path;
  path.max_depth = 1000;
  struct Total {
    Color power;
    float max_seen;
  };
  const std::vector<Total> totals = trace_photons_parallel<Total>(
      lights, n, 3, 2, [&](int64_t, const LightEmission& e, Rng& rng, std::vector<Total>& sink) {
        Total t{Color(0.0f), 0.0f};
        trace_photon_path(
            tracer, e, rng, path,
            [&](const PhotonEvent& ev) {
              t.power += ev.power;
              t.max_seen = std::max(t.max_seen, max_component(ev.power));
              return true;
            },
            [](const PhotonEvent&) {});
        sink.push_back(t);
      });
  ASSERT_EQ(static_cast<int64_t>(totals.size()), n);
  for (int c = 0; c < 3; ++c) {
    double sum = 0, sum2 = 0;
    for (const Total& t : totals) {
      sum += t.power[c];
      sum2 += double(t.power[c]) * t.power[c];
      if (c == 0) {
        ASSERT_LE(t.max_seen, emitted * (1.0f + 1e-5f));
      }
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    const double expected = emitted / (1.0 - m.albedo[c]);
    EXPECT_NEAR(mean, expected, 4.5 * se) << "channel " << c;
  }
}

// What the photons of the distant lights deliver, against closed forms that do not come
// from LightSampler: a lone floor (two-sided Lambert, side 2·half, no other geometry) under
// a sun or a sky. Each photon that reaches the floor counts its flux on the side it arrives
// from. A photon carries its light's whole power Φ (build_photon_maps divides by the count
// later), so over `n` emitted photons (those that miss count zero) the means per photon
// estimate the power the light sends through the scene (its documented Φ: the light's
// radiance over a disk of radius R, R half the diagonal of the scene's bounding box) and the
// power landing on each side of the floor (irradiance × area, whatever R is).
struct DistantLightPower {
  test::RunningStat emitted[3], top[3], bottom[3];
  Color min_emitted{1e30f}, max_emitted{-1e30f};
};

DistantLightPower trace_floor_photons(const Scene& s, int64_t n) {
  const RayTracer tracer(s);
  const LightSampler lights(s);
  struct Record {
    Color emitted, top, bottom;
  };
  const std::vector<Record> records = trace_photons_parallel<Record>(
      lights, n, 21, 5, [&](int64_t, const LightEmission& e, Rng& rng, std::vector<Record>& sink) {
        Record r{e.flux, Color(0.0f), Color(0.0f)};
        trace_photon_path(
            tracer, e, rng, PhotonPathSettings{},
            [&](const PhotonEvent& ev) {
              if (ev.depth == 0) (ev.wi.y > 0.0f ? r.top : r.bottom) += ev.power;
              return false;
            },
            [](const PhotonEvent&) {});
        sink.push_back(r);
      });
  DistantLightPower p;
  for (const Record& r : records)
    for (int c = 0; c < 3; ++c) {
      p.min_emitted[c] = std::min(p.min_emitted[c], r.emitted[c]);
      p.max_emitted[c] = std::max(p.max_emitted[c], r.emitted[c]);
      p.emitted[c].add(r.emitted[c]);
      p.top[c].add(r.top[c]);
      p.bottom[c].add(r.bottom[c]);
    }
  for (int64_t i = static_cast<int64_t>(records.size()); i < n; ++i)  // black samples
    for (int c = 0; c < 3; ++c) {
      p.emitted[c].add(0.0);
      p.top[c].add(0.0);
      p.bottom[c].add(0.0);
    }
  return p;
}

Scene lone_floor(float half) {
  Scene s;
  Material m;
  m.albedo = Color(0.5f);
  // Written out rather than test::floor_quad(): GCC 12 at -O3 reports a false
  // -Wstringop-overflow for its vector insert when inlined here.
  const std::vector<vec3> quad = {{-half, 0, half}, {half, 0, half},  {half, 0, -half},
                                  {-half, 0, half}, {half, 0, -half}, {-half, 0, -half}};
  test::add_triangles(s, quad, test::add_material(s, m), "floor");
  return s;
}

TEST(PhotonTracer, SunPhotonsCarryItsIrradianceThroughTheSceneDisk) {
  // light_sampler.h: a sun of irradiance E emits Φ = E·πR² through a disk of radius R;
  // here R = half · √2 (the floor's bounding box is flat), so every photon carries exactly
  // E·πR² (one light: selection pmf 1). The floor, whole inside that disk's beam, receives
  // E·cosθ·A on its lit side and nothing below (z-test, kZ standard errors of the mean over
  // photons: each photon lands or not, a binomial spread).
  const float half = 1.5f;
  Scene s = lone_floor(half);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.irradiance = Color(3.0f, 2.0f, 1.0f);
  s.lights.push_back(sun);
  const int64_t n = 200000;
  const DistantLightPower p = trace_floor_photons(s, n);
  const double r = half * std::sqrt(2.0), area = 4.0 * half * half;
  const double cos_theta = -sun.direction.y;
  for (int c = 0; c < 3; ++c) {
    const double e = sun.irradiance[c];
    EXPECT_NEAR(p.emitted[c].mean(), e * kPi * r * r, 1e-5 * e * kPi * r * r) << "channel " << c;
    EXPECT_EQ(p.min_emitted[c], p.max_emitted[c]) << "every sun photon carries the same flux";
    EXPECT_NEAR(p.top[c].mean(), e * cos_theta * area, test::kZ * p.top[c].standard_error())
        << "channel " << c;
    EXPECT_EQ(p.bottom[c].mean(), 0.0);
  }
}

// ∫ L dω, ∫ L max(ω_y, 0) dω and ∫ L max(−ω_y, 0) dω over the sphere by the midpoint rule
// in (cos θ, φ) — uniform in solid angle — with 800 × 1600 cells, 50 per texel of the map
// below along each axis: the rule's error on its bilinear texels is far below the photons'.
struct SkyIntegrals {
  Color total{0.0f}, up{0.0f}, down{0.0f};
};
SkyIntegrals sky_integrals(const Environment& env) {
  const int nz = 800, nphi = 1600;
  glm::dvec3 total(0.0), up(0.0), down(0.0);
  for (int i = 0; i < nz; ++i) {
    const double z = -1.0 + 2.0 * (i + 0.5) / nz, rho = std::sqrt(1.0 - z * z);
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nphi;
      const vec3 d(static_cast<float>(rho * std::cos(phi)), static_cast<float>(z),
                   static_cast<float>(rho * std::sin(phi)));
      const glm::dvec3 l(environment_radiance(env, d));
      total += l;
      (z > 0.0 ? up : down) += l * std::abs(z);
    }
  }
  const double cell = 4.0 * kPi / (static_cast<double>(nz) * nphi);
  return {Color(total * cell), Color(up * cell), Color(down * cell)};
}

TEST(PhotonTracer, EnvironmentPhotonsCarryTheSkyThroughTheSceneDisk) {
  // light_sampler.h: an environment emits Φ = πR²·∫L dω through a disk of radius R facing
  // each direction. A constant sky L: every photon carries exactly 4π·L·πR² (uniform
  // directions), and each side of the floor receives π·L·A. A map with a bright patch and a
  // bright band, rotated: the mean photon flux against πR²·∫L dω and the floor's sides
  // against A·∫ L max(±ω_y, 0) dω, all by quadrature of environment_radiance(); z-tests
  // with the spread over photons.
  const float half = 1.5f;
  const double r = half * std::sqrt(2.0), area = 4.0 * half * half, disk = kPi * r * r;
  const int64_t n = 200000;
  {
    Scene s = lone_floor(half);
    Environment sky;
    sky.constant = Color(0.5f, 1.0f, 2.0f);
    sky.scale = 1.5f;
    s.environment = sky;
    const DistantLightPower p = trace_floor_photons(s, n);
    for (int c = 0; c < 3; ++c) {
      const double l = sky.constant[c] * sky.scale;
      EXPECT_NEAR(p.emitted[c].mean(), 4.0 * kPi * l * disk, 1e-5 * 4.0 * kPi * l * disk);
      EXPECT_EQ(p.min_emitted[c], p.max_emitted[c]) << "uniform directions, equal flux";
      EXPECT_NEAR(p.top[c].mean(), kPi * l * area, test::kZ * p.top[c].standard_error())
          << "constant sky, channel " << c;
      EXPECT_NEAR(p.bottom[c].mean(), kPi * l * area, test::kZ * p.bottom[c].standard_error())
          << "constant sky, channel " << c;
    }
  }
  Scene s = lone_floor(half);
  Environment env;
  env.radiance = Image(32, 16, 3, 0.2f);
  for (int y = 5; y < 7; ++y)
    for (int x = 20; x < 23; ++x) env.radiance.set_rgb(x, y, Color(50.0f, 40.0f, 30.0f));
  for (int x = 0; x < 32; ++x) env.radiance.set_rgb(x, 12, Color(1.0f, 3.0f, 6.0f));  // below
  env.scale = 1.5f;
  env.rotation_y = 0.4f;
  s.environment = env;
  const SkyIntegrals sky = sky_integrals(env);
  const DistantLightPower p = trace_floor_photons(s, n);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(p.emitted[c].mean(), disk * sky.total[c], test::kZ * p.emitted[c].standard_error())
        << "map, channel " << c;
    EXPECT_NEAR(p.top[c].mean(), area * sky.up[c], test::kZ * p.top[c].standard_error())
        << "map, channel " << c;
    EXPECT_NEAR(p.bottom[c].mean(), area * sky.down[c], test::kZ * p.bottom[c].standard_error())
        << "map, channel " << c;
  }
}

TEST(PhotonTracer, MapsAreDeterministicForASeedAcrossThreadCounts) {
  const Scene s = furnace_sphere(0.6f);
  const RayTracer tracer(s);
  const LightSampler lights(s);
  PhotonMapSettings ms;
  ms.global_photons = 20000;
  ms.caustic_photons = 0;
  ms.seed = 42;
  std::vector<Photon> one, many;
  {
    ThreadLimit limit(1);
    const PhotonMaps maps = build_photon_maps(tracer, lights, ms);
    one.assign(maps.global.photons().begin(), maps.global.photons().end());
  }
  {
    const PhotonMaps maps = build_photon_maps(tracer, lights, ms);
    many.assign(maps.global.photons().begin(), maps.global.photons().end());
  }
  ASSERT_EQ(one.size(), many.size());
  ASSERT_FALSE(one.empty());
  for (size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i].position, many[i].position) << i;
    ASSERT_EQ(one[i].power, many[i].power) << i;
  }
}

// Fraction of the rim of the disk of radius r around surface point si.p in its tangent
// plane (16 directions) that does not lie on the same flat surface as si.p: the rim point
// is unreachable along the surface (a wall in between), or a short probe down from just
// above it does not land on the same instance, facing the same way, at the probe's height.
// Where the surface around p is convex and flat (every Cornell face), the part of the disk's
// area outside it is at most the rim's: along a direction that leaves the surface within r
// only the sector's outer part is lost, along one that stays on it nothing (16 directions
// estimate the rim's fraction; an edge missed between two of them is a corner of the
// disk of under 1/16 of its rim).
double rim_outside_fraction(const RayTracer& tracer, const SurfaceInteraction& si, float r) {
  const vec3 n = glm::dot(si.ng, si.wo) > 0.0f ? si.ng : -si.ng;
  const Frame f = Frame::from_normal(n);
  const float h = 1e-3f;  // probe height: above the light's 0.1 mm gap under the ceiling
  int outside = 0;
  for (int k = 0; k < 16; ++k) {
    const float phi = 2.0f * kPi * (static_cast<float>(k) + 0.5f) / 16.0f;
    const vec3 step = r * (std::cos(phi) * f.t + std::sin(phi) * f.b);
    const Ray along{si.p + h, step / r, 0.0f, r};
    const Ray probe{si.p + step + h, -n, 0.0f, 2.0f * h};
    Hit hit;
    const bool same = !tracer.occluded(along) && tracer.intersect(probe, &hit) &&
                      hit.instance == si.instance && std::abs(hit.t - h) < 1e-2f * h &&
                      std::abs(glm::dot(tracer.interaction(probe, hit).ng, si.ng)) > 0.9999f;
    outside += !same;
  }
  return outside / 16.0;
}

TEST(SppmIntegrator, AgreesWithThePathTracerOnTheCornellBox) {
  // Region by region (4×4 regions of 8×8 pixels at 32×32) and channel by channel, SPPM's
  // mean over `seeds` renders against the path tracer's: Welch t with Bonferroni over the
  // checks (pixels of one SPPM render share photons, so the spread is taken over seeds, of
  // region means).
  //
  // SPPM's residual bias, added to each region's tolerance: its photon estimate at a visible point
  // averages the photons within radius r ≤ r0 (the radius only shrinks) on surfaces facing the same
  // way, and divides by πr². Where that disk runs off the surface (edges, corners, the rim of the
  // light 0.1 mm under the ceiling) the photons beyond are missing (or, at the light's rim, come
  // from a surface facing the same way under about the same light): an error of at most the
  // fraction of the disk's area off the surface times the photon (k ≥ 2) part of the radiance. Per
  // pixel that fraction is bounded by rim_outside_fraction() averaged over 16 stratified points of
  // the pixel, and the photon part by the path tracer's all − direct (same seeds: the same paths,
  // so the difference is the k ≥ 2 light itself). Measured: 0.06–1.8% of a region's mean over the
  // 16 regions, the most where the box's and the blocks' edges cross them. Away from edges the disk
  // average misses only the second-order r²∇²L/8, which a whole region's mean sees only across the
  // region's boundary; it is not bounded here.
  const Scene s = load_scene("cornell");
  ASSERT_TRUE(s.camera.has_value());
  const int size = 32, seeds = 12, regions = 4, rs = size / regions, checks = regions * regions * 3;
  const float r0 = 0.005f;
  const auto region = [&](int x, int y, int c) {
    return static_cast<size_t>(((y / rs) * regions + x / rs) * 3 + c);
  };
  std::vector<std::vector<double>> path(checks), sppm(checks);
  const auto add_region_means = [&](const Image& img, std::vector<std::vector<double>>& out) {
    std::vector<double> sum(checks, 0.0);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) sum[region(x, y, c)] += img.pixel(x, y)[c];
    for (size_t i = 0; i < sum.size(); ++i) out[i].push_back(sum[i] / (rs * rs));
  };
  test::ImageSeries photon_part;  // the path tracer's k ≥ 2 light per pixel
  for (int seed = 0; seed < seeds; ++seed) {
    const uint64_t path_seed = 300 + static_cast<uint64_t>(seed);
    const Image all = render("path", {{"max_bounces", 64}}, s, *s.camera, size, 16, path_seed);
    const Image direct = render("path", {{"max_bounces", 64}, {"bounces", "direct"}}, s, *s.camera,
                                size, 16, path_seed);
    Image indirect = all;
    for (size_t i = 0; i < indirect.data().size(); ++i) indirect.data()[i] -= direct.data()[i];
    photon_part.add(indirect);
    add_region_means(all, path);
    add_region_means(render("sppm",
                            {{"iterations", 8},
                             {"photons_per_iteration", 20000},
                             {"initial_radius", r0},
                             {"max_depth", 64}},
                            s, *s.camera, size, 1, 400 + static_cast<uint64_t>(seed)),
                     sppm);
  }
  const RayTracer tracer(s);
  std::vector<double> bias_bound(checks, 0.0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      double off = 0.0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const Ray ray =
              s.camera->generate_ray(static_cast<float>(x) + (i + 0.5f) / 4.0f,
                                     static_cast<float>(y) + (j + 0.5f) / 4.0f, size, size);
          Hit hit;
          if (tracer.intersect(ray, &hit))
            off += rim_outside_fraction(tracer, tracer.interaction(ray, hit), r0) / 16.0;
        }
      for (int c = 0; c < 3; ++c)
        bias_bound[region(x, y, c)] +=
            off * std::max(photon_part.mean(x, y, c), 0.0) / static_cast<double>(rs * rs);
    }
  // The 48 regions and, more sensitive to a change everywhere, the whole image per channel
  // (the mean of the regions, its bound the mean of theirs): one family of 51 checks.
  for (int c = 0; c < 3; ++c) {
    std::vector<double> path_image(seeds, 0.0), sppm_image(seeds, 0.0);
    double bound = 0.0;
    for (int r = 0; r < regions * regions; ++r) {
      const size_t i = static_cast<size_t>(r * 3 + c);
      for (int k = 0; k < seeds; ++k) {
        path_image[static_cast<size_t>(k)] += path[i][static_cast<size_t>(k)] / (regions * regions);
        sppm_image[static_cast<size_t>(k)] += sppm[i][static_cast<size_t>(k)] / (regions * regions);
      }
      bound += bias_bound[i] / (regions * regions);
    }
    path.push_back(path_image);
    sppm.push_back(sppm_image);
    bias_bound.push_back(bound);
  }
  double worst_z = 0.0, worst_bound = 0.0;
  for (size_t i = 0; i < path.size(); ++i) {
    const SeedStats p = seed_stats(path[i]), q = seed_stats(sppm[i]);
    const double vp = p.sd * p.sd / p.n, vq = q.sd * q.sd / q.n;
    const double se = std::sqrt(vp + vq);
    const double crit =
        test::family_t(static_cast<int>(path.size()), test::welch_dof(vp, p.n, vq, q.n));
    const std::string what = i < static_cast<size_t>(checks) ? "region " + std::to_string(i / 3)
                                                             : std::string("whole image");
    EXPECT_NEAR(q.mean, p.mean, crit * se + bias_bound[i])
        << what << " channel " << i % 3 << ": path " << p.mean << " ± " << p.sd << ", sppm "
        << q.mean << " ± " << q.sd << " (sd over seeds), bias bound " << bias_bound[i];
    worst_z = std::max(worst_z, std::abs(q.mean - p.mean) / se);
    worst_bound = std::max(worst_bound, bias_bound[i] / p.mean);
  }
  std::printf("largest |sppm − path| %.2f standard errors; largest bias bound %.1f%% of a region\n",
              worst_z, 100.0 * worst_bound);
}

TEST(PhotonShading, DirectLightingMatchesTheAreaLightIntegral) {
  // Cornell light (0.13 × 0.105 m at y = 0.5487, Le = (17, 12, 4)) seen from floor points,
  // without the shadow ray: E = Le ∫ cosθ·cosθ'/d² dA (midpoint rule, 400² cells; its error
  // is far below the Monte Carlo tolerance), L = f·E. z-test with the samples' variance.
  const Scene s = load_scene("cornell");
  const RayTracer tracer(s);
  const LightSampler lights(s);
  for (vec3 p0 : {vec3(0.278f, 0.3f, 0.28f), vec3(0.1f, 0.3f, 0.1f), vec3(0.45f, 0.3f, 0.5f)}) {
    Ray ray{p0, vec3(0, -1, 0)};
    Hit hit;
    ASSERT_TRUE(tracer.intersect(ray, &hit));
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    ASSERT_NEAR(si.p.y, 0.0f, 1e-4f);
    const Bsdf bsdf(s, si);
    Rng rng(1, 2);
    double sum = 0, sum2 = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
      const double v = photon_direct_lighting(tracer, lights, si, bsdf, si.wo, rng.next_float(),
                                              vec2(rng.next_float(), rng.next_float()), false)
                           .g;
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    double e = 0;
    const int m = 400;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const vec3 q(0.213f + (i + 0.5f) * 0.13f / m, 0.5487f, 0.227f + (j + 0.5f) * 0.105f / m);
        const vec3 d = q - si.p;
        const double d2 = glm::dot(d, d);
        const double c = d.y / std::sqrt(d2);
        e += c * c / d2 * (0.13 * 0.105 / (m * m));
      }
    const double expect = 12.0 * e * bsdf.eval(si.wo, vec3(0, 1, 0)).g;
    EXPECT_NEAR(mean, expect, 4.5 * se) << "at " << si.p.x << ", " << si.p.z;
  }
}

TEST(PhotonIntegrators, BadParametersAreErrors) {
  auto create = [](const std::string& name, const nlohmann::json& j) {
    return Integrator::create(name, params(j));
  };
  EXPECT_THROW(create("photon", {{"radius", -1.0}}), Error);
  EXPECT_THROW(create("photon", {{"photons", 0}}), Error);
  EXPECT_THROW(create("photon", {{"k", -3}}), Error);
  EXPECT_THROW(create("photon", {{"filter", "box"}}), Error);
  EXPECT_THROW(create("photon", {{"shadow_photons", "maybe"}}), Error);
  EXPECT_THROW(create("photon", {{"gather_rays", 0}}), Error);
  EXPECT_THROW(create("sppm", {{"alpha", 1.0}}), Error);
  EXPECT_THROW(create("sppm", {{"alpha", 0.0}}), Error);
  EXPECT_THROW(create("sppm", {{"initial_radius", -0.1}}), Error);
  EXPECT_THROW(create("sppm", {{"photons_per_iteration", 0}}), Error);
  EXPECT_THROW(create("sppm", {{"iterations", 0}}), Error);
  EXPECT_THROW(create("sppm", {{"photon_count", 5}}), Error);  // unknown key
  try {
    create("sppm", {{"alpha", 2.0}});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("alpha"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(create("photon", {{"filter", "gaussian"}, {"k", 0}, {"radius", 0.1}}));
  EXPECT_NO_THROW(create("sppm", {{"alpha", 0.5}}));
}

}  // namespace
}  // namespace illum
