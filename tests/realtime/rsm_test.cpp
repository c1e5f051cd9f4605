// Reflective shadow maps (techniques/rsm.cpp) on the device, validation layers on: the flux of
// every light view sums to the light's flux reflected by what it sees — a spot on a floor
// (its cone's flux I·2π(1 − cos θc)), a point light in a closed box (4πI), a directional light
// over a floor (E × the box's area) — each times the albedo; positions and normals are the
// surface's; a directional box moved by less than a texel keeps its texel grid; `rsm.lights`
// picks one light and refuses what is not one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/rsm_views.h"
#include "illum/realtime/techniques/techniques.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 32;
const Color kAlbedo(0.8f, 0.5f, 0.3f);

class RsmTest : public test::ValidatedVulkanTest {};

Scene floor_scene(float half) {
  Scene s;
  s.name = "rsm-floor";
  Material m;
  m.albedo = kAlbedo;
  s.materials = {m};
  test::add_quad(s, {-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half}, 0);
  Camera cam;
  cam.position = vec3(0.3f, 1.5f, 2.0f);
  cam.look_at = vec3(0.0f, 0.0f, 0.0f);
  cam.fov_y = radians(50.0f);
  s.camera = cam;
  return s;
}

RenderSettings settings(int resolution, int lights = -1) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = "forward";
  o.shadows = "none";
  o.enable("rsm");
  o.set("rsm.resolution", resolution);
  o.set("rsm.lights", lights);
  return o;
}

struct Sums {
  double flux[3] = {0, 0, 0};
  int covered = 0;
  float worst_plane = 0.0f;   // largest |y| of a covered texel (the floor is y = 0)
  float worst_normal = 0.0f;  // largest |n − (0, 1, 0)| of a covered texel
};

// Σ over `layers` layers of the maps, and how far positions and normals are from the floor's.
Sums sum_layers(Renderer& r, uint32_t first, uint32_t layers) {
  Sums s;
  for (uint32_t k = first; k < first + layers; ++k) {
    const Image pos = r.read_resource(rsm::kPosition, k);
    const Image nrm = r.read_resource(rsm::kNormal, k);
    const Image flux = r.read_resource(rsm::kFlux, k);
    for (int y = 0; y < flux.height(); ++y)
      for (int x = 0; x < flux.width(); ++x) {
        for (int c = 0; c < 3; ++c) s.flux[c] += flux.pixel(x, y)[c];
        if (pos.pixel(x, y)[3] != 1.0f) continue;
        ++s.covered;
        s.worst_plane = std::max(s.worst_plane, std::abs(pos.pixel(x, y)[1]));
        const vec3 n(nrm.pixel(x, y)[0], nrm.pixel(x, y)[1], nrm.pixel(x, y)[2]);
        s.worst_normal = std::max(s.worst_normal, glm::length(n - vec3(0, 1, 0)));
      }
  }
  return s;
}

// A spot straight down on a floor that holds its whole cone: Σ Φ = ρ·I·2π(1 − cos θc). Texels
// are counted by their centre's direction, so those the cone's edge crosses (≈ 2π·n/2 of the
// ≈ π·n²/4 lit ones) are counted whole or not at all: an error that shrinks as 1/n (measured
// +2.7e-3 at 64², +1.5e-3 at 128², printed). Tolerance 5e-3; the constant weight 4π/(6n²) or a
// missing cone test miss by far more (mutations of the report).
TEST_F(RsmTest, SpotOnAFloorReflectsItsConesFluxTimesTheAlbedo) {
  Scene scene = floor_scene(10.0f);
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(0.2f, 1.0f, -0.1f);
  spot.direction = vec3(0, -1, 0);
  spot.cone_half_angle = radians(30.0f);
  spot.intensity = Color(2.0f, 1.0f, 0.5f);
  scene.lights = {spot};
  for (int res : {64, 128}) {
    Renderer r(context(), scene, settings(res));
    r.render(*scene.camera);
    const Image first = r.read_resource(rsm::kFlux, 0);
    ASSERT_EQ(first.width(), res);
    const Sums s = sum_layers(r, 0, 1);
    const double cone = 2.0 * kPi * (1.0 - std::cos(double(spot.cone_half_angle)));
    for (int c = 0; c < 3; ++c) {
      const double want = double(kAlbedo[c]) * double(spot.intensity[c]) * cone;
      EXPECT_NEAR(s.flux[c], want, 5e-3 * want) << "resolution " << res << " channel " << c;
      if (c == 0)
        std::printf("spot, %d²: sum / closed form - 1 = %+.2e\n", res, s.flux[c] / want - 1.0);
    }
    // The whole square view sees the floor (the cone is its inscribed circle).
    EXPECT_EQ(s.covered, res * res);
    EXPECT_LT(s.worst_plane, 1e-5f);
    EXPECT_LT(s.worst_normal, 2e-3f);  // fp16 rounding
  }
}

