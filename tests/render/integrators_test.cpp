// Integrators on procedural scenes with known answers: the white furnace, analytic
// irradiance from point and spot lights, Whitted against the path tracer's direct mode,
// the bounce decomposition, energy bounds, determinism and option validation.
// Statistical checks use kZ standard errors estimated from the images themselves (every
// pixel is an independent estimate: its own scrambled Sobol' sequence).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/core/rng.h"
#include "illum/core/sampling.h"
#include "illum/render/integrator.h"
#include "illum/render/path_integrator.h"
#include "illum/render/render_setup.h"
#include "illum/render/sppm.h"
#include "illum/render/tile_renderer.h"
#include "illum/scene/environment.h"
#include "illum/trace/ray_tracer.h"
#include "pixel_statistics.h"
#include "render_test_scenes.h"

namespace illum {
namespace {

constexpr double kZ = 5.0;

Params params(const nlohmann::json& j) {
  return Params(j, "--param");
}

Image render(const std::string& name, const nlohmann::json& p, const Scene& scene,
             const Camera& cam, int size, int spp, uint64_t seed = 1, int threads = 0) {
  const RayTracer tracer(scene);
  RenderOptions o;
  o.width = o.height = size;
  o.spp = spp;
  o.seed = seed;
  o.threads = threads;
  o.progress = false;
  return Integrator::create(name, params(p))->render(tracer, cam, o);
}

struct PixelStats {
  double mean = 0, err = 0;  // mean over pixels and its standard error
};
PixelStats pixel_stats(const Image& img, int channel = 1) {
  double s = 0, s2 = 0;
  const double n = static_cast<double>(img.pixel_count());
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const double v = img.pixel(x, y)[channel];
      s += v;
      s2 += v * v;
    }
  const double m = s / n;
  return {m, std::sqrt(std::max(s2 / n - m * m, 0.0) / n)};
}

TEST(PathIntegrator, WhiteFurnaceSphere) {
  // Camera inside a closed Lambert sphere of albedo a emitting Le everywhere: L = Le/(1−a).
  for (const float a : {0.0f, 0.5f, 0.8f}) {
    const Scene s = test::furnace_sphere(a, 12, 24);
    Camera cam;
    cam.position = vec3(0.1f, -0.2f, 0.05f);
    cam.look_at = vec3(1, 0.3f, 0.2f);
    cam.fov_y = radians(90.0f);
    const Image img = render("path", {{"max_bounces", 1000}}, s, cam, 24, 8);
    const PixelStats st = pixel_stats(img);
    const double expected = 1.0 / (1.0 - a);
    // 1e-4: float rounding of the samples' sums (a path of n vertices adds n terms, each
    // off by 2⁻²⁴ of the sum at most; 1e-4 covers paths of 1600), needed at a = 0, where
    // every sample is exactly Le and the standard error is zero.
    EXPECT_NEAR(st.mean, expected, kZ * st.err + 1e-4 * expected) << "albedo " << a;
  }
}

// A camera looking straight down at the y = 0 plane.
Camera top_camera() {
  Camera cam;
  cam.position = vec3(0.0f, 3.0f, 0.0f);
  cam.look_at = vec3(0.0f);
  cam.up = vec3(0.0f, 0.0f, -1.0f);
  cam.fov_y = radians(70.0f);
  return cam;
}

TEST(PathIntegrator, PlaneUnderEnvironmentMap) {
  // A Lambert plane under an environment: every point sees the whole upper hemisphere, so
  // L = a/π ∫ L_env cos θ dω — computed here independently by uniform hemisphere sampling.
  // Exercises environment importance sampling, BSDF sampling and their MIS weights.
  const float a = 0.7f;
  Scene s;
  Material m;
  m.albedo = Color(a);
  test::add_triangles(s, test::floor_quad(10.0f), test::add_material(s, m), "floor");
  Environment env;
  env.radiance = Image(32, 16, 3, 0.3f);
  for (int y = 3; y < 5; ++y) {
    for (int x = 8; x < 11; ++x) env.radiance.set_rgb(x, y, Color(40.0f));
  }
  env.rotation_y = 0.3f;
  s.environment = env;
  // Midpoint quadrature over (cos θ, φ) — uniform in solid angle. Halving its cells moves
  // the result by 3e-7 (relative), far below the render's standard error (~1%); the
  // tolerance keeps 1e-5 of the expected value for that and float rounding.
  double sum = 0;
  const int nz = 800, nphi = 1600;
  for (int i = 0; i < nz; ++i) {
    const float z = (static_cast<float>(i) + 0.5f) / nz, r = std::sqrt(1.0f - z * z);
    for (int j = 0; j < nphi; ++j) {
      const float phi = 2.0f * kPi * (static_cast<float>(j) + 0.5f) / nphi;
      sum +=
          environment_radiance(*s.environment, vec3(r * std::cos(phi), z, r * std::sin(phi))).g * z;
    }
  }
  const double expected = a / std::numbers::pi * sum * (2.0 * std::numbers::pi) / (nz * nphi);
  const Image img = render("path", {{"max_bounces", 4}}, s, top_camera(), 24, 8);
  const PixelStats st = pixel_stats(img);
  EXPECT_NEAR(st.mean, expected, kZ * st.err + 1e-5 * expected);
}

// Range of the analytic radiance over a pixel's footprint (a 7×7 grid across it): the
// pixel's mean over jittered samples must lie within it.
template <typename Fn>
std::pair<double, double> footprint_range(const Camera& cam, int x, int y, int size,
                                          Fn&& radiance) {
  double lo = 1e30, hi = -1e30;
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 6; ++i) {
      const Ray r =
          cam.generate_ray(static_cast<float>(x) + static_cast<float>(i) / 6.0f,
                           static_cast<float>(y) + static_cast<float>(j) / 6.0f, size, size);
      const float t = -r.origin.y / r.direction.y;
      const vec3 p = r.origin + t * r.direction;
      const double v = radiance(p);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  return {lo, hi};
}

Scene plane_scene(float albedo) {
  Scene s;
  s.name = "plane";
  Material m;
  m.albedo = Color(albedo);
  test::add_triangles(s, test::floor_quad(10.0f), test::add_material(s, m), "floor");
  return s;
}

TEST(DirectLighting, PointLightIrradianceOnPlane) {
  const float rho = 0.6f, intensity = 2.0f;
  Scene s = plane_scene(rho);
  Light l;
  l.type = LightType::kPoint;
  l.position = vec3(0.3f, 1.0f, -0.2f);
  l.intensity = Color(intensity);
  s.lights.push_back(l);
  const Camera cam = top_camera();
  const int size = 24;
  auto analytic = [&](const vec3& p) {  // L = ρ/π · I cosθ / r²
    const vec3 d = l.position - p;
    const double r2 = glm::dot(d, d);
    return rho / std::numbers::pi * intensity * (d.y / std::sqrt(r2)) / r2;
  };
  for (const char* integrator : {"whitted", "path"}) {
    const nlohmann::json p = std::string(integrator) == "path"
                                 ? nlohmann::json{{"bounces", "direct"}}
                                 : nlohmann::json::object();
    const Image img = render(integrator, p, s, cam, size, 4);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const auto [lo, hi] = footprint_range(cam, x, y, size, analytic);
        const double v = img.pixel(x, y)[1];
        ASSERT_GE(v, lo * (1 - 1e-4)) << integrator << " pixel " << x << "," << y;
        ASSERT_LE(v, hi * (1 + 1e-4)) << integrator << " pixel " << x << "," << y;
      }
  }
}

