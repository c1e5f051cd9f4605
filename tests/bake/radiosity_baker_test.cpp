// The radiosity light-map baker (bake/radiosity_baker.h): the closed furnace box against its
// closed form, the Cornell box against the path-traced baker texel by texel, the bases,
// determinism and bad options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "bake_test_scenes.h"
#include "charted_cornell.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/params.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

using bake::RadiosityBake;
using bake::RadiosityBakeOptions;

using Charted = test::ChartedScene;

// Where radiosity's piecewise-constant sources cannot agree with the path tracer's point
// evaluation texel by texel, by construction rather than by error:
//   penumbra  the texel's point sees part of the emitters (0 < v < 1 over a 16×16 grid of
//             points on each emissive triangle): shots test visibility from one point per
//             source group, so the shadow edge moves by up to a group;
//   near      another surface lies within `near_distance` of the point (corners, contacts):
//             the sources there are closer than a few of their own sizes, where a
//             point-to-disk factor per texel is not the integral over it.
struct TexelClass {
  bool penumbra = false, near = false;
  bool sees_emitter = false;  // some emitter point is visible
};

std::vector<TexelClass> classify(const Scene& scene, const RayTracer& tracer,
                                 const atlas::TexelRaster& raster, float near_distance) {
  std::vector<vec3> emitter_points;
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (!scene.materials[size_t(mesh.material)].is_emissive()) continue;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      vec3 p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = vec3(inst.transform * vec4(mesh.positions[mesh.indices[3 * t + size_t(k)]], 1.0f));
      constexpr int kGrid = 16;
      for (int i = 0; i < kGrid; ++i)
        for (int j = 0; j < kGrid - i; ++j) {
          const float a = (float(i) + 1.0f / 3.0f) / kGrid, b = (float(j) + 1.0f / 3.0f) / kGrid;
          emitter_points.push_back(p[0] + a * (p[1] - p[0]) + b * (p[2] - p[0]));
        }
    }
  }
  std::vector<TexelClass> out(raster.samples.size());
  for (size_t i = 0; i < raster.samples.size(); ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    int seen = 0, facing = 0;
    for (const vec3& q : emitter_points) {
      const vec3 d = q - s.position;
      if (glm::dot(d, s.geometric_normal) <= 0.0f) continue;
      ++facing;
      const vec3 o = offset_ray_origin(s.position, s.geometric_normal, d);
      seen += tracer.occluded(Ray{o, q - o, 0.0f, 0.999f}) ? 0 : 1;
    }
    out[i].penumbra = seen > 0 && seen < facing;
    out[i].sees_emitter = seen > 0;
    const Frame frame = Frame::from_normal(s.normal);
    for (int k = 0; k < 64 && !out[i].near && near_distance > 0.0f; ++k) {
      const vec2 u((float(k % 8) + 0.5f) / 8.0f, (float(k / 8) + 0.5f) / 8.0f);
      const vec3 w = glm::normalize(frame.to_world(sample_cosine_hemisphere(u)));
      if (glm::dot(w, s.geometric_normal) <= 0.0f) continue;
      out[i].near = tracer.occluded(
          Ray{offset_ray_origin(s.position, s.geometric_normal, w), w, 0.0f, near_distance});
    }
  }
  return out;
}

// The raw path-traced bake the Cornell comparisons measure radiosity against.
bake::LightmapBake path_bake_512(const Charted& c) {
  bake::LightmapBakeOptions po;
  po.spp = 512;
  po.progress = false;
  po.dilate = 0;
  return bake::bake_lightmap(c.scene, *c.tracer, c.raster, po);
}

RadiosityBakeOptions quiet(double threshold = 1e-3) {
  RadiosityBakeOptions o;
  o.threshold = threshold;
  o.progress = false;
  o.dilate = 0;
  return o;
}