// A point light in a closed box of one albedo: its six faces see every direction once, so
// Σ Φ = ρ·4πI whatever the texel count — the exact solid angles telescope to the faces'
// 4π. Tolerance: float sums of 6·64² terms, 1e-4 relative.
TEST_F(RsmTest, PointLightInAClosedBoxReflectsFourPiIntensity) {
  Scene scene;
  scene.name = "rsm-box";
  Material m;
  m.albedo = kAlbedo;
  scene.materials = {m};
  test::add_block(scene, vec3(0.0f, 0.5f, 0.0f), vec3(0.7f, 0.5f, 0.4f), 0.0f, 0);
  test::add_quad(scene, {-0.7f, 0, -0.4f}, {0.7f, 0, -0.4f}, {0.7f, 0, 0.4f}, {-0.7f, 0, 0.4f},
                 0);  // the block has no bottom face
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.25f, 0.3f, -0.1f);  // off centre: the faces see unequal walls
  point.intensity = Color(0.4f, 0.9f, 1.3f);
  scene.lights = {point};
  Camera cam;
  cam.position = vec3(0.0f, 0.5f, 0.3f);
  cam.look_at = vec3(0.0f, 0.5f, -0.4f);
  scene.camera = cam;
  Renderer r(context(), scene, settings(64));
  r.render(*scene.camera);
  const Sums s = sum_layers(r, 0, 6);
  EXPECT_EQ(s.covered, 6 * 64 * 64);  // closed: every texel of every face sees a wall
  for (int c = 0; c < 3; ++c) {
    const double want = double(kAlbedo[c]) * 4.0 * kPi * double(point.intensity[c]);
    EXPECT_NEAR(s.flux[c], want, 1e-4 * want) << "channel " << c;
  }
  // Texel by texel (the sum above holds for any weights that add up to a face's 4π/6):
  // Φ/(ρ·I) is the texel's solid angle, here integrated numerically over the texel — 16×16
  // midpoints of dω = dA/(1 + x² + y²)^{3/2} on the plane at distance 1. Tolerance 5e-3
  // relative: float cancellation in the shader's four-corner difference (~2e-7 sr against
  // a corner texel's 1.9e-4 sr at 64²); the constant average 4π/(6n²) is 5× off at a corner.
  const Image face = r.read_resource(rsm::kFlux, 0);
  float worst = 0.0f;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      double omega = 0.0;
      const double h = 2.0 / 64.0, sub = h / 16.0;
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
          const double u = -1.0 + h * x + sub * (i + 0.5), v = -1.0 + h * y + sub * (j + 0.5);
          omega += sub * sub / std::pow(1.0 + u * u + v * v, 1.5);
        }
      const double got = face.pixel(x, y)[1] / (double(kAlbedo[1]) * double(point.intensity[1]));
      worst = std::max(worst, float(std::abs(got - omega) / omega));
    }
  EXPECT_LT(worst, 5e-3f);
}

// A directional light straight down on a floor larger than its box: Σ Φ = ρ·E·(2R)², R the
// box's half side (rsm_directional_box: the sphere around the camera's view out to
// rsm.distance). Tolerance: float sums, 1e-4 relative.
TEST_F(RsmTest, DirectionalLightReflectsIrradianceTimesTheBoxArea) {
  Scene scene = floor_scene(50.0f);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = vec3(0, -1, 0);
  sun.irradiance = Color(3.0f, 2.0f, 1.0f);
  scene.lights = {sun};
  RenderSettings o = settings(64);
  o.set("rsm.distance", 3.0f);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  const FrameView cam = camera_view(*scene.camera, scene.bounds(), kSize, kSize);
  const RsmBox box = rsm_directional_box(cam.inv_view_proj, cam.camera.position, cam.near_plane,
                                         std::min(3.0f, cam.far_plane));
  ASSERT_GT(box.radius, 1.0f);
  ASSERT_LT(box.radius, 10.0f);  // well inside the floor
  const Sums s = sum_layers(r, 0, 1);
  EXPECT_EQ(s.covered, 64 * 64);
  EXPECT_LT(s.worst_plane, 1e-5f);
  EXPECT_LT(s.worst_normal, 2e-3f);
  const double area = 4.0 * double(box.radius) * double(box.radius);
  for (int c = 0; c < 3; ++c) {
    const double want = double(kAlbedo[c]) * double(sun.irradiance[c]) * area;
    EXPECT_NEAR(s.flux[c], want, 1e-4 * want) << "channel " << c;
  }
}