TEST(DirectLighting, SpotLightIsZeroOutsideItsCone) {
  const float rho = 0.5f, flux = 100.0f, half = radians(25.0f);
  Scene s = plane_scene(rho);
  Light l;
  l.type = LightType::kSpot;
  l.position = vec3(0.2f, 1.5f, 0.1f);
  l.direction = glm::normalize(vec3(0.1f, -1.0f, 0.0f));
  l.cone_half_angle = half;
  l.intensity = Color(flux / l.cone_solid_angle());
  s.lights.push_back(l);
  const Camera cam = top_camera();
  const int size = 32;
  const double omega = 2.0 * std::numbers::pi * (1.0 - std::cos(half));
  auto inside = [&](const vec3& p) {
    return glm::dot(glm::normalize(p - l.position), l.direction) > l.cos_cutoff();
  };
  auto analytic = [&](const vec3& p) {  // S004: E = Φ cosθ / (Ω r²), zero outside
    if (!inside(p)) return 0.0;
    const vec3 d = l.position - p;
    const double r2 = glm::dot(d, d);
    return rho / std::numbers::pi * flux * (d.y / std::sqrt(r2)) / (omega * r2);
  };
  for (const char* integrator : {"whitted", "path"}) {
    const nlohmann::json p = std::string(integrator) == "path"
                                 ? nlohmann::json{{"bounces", "direct"}}
                                 : nlohmann::json::object();
    const Image img = render(integrator, p, s, cam, size, 4);
    int lit = 0, dark = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const auto [lo, hi] = footprint_range(cam, x, y, size, analytic);
        const double v = img.pixel(x, y)[1];
        if (hi == 0.0) {
          ASSERT_EQ(v, 0.0) << integrator << " pixel " << x << "," << y << " is outside the cone";
          ++dark;
        } else if (lo > 0.0) {
          ASSERT_GE(v, lo * (1 - 1e-4)) << integrator;
          ASSERT_LE(v, hi * (1 + 1e-4)) << integrator;
          ++lit;
        }
      }
    EXPECT_GT(lit, 20);
    EXPECT_GT(dark, 20);
  }
}

