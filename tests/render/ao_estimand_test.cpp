// The `ao` integrator's bias and falloff (the estimand the real-time SSAO add-on is checked
// against, docs/realtime.md "SSAO"): a point on a floor under a parallel ceiling at height
// h, every ray up hits the ceiling at t = h/cos θ, so
//   O = (1/π) ∫ V_R · max(cos θ − b, 0) · g(t) dω = 2 ∫_{max(h/R, b)}^1 (c − b) g(h/c) dc,
// integrated here by Simpson's rule; the image mean over the floor is compared with 1 − O
// within kZ standard errors estimated from the image (every pixel an independent estimate).
#include <gtest/gtest.h>

#include <cmath>

#include "illum/core/params.h"
#include "illum/render/ao_integrator.h"
#include "illum/render/integrator.h"
#include "illum/trace/ray_tracer.h"
#include "render_test_scenes.h"

namespace illum {
namespace {

constexpr double kZ = 5.0;

// Floor y = 0 and ceiling y = h (facing down), both 2000 wide: rays within R ≤ 10 of a
// floor point near the origin stay far inside them.
Scene slab(float h) {
  Scene s;
  s.name = "slab";
  Material m;
  m.albedo = Color(0.5f);
  const int mat = test::add_material(s, m);
  test::add_triangles(s, test::floor_quad(1000.0f), mat, "floor");
  std::vector<vec3> ceiling;
  test::push_quad(ceiling, {-1000, h, -1000}, {1000, h, -1000}, {1000, h, 1000}, {-1000, h, 1000});
  test::add_triangles(s, ceiling, mat, "ceiling");
  return s;
}

Camera down_camera(float h) {
  Camera cam;
  cam.position = vec3(0.0f, 0.5f * h, 0.0f);
  cam.look_at = vec3(0.0f);
  cam.up = vec3(0.0f, 0.0f, 1.0f);
  cam.fov_y = radians(60.0f);
  return cam;
}

double analytic_occlusion(double h, double R, double b, double s) {
  auto f = [&](double c) {
    const double g = s > 0.0 ? 1.0 / (1.0 + (h / (c * s)) * (h / (c * s))) : 1.0;
    return (c - b) * g;
  };
  const double lo = std::max(h / R, b), hi = 1.0;
  const int n = 20000;  // Simpson, even; the integrand is smooth on [lo, 1]
  double sum = f(lo) + f(hi);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(lo + (hi - lo) * i / n);
  return 2.0 * sum * (hi - lo) / (3.0 * n);
}

Image render_ao(const Scene& scene, const Camera& cam, const nlohmann::json& p) {
  const RayTracer tracer(scene);
  RenderOptions o;
  o.width = o.height = 16;
  o.spp = 4;
  o.seed = 7;
  o.progress = false;
  return Integrator::create("ao", Params(p, "--param"))->render(tracer, cam, o);
}

TEST(AoEstimand, ParallelPlanesAgainstQuadrature) {
  const float h = 1.0f, R = 10.0f;
  const Scene scene = slab(h);
  const Camera cam = down_camera(h);
  struct Case {
    float bias, falloff;
  };
  for (const Case c :
       {Case{0.0f, 0.0f}, Case{0.3f, 0.0f}, Case{0.0f, 1.0f}, Case{0.1f, 0.5f}, Case{0.2f, 3.0f}}) {
    const Image img = render_ao(
        scene, cam, {{"samples", 16}, {"distance", R}, {"bias", c.bias}, {"falloff", c.falloff}});
    double sum = 0, sum2 = 0;
    const double n = static_cast<double>(img.pixel_count());
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        const double v = img.pixel(x, y)[0];
        sum += v;
        sum2 += v * v;
      }
    const double mean = sum / n;
    const double err = std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n);
    const double expected = 1.0 - analytic_occlusion(h, R, c.bias, c.falloff);
    // Beside the statistics: the shadow ray starts 1e-4 (offset_ray_origin, |p| ≤ 1) above
    // the floor, shortening t by at most 1e-4/cos θ ≤ 1e-3 (cos θ ≥ h/R = 0.1); g moves by
    // at most |g'|·Δt ≤ 0.65/s · 1e-3 and the cut-off cosine by 1e-4/R: under 2e-3 in all.
    const double offset_bound = 2e-3;
    EXPECT_NEAR(mean, expected, kZ * err + offset_bound)
        << "bias " << c.bias << " falloff " << c.falloff << " (err " << err << ")";
  }
}

TEST(AoEstimand, DefaultsAreThePlainAoImage) {
  const float h = 1.0f;
  const Scene scene = slab(h);
  const Camera cam = down_camera(h);
  const Image plain = render_ao(scene, cam, {{"samples", 8}, {"distance", 10.0f}});
  const Image zero = render_ao(
      scene, cam, {{"samples", 8}, {"distance", 10.0f}, {"bias", 0.0f}, {"falloff", 0.0f}});
  ASSERT_EQ(plain.data().size(), zero.data().size());
  for (size_t i = 0; i < plain.data().size(); ++i) ASSERT_EQ(plain.data()[i], zero.data()[i]);
  // The weight of one ray: 1 with neither bias nor falloff; the Méndez term over cos θ else.
  EXPECT_EQ(AoIntegrator::occlusion_weight(0.3f, 5.0f, 0.0f, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(AoIntegrator::occlusion_weight(0.5f, 2.0f, 0.1f, 1.0f), 0.4f / 0.5f / 5.0f);
  EXPECT_EQ(AoIntegrator::occlusion_weight(0.1f, 0.0f, 0.2f, 1.0f), 0.0f);
}

TEST(AoEstimand, BadValuesAreErrors) {
  auto make = [](const nlohmann::json& p) {
    return Integrator::create("ao", Params(p, "--param"));
  };
  EXPECT_THROW(make({{"bias", -0.1f}}), Error);
  EXPECT_THROW(make({{"bias", 1.0f}}), Error);
  EXPECT_THROW(make({{"falloff", -1.0f}}), Error);
  EXPECT_THROW(make({{"falloff", "far"}}), Error);
  EXPECT_NO_THROW(make({{"bias", 0.5f}, {"falloff", 2.0f}}));
}

}  // namespace
}  // namespace illum
