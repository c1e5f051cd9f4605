// Integrators on procedural scenes with known answers: the white furnace, analytic
// irradiance from point and spot lights, Whitted against the path tracer's direct mode,
// the bounce decomposition, energy bounds, determinism and option validation.
// Statistical checks use kZ standard errors estimated from the images themselves (every
// pixel is an independent estimate: its own scrambled Sobol' sequence).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "illum/core/error.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/render/path_integrator.h"
#include "illum/render/render_setup.h"
#include "illum/scene/environment.h"
#include "illum/trace/ray_tracer.h"
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
  // Midpoint quadrature over (cos θ, φ) — uniform in solid angle — fine enough that its
  // error is far below the render's.
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
  EXPECT_NEAR(st.mean, expected, kZ * st.err + 1e-3 * expected);
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
  // Looking straight down through a horizontal glass slab (index 1.5) at a lit plane: the
  // slab passes T²(1 + R² + …) of the radiance, T = 1 − R, R = ((η−1)/(η+1))² at normal
  // incidence; the 1/η² entering and η² leaving cancel. Whitted traces both lobes
  // deterministically; the path tracer picks one at random and must agree on average.
  Scene bare = plane_scene(0.8f);
  Light l;
  l.type = LightType::kPoint;
  l.position = vec3(0.0f, 0.5f, 0.0f);  // under the slab: the slab casts no shadow
  l.intensity = Color(1.0f);
  bare.lights.push_back(l);
  Scene glass = bare;
  Material m;
  m.type = MaterialType::kDielectric;
  m.ior = 1.5f;
  test::add_triangles(glass, test::inward_box({-3, 1.0f, -3}, {3, 1.2f, 3}, false),
                      test::add_material(glass, m), "slab");
  Camera cam = top_camera();
  cam.fov_y = radians(4.0f);  // nearly normal incidence everywhere
  const double r = 0.04, expected_ratio = (1 - r) * (1 - r) * (1 + r * r);
  const Image ref = render("whitted", nlohmann::json::object(), bare, cam, 16, 4);
  const Image w = render("whitted", nlohmann::json::object(), glass, cam, 16, 4);
  const Image p = render("path", {{"bounces", "direct"}}, glass, cam, 16, 64);
  const PixelStats sr = pixel_stats(ref), sw = pixel_stats(w), sp = pixel_stats(p);
  EXPECT_NEAR(sw.mean / sr.mean, expected_ratio, 2e-3);
  EXPECT_NEAR(sp.mean / sr.mean, expected_ratio, kZ * sp.err / sr.mean + 2e-3);
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
  for (const char* integrator : {"path", "whitted"}) {
    const nlohmann::json p = std::string(integrator) == "path"
                                 ? nlohmann::json{{"bounces", "direct"}}
                                 : nlohmann::json::object();
    const PixelStats st = pixel_stats(render(integrator, p, s, cam, 16, 16));
    EXPECT_NEAR(st.mean, expected, kZ * st.err + 1e-3 * expected) << integrator;
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

Scene closed_box(float albedo, float le) {
  Scene s;
  s.name = "closed-box";
  Material wall;
  wall.albedo = Color(albedo);
  test::add_triangles(s, test::inward_box(vec3(-1), vec3(1)), test::add_material(s, wall), "walls");
  Material emitter = wall;
  emitter.emission = Color(le);
  std::vector<vec3> quad;  // just below the ceiling, facing down
  test::push_quad(quad, {-0.3f, 0.99f, -0.3f}, {0.3f, 0.99f, -0.3f}, {0.3f, 0.99f, 0.3f},
                  {-0.3f, 0.99f, 0.3f});
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
  // most 2 diffuse vertices: direct (k ≤ 1) + indirect1 (k = 2).
  const Scene s = closed_box(0.6f, 4.0f);
  const Camera cam = box_camera();
  const PixelStats all = pixel_stats(render("path", {{"max_bounces", 2}}, s, cam, 24, 16, 3));
  const PixelStats direct =
      pixel_stats(render("path", {{"max_bounces", 2}, {"bounces", "direct"}}, s, cam, 24, 16, 4));
  const PixelStats ind = pixel_stats(
      render("path", {{"max_bounces", 2}, {"bounces", "indirect1"}}, s, cam, 24, 16, 5));
  EXPECT_GT(ind.mean, 0.0);
  EXPECT_GT(direct.mean, ind.mean);
  // The pixel spread includes real image variation, so this error bound is conservative.
  const double err = std::sqrt(all.err * all.err + direct.err * direct.err + ind.err * ind.err);
  EXPECT_NEAR(all.mean, direct.mean + ind.mean, kZ * err);
  // And with unlimited bounces "all" carries more light than the two-bounce subset.
  const PixelStats full = pixel_stats(render("path", nlohmann::json::object(), s, cam, 24, 16, 6));
  EXPECT_GT(full.mean, all.mean);
}

TEST(PathIntegrator, NeverCreatesEnergyInAClosedBox) {
  // In a closed scene of albedo ≤ a lit by emitters of radiance ≤ Le, L ≤ Le/(1 − a).
  const float a = 0.7f, le = 5.0f;
  const Scene s = closed_box(a, le);
  const Camera cam = box_camera();
  const Image i1 = render("path", {{"max_bounces", 64}}, s, cam, 24, 32, 11);
  const Image i2 = render("path", {{"max_bounces", 64}}, s, cam, 24, 32, 12);
  // Per-pixel noise from two independent renders: Var = E[(a − b)²]/2.
  double d2 = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const double d = i1.pixel(x, y)[1] - i2.pixel(x, y)[1];
      d2 += d * d;
    }
  const double sigma = std::sqrt(d2 / (2.0 * static_cast<double>(i1.pixel_count())));
  const double bound = le / (1.0 - a);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      ASSERT_LE(0.5 * (i1.pixel(x, y)[1] + i2.pixel(x, y)[1]), bound + kZ * sigma) << x << "," << y;
    }
  EXPECT_LT(pixel_stats(i1).mean, bound);
}

TEST(Integrators, DeterministicForSeedAndThreads) {
  const Scene s = closed_box(0.6f, 4.0f);
  const Camera cam = box_camera();
  for (const char* name : {"path", "whitted", "ao"}) {
    const Image a = render(name, nlohmann::json::object(), s, cam, 20, 4, 42, 2);
    const Image b = render(name, nlohmann::json::object(), s, cam, 20, 4, 42, 2);
    const Image c = render(name, nlohmann::json::object(), s, cam, 20, 4, 42, 1);
    EXPECT_EQ(a.data(), b.data()) << name;
    EXPECT_EQ(a.data(), c.data()) << name << ": per-pixel sequences make threads irrelevant";
    if (std::string(name) == "path") {
      const Image d = render(name, nlohmann::json::object(), s, cam, 20, 4, 43, 2);
      EXPECT_NE(a.data(), d.data());
    }
  }
}

TEST(PathIntegrator, StopsAtTheTimeBudget) {
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
  EXPECT_GE(st.seconds, 0.3);
  EXPECT_LT(st.spp, o.spp);
  EXPECT_GT(st.spp, 0);
  EXPECT_GT(path.stats().rays, st.samples);  // at least one ray per sample
  EXPECT_EQ(img.width(), 8);
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
  EXPECT_NEAR(d.pixel(4, 4)[0], 3.0f, 0.02f);
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