TEST(Specular, GlassSlabTransmitsFresnelSquared) {
  // Looking straight down through a horizontal glass slab (index η = 1.5, thickness t) at a
  // lit plane: the slab passes T² of the radiance straight through and T²R² after one
  // internal round trip, T = 1 − R, R = ((η−1)/(η+1))² at normal incidence; the 1/η²
  // entering and η² leaving cancel. It also moves the image: a ray at angle α reaches the
  // plane where, without the slab, a camera t(1 − 1/η) lower would see it (t(3/η − 1)
  // higher after a round trip), to first order in α. So the reference is the bare plane
  // seen from those two heights, weighted T² and T²R², with the same pixel samples.
  // Whitted traces both lobes deterministically; the path tracer picks one at random and
  // must agree on average. What the reference leaves out, at α ≤ 2.83° (the corner of the
  // 4° view): the third-order displacement, ≤ 4.5e-6 m, against an irradiance changing by
  // ≤ 1.6 per metre (relative) over the patch: ≤ 7e-6; Fresnel's change with angle, ≤ 2e-7;
  // the R⁴ term the path tracer adds, 2.6e-6. Tolerance 2e-5 (plus the path tracer's kZ
  // standard errors).
  const float eta = 1.5f, thickness = 0.2f;
  Scene bare = plane_scene(0.8f);
  Light l;
  l.type = LightType::kPoint;
  l.position = vec3(0.0f, 0.5f, 0.0f);  // under the slab: the slab casts no shadow
  l.intensity = Color(1.0f);
  bare.lights.push_back(l);
  Scene glass = bare;
  Material m;
  m.type = MaterialType::kDielectric;
  m.ior = eta;
  test::add_triangles(glass, test::inward_box({-3, 1.0f, -3}, {3, 1.0f + thickness, 3}, false),
                      test::add_material(glass, m), "slab");
  Camera cam = top_camera();
  cam.fov_y = radians(4.0f);  // nearly normal incidence everywhere
  const auto raised = [&](float dy) {
    Camera c = cam;
    c.position.y += dy;
    c.look_at.y += dy;
    return c;
  };
  const double r = std::pow((eta - 1.0) / (eta + 1.0), 2.0), t2 = (1 - r) * (1 - r);
  const double straight = pixel_stats(render("whitted", nlohmann::json::object(), bare,
                                             raised(-thickness * (1.0f - 1.0f / eta)), 16, 4))
                              .mean;
  const double round_trip = pixel_stats(render("whitted", nlohmann::json::object(), bare,
                                               raised(thickness * (3.0f / eta - 1.0f)), 16, 4))
                                .mean;
  const double expected = t2 * (straight + r * r * round_trip);
  const PixelStats sw = pixel_stats(render("whitted", nlohmann::json::object(), glass, cam, 16, 4));
  const PixelStats sp = pixel_stats(render("path", {{"bounces", "direct"}}, glass, cam, 16, 64));
  EXPECT_NEAR(sw.mean / expected, 1.0, 2e-5);
  EXPECT_NEAR(sp.mean / expected, 1.0, kZ * sp.err / expected + 2e-5);
}

// Point straight below the centre of a parallel a×b rectangle at distance c: irradiance
// π·L·F, F = 4 × the corner form factor (standard closed form).
double rect_irradiance_below_centre(double le, double a, double b, double c) {
  const double x = 0.5 * a / c, y = 0.5 * b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  const double f =
      (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * std::numbers::pi);
  return std::numbers::pi * le * 4.0 * f;
}

TEST(DirectLighting, NearbyAreaLightDoesNotShadowItself) {
  // A small emitter 0.4 m above a plane (scene smaller than 1 m, so ray offsets are 1e-4 m
  // absolute): shadow rays must reach the emitter without hitting it early. A narrow camera
  // under the light sees only the plane right below its centre.
  const float rho = 0.5f, le = 3.0f, a = 0.2f, b = 0.1f, h = 0.4f;
  Scene s = plane_scene(rho);
  s.meshes[0].positions = test::floor_quad(0.45f);
  Material m;
  m.emission = Color(le);
  std::vector<vec3> quad;
  test::push_quad(quad, {-a / 2, h, -b / 2}, {a / 2, h, -b / 2}, {a / 2, h, b / 2},
                  {-a / 2, h, b / 2});
  s.lights.push_back(
      test::area_light(test::add_triangles(s, quad, test::add_material(s, m), "light")));
  Camera cam = top_camera();
  cam.position = vec3(0.0f, 0.3f, 0.0f);
  cam.fov_y = radians(1.0f);
  const double expected = rho / std::numbers::pi * rect_irradiance_below_centre(le, a, b, h);
  // The camera sees ±2.6 mm around the centre, where E is lower than at the centre by at
  // most 1.6e-4 of it (at the corners; midpoint quadrature of the emitter): 2e-4 allowed.
  for (const char* integrator : {"path", "whitted"}) {
    const nlohmann::json p = std::string(integrator) == "path"
                                 ? nlohmann::json{{"bounces", "direct"}}
                                 : nlohmann::json::object();
    const PixelStats st = pixel_stats(render(integrator, p, s, cam, 16, 16));
    EXPECT_NEAR(st.mean, expected, kZ * st.err + 2e-4 * expected) << integrator;
  }
}

