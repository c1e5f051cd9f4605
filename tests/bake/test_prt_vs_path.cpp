// PRT against the path tracer (issue 11, deliverable 3): the Cornell box (open at the front)
// with its lamp off, lit only by a distant sky. Lit by the band-limited (SH-projected) sky,
// the relit interreflected transfer and the path tracer given that same sky as its
// environment map must agree region by region within their Monte-Carlo errors: a
// band-limited light has no coefficients beyond the transfer's, so the transfer is exact
// there up to its own noise and its texel discretization. Against the true (unprojected)
// sky the difference is the band-limiting error, which is reported, not bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "illum/atlas/atlas.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/core/image.h"
#include "illum/core/sh.h"
#include "illum/render/integrator.h"
#include "illum/scene/environment.h"
#include "illum/scene/load.h"

namespace illum {
namespace {

constexpr double kZ = 5.0;
constexpr int kBands = 4;
constexpr int kSide = 32;   // image side in pixels
constexpr int kRegion = 8;  // region side in pixels (16 regions)
constexpr int kPathSpp = 256;
constexpr int kPrtSpp = 64;

// A smooth sky: a dim dome plus a broad lobe from the front-upper-left, so that light
// enters the box's opening. Positive, and far from band-limited at 4 bands.
double sky(const glm::dvec3& w) {
  const glm::dvec3 s = glm::normalize(glm::dvec3(-0.4, 0.6, 1.0));
  const double c = std::max(0.0, glm::dot(w, s));
  return 0.3 + 4.0 * c * c * c;
}

Image map_of(const std::function<double(const glm::dvec3&)>& f, int width) {
  Image map(width, width / 2, 3);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < width; ++x) {
      const vec3 d =
          equirect_direction_from_uv({(x + 0.5f) / float(width), (y + 0.5f) / float(map.height())});
      map.set_rgb(x, y, Color(float(f(glm::dvec3(d)))));
    }
  return map;
}

struct Regions {
  std::vector<double> mean;  // channel-summed mean per region over hit pixels
};

Regions regions_of(const Image& image) {
  Regions r;
  for (int ry = 0; ry < kSide / kRegion; ++ry)
    for (int rx = 0; rx < kSide / kRegion; ++rx) {
      double sum = 0.0;
      for (int y = ry * kRegion; y < (ry + 1) * kRegion; ++y)
        for (int x = rx * kRegion; x < (rx + 1) * kRegion; ++x) {
          const Color c = image.rgb(x, y);
          sum += double(c.x + c.y + c.z);
        }
      r.mean.push_back(sum / double(kRegion * kRegion));
    }
  return r;
}

TEST(PrtVsPath, CornellUnderABandLimitedSkyAgreesWithThePathTracer) {
  Scene scene = load_scene("cornell");
  for (Material& m : scene.materials) m.emission = Color(0.0f);
  scene.lights.clear();
  const atlas::Atlas atlas = atlas::chart_scene(scene, {.resolution = 64});
  Light env_light;
  env_light.name = "environment";
  env_light.type = LightType::kEnvironment;
  scene.lights.push_back(env_light);

  // The sky's projection by quadrature exact for bands ≤ kBands of a polynomial of degree 3
  // in (x, y, z) where the lobe is on, to ~1e-3 elsewhere: a fine rule makes it converge.
  const sh::SphereQuadrature rule = sh::sphere_quadrature(64);
  const std::vector<double> c = sh::project(kBands, rule, sky);
  bake::ShLight light;
  light.bands = kBands;
  for (double v : c) light.coefficients.push_back(Color(float(v)));
  const Image limited = bake::sh_environment_map(light, 256);
  for (float v : limited.data()) ASSERT_GT(v, 0.0f) << "the band-limited sky must stay positive";

  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);
  // The scene's camera, narrowed to see only the box: a sliver of bright sky at the image's
  // edge (24× the walls) would make region means depend on how each renderer places its
  // samples in the edge pixels (relight: a fixed 4×4 grid; the path tracer: jittered).
  Camera camera = *scene.camera;
  camera.fov_y *= 0.85f;

  // Two bakes (seeds) give the transfer's error; two path-traced images the tracer's.
  std::vector<Regions> prt, path, truth;
  for (uint64_t seed : {1u, 2u}) {
    bake::PrtBakeOptions o;
    o.bands = kBands;
    o.mode = bake::PrtMode::kInterreflected;
    o.spp = kPrtSpp;
    o.seed = seed;
    o.progress = false;
    o.vertices = false;
    bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, o);
    bake::PrtSet set;
    set.bands = kBands;
    set.texel_transfer = std::move(baked.texel_transfer);
    bake::RelightOptions ro;
    ro.width = ro.height = kSide;
    ro.samples = 16;
    const Image relit = bake::relight(scene, tracer, set, light, camera, ro);
    prt.push_back(regions_of(relit));
  }
  RenderOptions render;
  render.width = render.height = kSide;
  render.spp = kPathSpp;
  render.progress = false;
  const auto path_tracer = [&](const Image& map, uint64_t seed) {
    Environment env;
    env.radiance = map;
    scene.environment = env;
    const RayTracer t(scene);
    render.seed = seed;
    return regions_of(Integrator::create("path", Params({{"max_bounces", 64}}, "test"))
                          ->render(t, camera, render));
  };
  for (uint64_t seed : {11u, 12u}) path.push_back(path_tracer(limited, seed));
  truth.push_back(path_tracer(map_of(sky, 256), 13));

  // Each side's error of the mean of its two runs: (a − b)²/4 estimates its variance with one
  // degree of freedom per region, so the relative variance is pooled over the regions (the
  // noise scales with the light); the z-bound then holds per region.
  const size_t n = prt[0].mean.size();
  double rel_prt = 0.0, rel_path = 0.0;
  for (size_t r = 0; r < n; ++r) {
    const double mp = 0.5 * (prt[0].mean[r] + prt[1].mean[r]);
    const double mq = 0.5 * (path[0].mean[r] + path[1].mean[r]);
    rel_prt += std::pow(0.5 * (prt[0].mean[r] - prt[1].mean[r]) / mp, 2) / double(n);
    rel_path += std::pow(0.5 * (path[0].mean[r] - path[1].mean[r]) / mq, 2) / double(n);
  }
  double worst = 0.0, band_error = 0.0;
  for (size_t r = 0; r < n; ++r) {
    const double mp = 0.5 * (prt[0].mean[r] + prt[1].mean[r]);
    const double mq = 0.5 * (path[0].mean[r] + path[1].mean[r]);
    const double sigma = std::sqrt(rel_prt * mp * mp + rel_path * mq * mq);
    const double d = std::abs(mp - mq);
    std::printf("region %2zu: prt %.4f path %.4f true-light %.4f  |d|/sigma %.2f\n", r, mp, mq,
                truth[0].mean[r], d / sigma);
    EXPECT_LE(d, kZ * sigma) << "region " << r;
    worst = std::max(worst, d / sigma);
    band_error = std::max(band_error, std::abs(mq - truth[0].mean[r]) / truth[0].mean[r]);
  }
  std::printf(
      "relative sigma: prt %.4f path %.4f; worst |d|/sigma %.2f; band-limiting error "
      "(path tracer, SH sky vs true sky, worst region) %.3f\n",
      std::sqrt(rel_prt), std::sqrt(rel_path), worst, band_error);
  RecordProperty("band_limiting_error", std::to_string(band_error));
}

}  // namespace
}  // namespace illum