// Furnace: a closed box of albedo ρ whose walls all emit L_e. The converged radiance is
// L_e/(1−ρ) everywhere, so the plain layer (E/π) is L_e/(1−ρ). Every shot hands out all of
// its power (the box is closed: reach 1), each arrival keeps (1−ρ) of it, so the map's
// area-weighted mean is exactly (L_e/(1−ρ))·(1 − U/U₀) with U/U₀ ≤ threshold the unshot share
// left: the mean lies in [exact·(1 − threshold), exact] up to float rounding, which a texel
// summing S shots in float bounds by S·2⁻²⁴ relative (recursive summation).
TEST(RadiosityBaker, FurnaceBoxMeanIsExactWithinTheThreshold) {
  const float albedo = 0.5f, le = 1.0f;
  const Charted box(test::furnace_box(albedo, le), 64);
  const double exact = le / (1.0 - albedo);
  for (const double threshold : {1e-2, 1e-3}) {
    const RadiosityBake b =
        bake::bake_radiosity(box.scene, *box.tracer, box.raster, quiet(threshold));
    ASSERT_TRUE(b.converged);
    double sum = 0.0, area = 0.0;
    for (const atlas::TexelSample& s : box.raster.samples) {
      const double a = b.area.pixel(s.x, s.y)[0];
      sum += a * b.layers[0].pixel(s.x, s.y)[0];
      area += a;
    }
    const double mean = sum / area;
    const double rounding = double(b.shots) * 0x1p-24;
    EXPECT_LE(mean, exact * (1.0 + rounding)) << "threshold " << threshold;
    EXPECT_GE(mean, exact * (1.0 - threshold - rounding)) << "threshold " << threshold;
    EXPECT_LE(b.remaining_power, threshold * b.initial_power);
    float lo = 1e30f, hi = 0.0f;  // reported, not checked: corners carry the factors' error
    for (const atlas::TexelSample& s : box.raster.samples) {
      lo = std::min(lo, b.layers[0].pixel(s.x, s.y)[0]);
      hi = std::max(hi, b.layers[0].pixel(s.x, s.y)[0]);
    }
    std::printf(
        "furnace threshold %g: texels in [%.4f, %.4f]; area mean %.6f, exact %.6f, %lld shots\n",
        threshold, double(lo), double(hi), mean, exact, (long long)b.shots);
  }
}

// Cornell box, radiosity against the path-traced baker texel by texel. Both evaluate the
// light arriving at the same sample point per texel, so they differ by
//   (a) the path bake's noise: its per-texel variance σ² (run means, lightmap_baker.h), kZ σ;
//   (b) radiosity's piecewise-constant sources: a group of n×n texels shoots from its centre
//       with one radiosity. The error of that is first order in the source size at worst
//       (second order where the radiosity is smooth), so Richardson between n = 3 and n = 1
//       bounds the n = 3 error by 1.5·|R₃ − R₁| (e(3h) − e(h) = 2ch for e = c·size);
//   (c) a texel's own point-to-disk factor for sources at distance r ≥ d: the centre rule's
//       relative error for a kernel cos·cos/r² over a square of side h is about ½(h/r)²,
//       so ½(h/d)² of the texel's value, d = 2h the nearest surface allowed below;
//   (d) power conservation spreading the factors' deficit over the shot: the power-weighted
//       mean |scale − 1| of the shots, times the value; and the threshold τ.
// Texels where (b)–(c) do not describe the error are left out and counted: the penumbra
// (visibility is tested from one point per source group, so the shadow edge moves by up to a
// group) and texels with another surface within d (corners, contacts).
TEST(RadiosityBaker, CornellAgreesWithThePathBakerPerTexel) {
  constexpr double kZ = 5.0;
  const Charted c(load_scene("cornell"), 40);
  RadiosityBakeOptions o = quiet(1e-3);
  const RadiosityBake r3 = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  o.group_size = 1;
  const RadiosityBake r1 = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  const bake::LightmapBake p = path_bake_512(c);

  const float h = c.texel_size;
  const double near_distance = 2.0 * h;
  const double quadrature = 0.5 * (h / near_distance) * (h / near_distance);
  const double conservation = std::abs(r3.scale_mean - 1.0);
  const std::vector<TexelClass> cls = classify(c.scene, *c.tracer, c.raster, float(near_distance));
  auto lum = [](const Image& image, const atlas::TexelSample& s) {
    const float* v = image.pixel(s.x, s.y);
    return double(luminance(Color(v[0], v[1], v[2])));
  };
  size_t penumbra = 0, near = 0, kept = 0, failed = 0;
  std::vector<double> relative;
  for (size_t i = 0; i < c.raster.samples.size(); ++i) {
    const atlas::TexelSample& s = c.raster.samples[i];
    penumbra += cls[i].penumbra;
    near += cls[i].near;
    if (cls[i].penumbra || cls[i].near) continue;
    ++kept;
    const double rv = lum(r3.layers[0], s), pv = lum(p.layers[0], s);
    const double tolerance = kZ * std::sqrt(double(p.variance.pixel(s.x, s.y)[0])) +
                             1.5 * std::abs(rv - lum(r1.layers[0], s)) +
                             (quadrature + conservation + o.threshold) * rv;
    if (pv > 0.0) relative.push_back(std::abs(rv - pv) / pv);
    if (std::abs(rv - pv) > tolerance) {
      ++failed;
      ADD_FAILURE() << "texel (" << s.x << ", " << s.y << "): radiosity " << rv << ", path " << pv
                    << ", tolerance " << tolerance;
    }
  }
  std::sort(relative.begin(), relative.end());
  std::printf(
      "Cornell 40²: %zu texels, %zu in the penumbra, %zu near another surface, %zu "
      "compared; |R−P|/P median %.3f, 90th %.3f, max %.3f; conservation %.3f\n",
      c.raster.samples.size(), penumbra, near, kept, relative[relative.size() / 2],
      relative[relative.size() * 9 / 10], relative.back(), conservation);
  EXPECT_EQ(failed, 0u);
  // The comparison must cover a real part of the map, not only what was easy.
  EXPECT_GE(kept * 4, c.raster.samples.size());
}