Scene occluded_scene() {
  Scene s = plane_scene(0.7f);
  Material m;
  m.albedo = Color(0.4f, 0.5f, 0.6f);
  test::add_triangles(s, test::inward_box({-0.3f, 0.4f, -0.3f}, {0.2f, 0.7f, 0.1f}, false),
                      test::add_material(s, m), "box");
  Light a;
  a.type = LightType::kPoint;
  a.position = vec3(0.5f, 1.5f, 0.2f);
  a.intensity = Color(3.0f, 2.0f, 1.0f);
  Light b = a;
  b.position = vec3(-1.0f, 1.0f, -0.5f);
  b.intensity = Color(1.0f, 1.5f, 2.0f);
  s.lights = {a, b};
  return s;
}

TEST(DirectLighting, WhittedMatchesPathDirectForPointLights) {
  const Scene s = occluded_scene();
  Camera cam;
  cam.position = vec3(1.5f, 2.0f, 2.5f);
  cam.look_at = vec3(0.0f, 0.3f, 0.0f);
  const Image w = render("whitted", nlohmann::json::object(), s, cam, 32, 8);
  const Image p = render("path", {{"bounces", "direct"}}, s, cam, 32, 8);
  for (int c = 0; c < 3; ++c) {
    // Paired per-pixel differences: their mean must be zero within its standard error.
    double sd = 0, sd2 = 0, sw = 0;
    const double n = static_cast<double>(w.pixel_count());
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const double d = p.pixel(x, y)[c] - w.pixel(x, y)[c];
        sd += d;
        sd2 += d * d;
        sw += w.pixel(x, y)[c];
      }
    const double mean = sd / n, err = std::sqrt(std::max(sd2 / n - mean * mean, 0.0) / n);
    // 1e-5 of the mean: float rounding of the two sums (the path tracer's choice between the
    // two lights keeps err well above it).
    EXPECT_LE(std::abs(mean), kZ * err + 1e-5 * sw / n) << "channel " << c;
    EXPECT_GT(sw, 0.0);
  }
}

TEST(Whitted, ShadowsOffReproducesTheUnshadowedSeedImage) {
  // shadows=false (S004's first image) lights every surface point as if nothing occluded
  // the lights: never darker than with shadows, brighter where the box casts its shadow,
  // and on the plane exactly the analytic unshadowed sum of the point lights.
  const Scene s = occluded_scene();
  const Camera cam = top_camera();
  const int size = 24;
  const Image on = render("whitted", nlohmann::json::object(), s, cam, size, 4);
  const Image off = render("whitted", {{"shadows", false}}, s, cam, size, 4);
  int brighter = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      ASSERT_GE(off.pixel(x, y)[1], on.pixel(x, y)[1]);
      brighter += off.pixel(x, y)[1] > on.pixel(x, y)[1] * 1.01f;
    }
  }
  EXPECT_GT(brighter, 5);
  // A pixel whose footprint lies on the plane in the box's shadow region is still bounded
  // by the analytic unshadowed value.
  auto analytic = [&](const vec3& p) {
    double l = 0;
    for (const Light& light : s.lights) {
      const vec3 d = light.position - p;
      const double r2 = glm::dot(d, d);
      l += 0.7 / std::numbers::pi * light.intensity.g * (d.y / std::sqrt(r2)) / r2;
    }
    return l;
  };
  const auto [lo, hi] = footprint_range(cam, 0, 0, size, analytic);  // a corner: plane only
  EXPECT_GE(off.pixel(0, 0)[1], lo * (1 - 1e-4));
  EXPECT_LE(off.pixel(0, 0)[1], hi * (1 + 1e-4));
}

// A closed box [−1, 1]³ of Lambert albedo `albedo` with a square emitter of radiance `le`
// and half-side `half` just below the ceiling, facing down.
Scene closed_box(float albedo, float le, float half = 0.3f) {
  Scene s;
  s.name = "closed-box";
  Material wall;
  wall.albedo = Color(albedo);
  test::add_triangles(s, test::inward_box(vec3(-1), vec3(1)), test::add_material(s, wall), "walls");
  Material emitter = wall;
  emitter.emission = Color(le);
  std::vector<vec3> quad;  // just below the ceiling, facing down
  test::push_quad(quad, {-half, 0.99f, -half}, {half, 0.99f, -half}, {half, 0.99f, half},
                  {-half, 0.99f, half});
  s.lights.push_back(
      test::area_light(test::add_triangles(s, quad, test::add_material(s, emitter), "light")));
  return s;
}