// The directional box is snapped to whole texels: moved by a fraction of a texel, the texel
// centres land on the same world grid (positions of a floor texel differ by whole texels).
TEST_F(RsmTest, DirectionalBoxKeepsItsTexelGridAsTheCameraMoves) {
  Scene scene = floor_scene(50.0f);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = vec3(0, -1, 0);
  sun.irradiance = Color(1.0f);
  scene.lights = {sun};
  RenderSettings o = settings(64);
  o.set("rsm.distance", 3.0f);
  Renderer r(context(), scene, o);
  Camera cam = *scene.camera;
  r.render(cam);
  const Image a = r.read_resource(rsm::kPosition, 0);
  const float texel =
      std::abs(a.pixel(1, 0)[0] - a.pixel(0, 0)[0]) + std::abs(a.pixel(1, 0)[2] - a.pixel(0, 0)[2]);
  ASSERT_GT(texel, 0.0f);
  cam.position += vec3(0.37f * texel, 0.0f, 0.21f * texel);
  cam.look_at += vec3(0.37f * texel, 0.0f, 0.21f * texel);
  r.render(cam);
  const Image b = r.read_resource(rsm::kPosition, 0);
  float worst = 0.0f;
  for (int i = 0; i < 2; ++i) {
    const int axis = i == 0 ? 0 : 2;
    const float shift = (b.pixel(7, 9)[axis] - a.pixel(7, 9)[axis]) / texel;
    worst = std::max(worst, std::abs(shift - std::round(shift)));
  }
  EXPECT_LT(worst, 1e-3f);
}

// rsm.lights=1 draws light 1 alone (one layer, its flux); an index past the lights or a word
// or a resolution other than 64, 128, 256 is refused with one line naming the value.
TEST_F(RsmTest, LightsParameterPicksOneLightOrIsRefused) {
  Scene scene = floor_scene(10.0f);
  Light a;
  a.type = LightType::kPoint;
  a.position = vec3(0.0f, 1.0f, 0.0f);
  a.intensity = Color(5.0f);
  Light b;
  b.type = LightType::kSpot;
  b.position = vec3(0.1f, 1.0f, 0.0f);
  b.direction = vec3(0, -1, 0);
  b.cone_half_angle = radians(20.0f);
  b.intensity = Color(1.0f, 2.0f, 3.0f);
  scene.lights = {a, b};
  {
    Renderer r(context(), scene, settings(64, 1));
    r.render(*scene.camera);
    const Sums s = sum_layers(r, 0, 1);
    const double cone = 2.0 * kPi * (1.0 - std::cos(double(b.cone_half_angle)));
    for (int c = 0; c < 3; ++c) {
      const double want = double(kAlbedo[c]) * double(b.intensity[c]) * cone;
      EXPECT_NEAR(s.flux[c], want, 1e-2 * want) << "channel " << c;
    }
    EXPECT_THROW(r.read_resource(rsm::kFlux, 1), Error);  // one layer only
  }
  {
    // Both: the point light's six faces, then the spot's layer.
    Renderer r(context(), scene, settings(64));
    r.render(*scene.camera);
    EXPECT_NO_THROW(r.read_resource(rsm::kFlux, 6));
    EXPECT_THROW(r.read_resource(rsm::kFlux, 7), Error);
  }
  for (int bad : {2, 7}) {
    try {
      Renderer r(context(), scene, settings(64, bad));
      r.render(*scene.camera);
      ADD_FAILURE() << "rsm.lights=" << bad << " was accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("rsm.lights=" + std::to_string(bad) + ": the scene has 2 light(s)"),
                std::string::npos)
          << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  // Not a power of two: refused with the values it takes.
  try {
    Renderer r(context(), scene, settings(100));
    r.render(*scene.camera);
    ADD_FAILURE() << "rsm.resolution=100 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rsm.resolution=100: one of 64, 128, 256"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace illum::realtime