double relative_rmse(const Charted& c, const Image& estimate, const Image& reference) {
  double e2 = 0.0, sum = 0.0;
  for (const atlas::TexelSample& s : c.raster.samples) {
    const double r = luminance(reference.rgb(s.x, s.y)), e = luminance(estimate.rgb(s.x, s.y));
    e2 += (e - r) * (e - r);
    sum += r;
  }
  const double n = double(c.raster.samples.size());
  return std::sqrt(e2 / n) / (sum / n);
}

// Receiver clusters (shooting_clusters.h) change only visibility, and only where a shadow
// edge bends between a cluster's probes. Where nothing occludes (the furnace box) the map is
// the unclustered one exactly, with fewer rays. In the Cornell box (two blocks: straight
// shadow edges, refined to the texel, and their corners) the clustered map must stay as
// close to the path-traced reference as the unclustered one, at three times the default
// ratio (at the default, this small map shares almost no cluster): its relative RMSE against a
// 512-spp path bake at most kAdded above the unclustered map's (whose own error there,
// discretisation + the reference's noise, is about 9%; the bound is a tenth of that).
TEST(RadiosityBaker, ClustersChangeOnlyTheVisibilityTheyShare) {
  {
    const Charted box(test::furnace_box(0.5f, 1.0f), 48);
    RadiosityBakeOptions o = quiet(1e-3);
    o.cluster_ratio = 0.0f;
    const RadiosityBake plain = bake::bake_radiosity(box.scene, *box.tracer, box.raster, o);
    o.cluster_ratio = 0.3f;
    const RadiosityBake clustered = bake::bake_radiosity(box.scene, *box.tracer, box.raster, o);
    std::printf("furnace 48²: %lld visibility rays without clusters, %lld with\n",
                (long long)plain.visibility_rays, (long long)clustered.visibility_rays);
    EXPECT_LT(clustered.visibility_rays, plain.visibility_rays);
    EXPECT_EQ(plain.layers[0].data(), clustered.layers[0].data());
  }
  constexpr double kAdded = 0.009;
  const Charted c(load_scene("cornell"), 40);
  RadiosityBakeOptions o = quiet(1e-3);
  o.cluster_ratio = 0.0f;
  const RadiosityBake plain = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  o.cluster_ratio = 3.0f * bake::kDefaultClusterRatio;  // so clusters are shared at 40²
  const RadiosityBake clustered = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  const bake::LightmapBake p = path_bake_512(c);
  const double e_plain = relative_rmse(c, plain.layers[0], p.layers[0]);
  const double e_clustered = relative_rmse(c, clustered.layers[0], p.layers[0]);
  std::printf(
      "Cornell 40²: relative RMSE against the path bake %.4f without clusters, %.4f with; "
      "visibility rays %lld / %lld\n",
      e_plain, e_clustered, (long long)plain.visibility_rays, (long long)clustered.visibility_rays);
  EXPECT_LE(e_clustered, e_plain + kAdded);
  EXPECT_LT(clustered.visibility_rays, plain.visibility_rays);
}