Camera box_camera() {
  Camera cam;
  cam.position = vec3(0.0f, 0.0f, 0.95f);
  cam.look_at = vec3(0.0f, 0.0f, -1.0f);
  cam.fov_y = radians(80.0f);
  return cam;
}

TEST(PathIntegrator, BounceModesPartitionTwoBouncePaths) {
  // With max_bounces = 2 and only diffuse surfaces, "all" holds exactly the paths with at
  // most 2 diffuse vertices: direct (k ≤ 1) + indirect1 (k = 2). Checked pixel by pixel on
  // paired differences d = all − direct − indirect1: each seed renders all three modes, so
  // d's mean over the seeds and its standard error come from the same paths. The modes draw
  // the same sampler dimensions in the same order (path_radiance.cpp), so d is zero up to
  // float rounding and its standard error tiny; the rounding allowance is 2⁻²⁰ (16 float
  // ulps: ≤ 5 terms per sample, 4 samples per pixel, one scaling) of all + direct + indirect1.
  // Were the streams ever to diverge, the same check is an ordinary paired t-test.
  const Scene s = closed_box(0.6f, 4.0f);
  const Camera cam = box_camera();
  const int size = 24, seeds = 16, spp = 4;
  test::ImageSeries d, all_series, ind_series;
  std::vector<double> magnitude(static_cast<size_t>(size) * size);
  for (int k = 0; k < seeds; ++k) {
    const uint64_t seed = 3 + static_cast<uint64_t>(k);
    const Image all = render("path", {{"max_bounces", 2}}, s, cam, size, spp, seed);
    const Image direct =
        render("path", {{"max_bounces", 2}, {"bounces", "direct"}}, s, cam, size, spp, seed);
    const Image ind =
        render("path", {{"max_bounces", 2}, {"bounces", "indirect1"}}, s, cam, size, spp, seed);
    Image diff(size, size, 3);
    for (size_t i = 0; i < diff.data().size(); ++i) {
      diff.data()[i] = all.data()[i] - direct.data()[i] - ind.data()[i];
      if (i % 3 == 1) magnitude[i / 3] += all.data()[i] + direct.data()[i] + ind.data()[i];
    }
    d.add(diff);
    all_series.add(all);
    ind_series.add(ind);
  }
  const int checks = size * size * 3;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) {
        const double tol =
            test::family_t(checks, seeds - 1) * std::sqrt(d.variance_of_mean(x, y, c)) +
            0x1p-20 * magnitude[static_cast<size_t>(y) * size + x] / seeds;
        ASSERT_LE(std::abs(d.mean(x, y, c)), tol) << "pixel " << x << "," << y << " channel " << c;
      }
  // Every pixel sees light that bounced once (a closed box), and with unlimited bounces
  // "all" carries more light than the two-bounce subset: over the image, by many standard
  // errors of the seeds' means.
  double ind_sum = 0, ind_var = 0, all_sum = 0, all_var = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      EXPECT_GT(ind_series.mean(x, y, 1), 0.0) << x << "," << y;
      ind_sum += ind_series.mean(x, y, 1);
      ind_var += ind_series.variance_of_mean(x, y, 1);
      all_sum += all_series.mean(x, y, 1);
      all_var += all_series.variance_of_mean(x, y, 1);
    }
  test::ImageSeries full;
  for (int k = 0; k < seeds; ++k)
    full.add(render("path", nlohmann::json::object(), s, cam, size, spp,
                    100 + static_cast<uint64_t>(k)));
  double full_sum = 0, full_var = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      full_sum += full.mean(x, y, 1);
      full_var += full.variance_of_mean(x, y, 1);
    }
  EXPECT_GT(ind_sum, test::family_t(1, seeds - 1) * std::sqrt(ind_var));
  EXPECT_GT(full_sum - all_sum, test::family_t(1, seeds - 1) * std::sqrt(full_var + all_var));
}

// One sample of the obviously correct estimator the path tracer is checked against in a
// closed Lambert box of uniform albedo a: cosine-sampled bounces (weight a each) continued
// with probability a, so a sample is the plain sum of the front-face emission its path
// finds. No light sampling, no MIS, no roulette weights: nothing of the code under test
// beyond casting rays and the camera.
double reference_radiance(const RayTracer& tracer, Ray ray, float albedo, Rng& rng) {
  const Scene& s = tracer.scene();
  double l = 0.0;
  for (;;) {
    Hit hit;
    if (!tracer.intersect(ray, &hit)) return l;
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    const bool front = glm::dot(si.ng, ray.direction) < 0.0f;
    if (front) l += s.materials[static_cast<size_t>(si.material)].emission.g;
    if (rng.next_float() >= albedo) return l;
    const vec3 n = front ? si.ng : -si.ng;
    const vec3 wi = Frame::from_normal(n).to_world(
        sample_cosine_hemisphere(vec2(rng.next_float(), rng.next_float())));
    ray = Ray{offset_ray_origin(si.p, si.ng, wi), wi};
  }
}

TEST(PathIntegrator, NeverCreatesEnergyInAClosedBox) {
  // Each pixel of the path tracer against an independent estimate of the same pixel
  // (reference_radiance, jittered over the pixel as the renderer's box filter is): the path
  // tracer may not exceed it by more than the family-wise critical value of their combined
  // standard error (one-sided: no pixel gains energy), and over the whole image the two
  // must agree (two-sided). Variances per pixel: the reference's from its own samples, the
  // path tracer's from `seeds` independent renders; Welch–Satterthwaite degrees of freedom.
  // The emitter is large (1.6 m square) so that the reference's plain BSDF sampling finds it
  // often: with these counts a uniform 1.3× gain exceeds the per-pixel bound in about a
  // quarter of the pixels and the whole-image bound by ~90 standard errors. max_bounces = 64 drops
  // paths the reference keeps, a fraction a^64 ≈ 1e-10 of the light.
  const float a = 0.7f, le = 5.0f;
  const Scene s = closed_box(a, le, 0.8f);
  const Camera cam = box_camera();
  const int size = 16, seeds = 32, spp = 8, ref_samples = 2048;
  test::ImageSeries path;
  for (int k = 0; k < seeds; ++k)
    path.add(
        render("path", {{"max_bounces", 64}}, s, cam, size, spp, 100 + static_cast<uint64_t>(k)));
  const RayTracer tracer(s);
  const int pixels = size * size;
  std::vector<double> ref_mean(pixels), ref_var(pixels);  // ref_var: variance of the mean
  parallel_for(
      pixels,
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
          const int x = static_cast<int>(i % size), y = static_cast<int>(i / size);
          Rng rng(77, static_cast<uint64_t>(i));
          double sum = 0, sum2 = 0;
          for (int k = 0; k < ref_samples; ++k) {
            const Ray ray = cam.generate_ray(static_cast<float>(x) + rng.next_float(),
                                             static_cast<float>(y) + rng.next_float(), size, size);
            const double v = reference_radiance(tracer, ray, a, rng);
            sum += v;
            sum2 += v * v;
          }
          const double m = sum / ref_samples;
          ref_mean[static_cast<size_t>(i)] = m;
          ref_var[static_cast<size_t>(i)] =
              std::max(sum2 - ref_samples * m * m, 0.0) / (double(ref_samples) * (ref_samples - 1));
        }
      },
      1);
  double diff_sum = 0, var_sum = 0, dof_den = 0, worst = -1e30;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const size_t i = static_cast<size_t>(y) * size + x;
      const double p = path.mean(x, y, 1), vp = path.variance_of_mean(x, y, 1);
      const double se = std::sqrt(vp + ref_var[i]);
      const double crit = test::student_t_quantile(
          test::kFamilyFalseAlarm / pixels, test::welch_dof(vp, seeds, ref_var[i], ref_samples));
      EXPECT_LE(p - ref_mean[i], crit * se) << "pixel " << x << "," << y << ": path " << p
                                            << ", reference " << ref_mean[i] << " ± " << se;
      worst = std::max(worst, (p - ref_mean[i]) / se);
      diff_sum += p - ref_mean[i];
      var_sum += vp + ref_var[i];
      dof_den += vp * vp / (seeds - 1) + ref_var[i] * ref_var[i] / (ref_samples - 1);
    }
  const double mean_diff = diff_sum / pixels, mean_se = std::sqrt(var_sum) / pixels;
  std::printf("largest per-pixel excess %.2f standard errors; image mean difference %.5f ± %.5f\n",
              worst, mean_diff, mean_se);
  EXPECT_NEAR(mean_diff, 0.0, test::family_t(1, var_sum * var_sum / dof_den) * mean_se);
}