// Every arrival comes from one direction (a shot's centre, a point light, a sky sample), so
// the plain layer E/π and the SH layer's z coefficient ∫L·Y₁₀ = kY1·E agree exactly:
// plain = c₁₀/(π·kY1) per texel, up to float rounding of the sums.
// A single plane sees nothing of itself, so its map is the direct light alone, which the
// baker computes without noise: a point light I·cosθ/r², a spot the same inside its hard cone
// and nothing outside, a sun E·cosθ, and a uniform sky of radiance L exactly L (each cosine
// sample of a constant sky weighs L·π). Plain layer = E/π; float rounding only.
TEST(RadiosityBaker, DirectLightOnAPlaneIsExact) {
  Scene s;
  const int mat = test::add_lambert(s, Color(0.5f));
  test::add_instance(s, test::uv_plane(1.0f, mat));
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.3f, 0.8f, -0.2f);
  point.intensity = Color(2.0f, 1.0f, 0.5f);
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(-0.2f, 0.5f, 0.1f);
  spot.direction = vec3(0.0f, -1.0f, 0.0f);
  spot.cone_half_angle = radians(40.0f);
  spot.intensity = Color(1.0f);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.irradiance = Color(3.0f);
  s.lights = {point, spot, sun};
  Environment sky;
  sky.constant = Color(0.25f);
  s.environment = sky;
  s.lights.push_back(Light{});
  s.lights.back().type = LightType::kEnvironment;
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 16, 16);
  const RadiosityBake b = bake::bake_radiosity(s, tracer, raster, quiet());
  size_t in_cone = 0;
  for (const atlas::TexelSample& t : raster.samples) {
    const vec3 p = t.position;
    auto from = [&](const vec3& q) {
      const vec3 d = q - p;
      return std::max(0.0f, glm::normalize(d).y) / glm::dot(d, d);
    };
    Color e = point.intensity * from(point.position) + sun.irradiance * -sun.direction.y +
              sky.constant * kPi;
    const vec3 to_texel = glm::normalize(p - spot.position);
    if (glm::dot(to_texel, spot.direction) > std::cos(spot.cone_half_angle)) {
      e += spot.intensity * from(spot.position);
      ++in_cone;
    }
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(b.layers[0].pixel(t.x, t.y)[ch], e[ch] / kPi, 1e-5 * e[ch]) << t.x << " " << t.y;
  }
  EXPECT_GT(in_cone, 0u);
  EXPECT_LT(in_cone, raster.samples.size());
}

// Shadows: an emitting square (facing down) above a floor, with a black square in between.
// Floor and blocker have albedo 0, so no light bounces: floor texels that see no point of
// the emitter (the umbra, by 16×16 points per emitter triangle, classify()) must be exactly
// black, and the floor must have such texels and lit ones.
TEST(RadiosityBaker, UmbraBehindABlockerIsBlack) {
  Scene s;
  const int black = test::add_lambert(s, Color(0.0f));
  const int glow = test::add_lambert(s, Color(0.0f), Color(1.0f));
  test::add_instance(s, test::uv_plane(1.0f, black));
  test::add_instance(s, test::uv_plane(0.3f, black),
                     glm::translate(mat4(1.0f), vec3(0.0f, 0.5f, 0.0f)));
  test::add_instance(s, test::uv_plane(0.2f, glow),
                     glm::translate(mat4(1.0f), vec3(0.0f, 1.0f, 0.0f)) *
                         glm::rotate(mat4(1.0f), kPi, vec3(1.0f, 0.0f, 0.0f)));
  // A point light and a spot under the emitter: the blocker's shadow of each covers the
  // emitter's umbra (|x|, |z| < 0.4 on the floor), so their shadow rays are tested too.
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.0f, 0.9f, 0.0f);
  point.intensity = Color(1.0f);
  Light spot = point;
  spot.type = LightType::kSpot;
  spot.position = vec3(0.05f, 0.9f, 0.0f);
  spot.cone_half_angle = radians(80.0f);
  s.lights = {point, spot};
  const Charted c(std::move(s), 48);
  const RadiosityBake b = bake::bake_radiosity(c.scene, *c.tracer, c.raster, quiet());
  const std::vector<TexelClass> cls = classify(c.scene, *c.tracer, c.raster, 0.0f);
  size_t umbra = 0, lit = 0;
  for (size_t i = 0; i < c.raster.samples.size(); ++i) {
    const atlas::TexelSample& t = c.raster.samples[i];
    if (t.instance != 0 || cls[i].penumbra) continue;
    const float v = b.layers[0].pixel(t.x, t.y)[0];
    if (cls[i].sees_emitter) {
      lit += v > 0.0f;
    } else {
      ++umbra;
      EXPECT_EQ(v, 0.0f) << "umbra texel (" << t.x << ", " << t.y << ")";
    }
  }
  EXPECT_GT(umbra, 10u);
  EXPECT_GT(lit, 10u);
}