TEST(Integrators, ByteIdenticalForOneTwoAndFourThreads) {
  // render/README.md: a pixel depends only on (seed, x, y, samples), never on the thread
  // that ran it, so every integrator must give the same bytes for 1, 2 and 4 threads (on a
  // machine with fewer cores, 4 threads run as many as there are). The box holds a glass
  // and a mirror block so that Whitted recursion, caustic photons and SPPM's delta chains
  // run too; 40×40 pixels are 9 tiles, and 10000 photons are three blocks of the tracer.
  Scene s = closed_box(0.6f, 4.0f);
  Material glass;
  glass.type = MaterialType::kDielectric;
  glass.ior = 1.5f;
  test::add_triangles(s, test::inward_box({-0.6f, -1.0f, -0.6f}, {-0.1f, -0.4f, -0.1f}, false),
                      test::add_material(s, glass), "glass");
  Material mirror;
  mirror.type = MaterialType::kMirror;
  mirror.specular = Color(0.9f);
  test::add_triangles(s, test::inward_box({0.2f, -1.0f, -0.8f}, {0.7f, 0.2f, -0.3f}, false),
                      test::add_material(s, mirror), "mirror");
  const Camera cam = box_camera();
  for (const std::string& name : Integrator::names()) {
    nlohmann::json p = nlohmann::json::object();
    if (name == "photon")
      p = {{"photons", 10000}, {"caustic_photons", 10000}, {"k", 20}, {"gather_rays", 1}};
    if (name == "sppm") p = {{"iterations", 2}, {"photons_per_iteration", 10000}};
    const Image one = render(name, p, s, cam, 40, 4, 42, 1);
    for (const int threads : {2, 4}) {
      EXPECT_TRUE(test::identical_bytes(one, render(name, p, s, cam, 40, 4, 42, threads)))
          << name << ": 1 and " << threads << " threads differ";
    }
    EXPECT_TRUE(test::identical_bytes(one, render(name, p, s, cam, 40, 4, 42, 1)))
        << name << ": two 1-thread renders differ";
    if (name == "path" || name == "photon" || name == "sppm") {
      EXPECT_FALSE(test::identical_bytes(one, render(name, p, s, cam, 40, 4, 43, 2)))
          << name << ": another seed must give another image";
    }
  }
}

TEST(Integrators, TileLoopHonoursTheThreadCount) {
  // The determinism check above only means something if the thread counts are real: the
  // shared pixel loop must run on exactly one thread when asked to, and on no more than it
  // was given otherwise — and, on a machine with two or more cores, really on two (a
  // render of 4 tiles × ~10 ms; up to five tries, so a worker the operating system wakes
  // late on a busy machine does not fail the test).
  const Camera cam = box_camera();
  for (const int threads : {1, 2}) {
    std::set<std::thread::id> ids;
    for (int attempt = 0; attempt < 5; ++attempt) {
      std::mutex mutex;
      std::set<std::thread::id> seen;
      RenderOptions o;
      o.width = o.height = 32;  // 4 tiles
      o.spp = 1;
      o.threads = threads;
      o.progress = false;
      render_tiles(cam, o, "threads", [&](const Ray&, SobolSampler&) {
        {
          std::lock_guard lock(mutex);
          seen.insert(std::this_thread::get_id());
        }
        std::this_thread::sleep_for(std::chrono::microseconds(20));
        return Color(0.0f);
      });
      EXPECT_LE(seen.size(), static_cast<size_t>(threads)) << threads << " threads asked for";
      ids = seen;
      if (ids.size() == static_cast<size_t>(threads)) break;
    }
    if (threads == 1 || ThreadLimit::hardware_threads() >= 2) {
      EXPECT_EQ(ids.size(), static_cast<size_t>(threads)) << threads << " threads asked for";
    }
  }
}

TEST(PathIntegrator, StopsAtTheTimeBudget) {
  // render/README.md: with a time budget the render stops after the first pass that ends
  // past it, so it runs at least the budget and overruns it by at most that one pass, whose
  // size the pass schedule (1, 1, 2, 4, 8, 16, 16, … spp) keeps at ≤ kMaxPassSpp samples
  // per pixel. Checked on the render's own clock readings, so machine load cannot make the
  // check pass or fail: the last pass began inside the budget and the render ended past it.
  const Scene s = closed_box(0.6f, 4.0f);
  const RayTracer tracer(s);
  PathIntegrator path{Params()};
  RenderOptions o;
  o.width = o.height = 8;
  o.spp = 1 << 24;  // far more than fits in the budget
  o.time_budget_s = 0.3;
  o.progress = false;
  const Image img = path.render(tracer, box_camera(), o);
  const RenderStats& st = path.stats().render;
  EXPECT_GE(st.seconds, o.time_budget_s);
  EXPECT_LT(st.last_pass_start_s, o.time_budget_s) << "a pass began after the budget was spent";
  EXPECT_LE(st.last_pass_start_s, st.seconds);
  ASSERT_GE(st.passes, 1);
  int schedule = 0;  // samples per pixel after st.passes passes of the documented schedule
  for (int pass = 0, size = 1; pass < st.passes; ++pass) {
    schedule += size;
    size = pass == 0 ? 1 : std::min(2 * size, kMaxPassSpp);
  }
  EXPECT_EQ(st.spp, schedule) << st.passes << " passes";
  EXPECT_LT(st.spp, o.spp);
  EXPECT_GT(path.stats().rays, st.samples);  // at least one ray per sample
  EXPECT_EQ(img.width(), 8);
}

TEST(SppmIntegrator, StopsAtTheTimeBudget) {
  // The same rule for SPPM's iterations (sppm.h): at least the budget, and the last
  // iteration began inside it.
  const Scene s = closed_box(0.6f, 4.0f);
  const RayTracer tracer(s);
  SppmIntegrator sppm{params({{"iterations", 1 << 20}, {"photons_per_iteration", 2000}})};
  RenderOptions o;
  o.width = o.height = 8;
  o.time_budget_s = 0.3;
  o.progress = false;
  sppm.render(tracer, box_camera(), o);
  const SppmIntegrator::Stats& st = sppm.stats();
  EXPECT_GE(st.seconds, o.time_budget_s);
  EXPECT_LT(st.last_iteration_start_s, o.time_budget_s);
  EXPECT_GT(st.iterations, 0);
  EXPECT_LT(st.iterations, 1 << 20);
}