TEST(RadiosityBaker, PlainAndShLayersHoldTheSameIrradiance) {
  const Charted c(load_scene("cornell"), 24);
  RadiosityBakeOptions o = quiet(1e-2);
  const RadiosityBake plain = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  o.basis = bake::LightmapBasis::kShL1;
  const RadiosityBake sh = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  o.basis = bake::LightmapBasis::kRnm;
  const RadiosityBake rnm = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
  ASSERT_EQ(sh.layers.size(), 4u);
  ASSERT_EQ(rnm.layers.size(), 3u);
  const double to_plain = 1.0 / (std::numbers::pi * sh::kY1);
  for (const atlas::TexelSample& s : c.raster.samples)
    for (int ch = 0; ch < 3; ++ch) {
      const double e = plain.layers[0].pixel(s.x, s.y)[ch];
      EXPECT_NEAR(sh.layers[2].pixel(s.x, s.y)[ch] * to_plain, e, 1e-4 * e + 1e-7)
          << s.x << " " << s.y;
      for (int k = 0; k < 3; ++k) EXPECT_GE(rnm.layers[size_t(k)].pixel(s.x, s.y)[ch], 0.0f);
    }
}

TEST(RadiosityBaker, SameMapsForOneTwoAndFourThreads) {
  const Charted c(load_scene("cornell"), 24);
  std::vector<std::vector<float>> maps;
  for (const int threads : {1, 2, 4}) {
    RadiosityBakeOptions o = quiet(1e-2);
    o.basis = bake::LightmapBasis::kShL1;
    o.threads = threads;
    const RadiosityBake b = bake::bake_radiosity(c.scene, *c.tracer, c.raster, o);
    std::vector<float> all;
    for (const Image& layer : b.layers)
      all.insert(all.end(), layer.data().begin(), layer.data().end());
    maps.push_back(std::move(all));
  }
  EXPECT_EQ(maps[0], maps[1]);
  EXPECT_EQ(maps[0], maps[2]);
}

TEST(RadiosityBaker, RefusesBadOptionsAndASceneWithoutLight) {
  auto error_of = [](const nlohmann::json& j) -> std::string {
    try {
      RadiosityBakeOptions::from_params(Params(j, "opts.json"));
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of({{"threshold", -0.1}}).find("threshold"), std::string::npos);
  EXPECT_NE(error_of({{"threshold", 1.0}}).find("threshold"), std::string::npos);
  EXPECT_NE(error_of({{"group_size", 0}}).find("group_size"), std::string::npos);
  EXPECT_NE(error_of({{"sky_rays", 0}}).find("sky_rays"), std::string::npos);
  EXPECT_NE(error_of({{"basis", "hl2"}}).find("basis"), std::string::npos);
  EXPECT_EQ(error_of({{"threshold", 0.5}}), "");

  const Charted c(load_scene("cornell"), 24);
  RadiosityBakeOptions o = quiet();
  o.threshold = std::nan("");
  EXPECT_THROW(bake::bake_radiosity(c.scene, *c.tracer, c.raster, o), Error);

  Scene dark = c.scene;
  dark.lights.clear();
  for (Material& m : dark.materials) m.emission = Color(0.0f);
  const RayTracer tracer(dark);
  try {
    bake::bake_radiosity(dark, tracer, c.raster, quiet());
    ADD_FAILURE() << "a scene without light was baked";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has no light"), std::string::npos) << e.what();
  }
}

TEST(RadiosityBaker, CtrlCStopsTheBake) {
  const Charted c(load_scene("cornell"), 24);
  request_interrupt();
  EXPECT_THROW(bake::bake_radiosity(c.scene, *c.tracer, c.raster, quiet()), Interrupted);
  clear_interrupt();
}

}  // namespace
}  // namespace illum