TEST(Integrators, DebugViewsOnAPlane) {
  const Scene s = plane_scene(0.25f);
  const Camera cam = top_camera();
  const Image n = render("normals", nlohmann::json::object(), s, cam, 8, 1);
  EXPECT_NEAR(n.pixel(4, 4)[0], 0.5f, 1e-5f);
  EXPECT_NEAR(n.pixel(4, 4)[1], 1.0f, 1e-5f);
  const Image al = render("albedo", nlohmann::json::object(), s, cam, 8, 1);
  EXPECT_NEAR(al.pixel(3, 5)[1], 0.25f, 1e-6f);
  const Image d = render("depth", {{"normalize", false}}, s, cam, 9, 1);
  EXPECT_GT(d.pixel(0, 0)[0], d.pixel(4, 4)[0]);  // corners are farther than the centre
  // The centre pixel holds the ray straight down (3 m) and its corners' rays are the
  // longest: its jittered depth lies between (to float rounding).
  double farthest = 0.0;
  for (const vec2 corner : {vec2(4, 4), vec2(5, 4), vec2(4, 5), vec2(5, 5)}) {
    const Ray r = cam.generate_ray(corner.x, corner.y, 9, 9);
    farthest = std::max(farthest, 3.0 / std::abs(double(glm::normalize(r.direction).y)));
  }
  EXPECT_GE(d.pixel(4, 4)[0], 3.0 * (1 - 1e-6));
  EXPECT_LE(d.pixel(4, 4)[0], farthest * (1 + 1e-6));
  const Image ao = render("ao", {{"samples", 8}}, s, cam, 8, 2);
  for (float v : ao.data()) EXPECT_EQ(v, 1.0f);  // nothing above an open plane
  // A closed box is occluded everywhere within a distance larger than the box.
  const Image closed =
      render("ao", {{"distance", 10.0f}}, closed_box(0.5f, 1.0f), box_camera(), 8, 2);
  for (float v : closed.data()) {
    EXPECT_EQ(v, 0.0f);
  }
}

TEST(Integrators, SceneWithoutLightsRendersBlack) {
  const Scene s = plane_scene(0.5f);
  for (const char* name : {"path", "whitted"}) {
    const Image img = render(name, nlohmann::json::object(), s, top_camera(), 8, 2);
    for (float v : img.data()) {
      EXPECT_EQ(v, 0.0f);
    }
  }
  Scene empty;
  empty.name = "empty";
  const Image img = render("path", nlohmann::json::object(), empty, scene_camera(empty), 8, 1);
  for (float v : img.data()) {
    EXPECT_EQ(v, 0.0f);
  }
}

TEST(Integrators, BadOptionsAndNamesAreErrors) {
  try {
    Integrator::create("phtoon", Params());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown integrator 'phtoon' (known: "),
              std::string::npos);
    EXPECT_NE(std::string(e.what()).find("path"), std::string::npos);
  }
  EXPECT_THROW(Integrator::create("path", params({{"max_bouncs", 3}})), Error);
  EXPECT_THROW(Integrator::create("path", params({{"bounces", "some"}})), Error);
  EXPECT_THROW(Integrator::create("ao", params({{"samples", 0}})), Error);
  const Scene s = plane_scene(0.5f);
  const RayTracer tracer(s);
  const auto integrator = Integrator::create("normals", Params());
  for (const auto& [w, h, spp] :
       {std::tuple{0, 8, 1}, {8, 0, 1}, {8, 8, 0}, {kMaxImageSide + 1, 8, 1}}) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.spp = spp;
    EXPECT_THROW(integrator->render(tracer, top_camera(), o), Error);
  }
}

TEST(RenderSetup, FramingCameraSeesTheWholeScene) {
  const Scene s = closed_box(0.5f, 1.0f);
  const Camera cam = scene_camera(s, 1.0f);
  const Bounds3 b = s.bounds();
  // Every corner of the bounds projects inside the image.
  const mat4 view = cam.view_matrix();
  for (int i = 0; i < 8; ++i) {
    const vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                      (i & 4) ? b.max.z : b.min.z);
    const vec3 v = vec3(view * vec4(corner, 1.0f));
    ASSERT_LT(v.z, 0.0f);
    const float t = std::tan(0.5f * cam.fov_y);
    EXPECT_LE(std::abs(v.x / -v.z), t);
    EXPECT_LE(std::abs(v.y / -v.z), t);
  }
}

}  // namespace
}  // namespace illum
