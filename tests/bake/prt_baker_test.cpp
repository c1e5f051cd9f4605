// PRT transfer (bake/prt_baker.h, prt_shooting.h, prt_relight.h): closed forms on an open
// plane, the ordering unshadowed ≥ shadowed ≤ interreflected, the furnace box's
// albedo/(1 − albedo) (also with a single-sided panel inside: two-sided shooting; and a dim
// box beside a bright one: the relative stop), determinism, and the options' ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "../render/render_test_scenes.h"
#include "bake_test_scenes.h"
#include "charted_cornell.h"
#include "illum/atlas/atlas.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/bake/prt_shooting.h"
#include "illum/bake/prt_vq.h"
#include "illum/core/sh.h"
#include "illum/scene/load.h"

namespace illum {
namespace {

using bake::PrtBake;
using bake::PrtBakeOptions;
using bake::PrtMode;

constexpr double kZ = 5.0;  // standard errors allowed for a Monte-Carlo estimate

PrtBakeOptions options_for(PrtMode mode, int bands, int spp) {
  PrtBakeOptions o;
  o.mode = mode;
  o.bands = bands;
  o.spp = spp;
  o.progress = false;
  o.seed = 7;
  return o;
}

// Σ_i T_i c_i (channel 0) for the transfer at `t`.
double apply(const float* t, const bake::ShLight& light) {
  double sum = 0.0;
  for (size_t i = 0; i < light.coefficients.size(); ++i)
    sum += double(t[i * 3]) * light.coefficients[i].x;
  return sum;
}

bake::ShLight constant_sky(int bands, float radiance) {
  Environment env;
  env.constant = Color(radiance);
  return bake::environment_light(bands, env);
}

// A 2 m plane facing +y with uv1 over the whole raster, alone in the world.
struct OpenPlane {
  OpenPlane() {
    const int mat = test::add_lambert(scene, Color(0.5f));
    test::add_instance(scene, test::uv_plane(1.0f, mat));
    tracer = std::make_unique<RayTracer>(scene);
    raster = atlas::rasterize_texels(scene, 16, 16);
  }
  Scene scene;
  std::unique_ptr<RayTracer> tracer;
  atlas::TexelRaster raster;
};

// Under a constant sky of radiance L an open plane receives E = πL: E/π = Σ T_i c_i = L.
// Unshadowed is the closed form; shadowed rays all escape and each weighs Y00 in c_0, so
// both are exact up to float rounding, at every texel, every vertex and every relit pixel.
TEST(PrtBaker, OpenPlaneUnderAConstantSkyIsExact) {
  OpenPlane plane;
  const float radiance = 2.0f;
  for (PrtMode mode : {PrtMode::kUnshadowed, PrtMode::kShadowed}) {
    SCOPED_TRACE(bake::to_string(mode));
    const PrtBake baked =
        bake_prt(plane.scene, *plane.tracer, plane.raster, options_for(mode, 4, 64));
    const bake::ShLight sky = constant_sky(4, radiance);
    ASSERT_EQ(baked.texels, plane.raster.covered());
    for (const atlas::TexelSample& s : plane.raster.samples)
      EXPECT_NEAR(apply(baked.texel_transfer.pixel(s.x, s.y), sky), radiance, 1e-5 * radiance);
    for (size_t v = 0; v < 4; ++v)
      EXPECT_NEAR(apply(&baked.vertex_transfer[0][v * 48], sky), radiance, 1e-5 * radiance);
    // Relit from above: albedo × L at every pixel (the camera sees the plane's inside only).
    baked::PrtSet set;
    set.bands = 4;
    set.texel_transfer = baked.texel_transfer;
    set.vertex_transfer = baked.vertex_transfer;
    Camera camera;
    camera.position = vec3(0.0f, 2.0f, 0.0f);
    camera.look_at = vec3(0.0f);
    camera.up = vec3(0.0f, 0.0f, -1.0f);
    camera.fov_y = radians(30.0f);
    bake::RelightOptions relight;
    relight.width = relight.height = 8;
    // Every texel has coefficient 0 exactly Y00 (unshadowed: the whole vector is the same),
    // so any VQ codebook's representatives, means of texels, keep it: the 4-tap lookup of
    // the compressed map must give the same pixels.
    set.atlas.width = baked.texel_transfer.width;
    set.atlas.height = baked.texel_transfer.height;
    bake::VqOptions vq;
    vq.representatives = 2;
    set.vq = bake::vq_compress(baked.texel_transfer.data, baked.texel_transfer.channels, vq);
    if (mode == PrtMode::kUnshadowed) {
      EXPECT_LT(set.vq.max_distance, 1e-6);
    }
    for (bake::PrtLookup lookup :
         {bake::PrtLookup::kTexels, bake::PrtLookup::kVertices, bake::PrtLookup::kVq}) {
      relight.lookup = lookup;
      const Image image = bake::relight(plane.scene, *plane.tracer, set, sky, camera, relight);
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_NEAR(image.rgb(x, y).x, 0.5f * radiance, 1e-5);
    }
  }
}

// With nothing in the way the shadowed estimate of every coefficient is the mean of Y_i over
// cosine-distributed directions, whose expectation is the unshadowed closed form and whose
// standard error is √(Var_cos[Y_i]/N); the variance, E_cos[Y_i²] − E_cos[Y_i]² with
// E_cos[f] = ∫_H f cos/π dω, comes from a fine quadrature (scrambled Sobol' points do better
// than independent samples, so the bound is on the safe side).
TEST(PrtBaker, ShadowedOpenPlaneMatchesTheClosedFormWithinItsError) {
  OpenPlane plane;
  const int bands = 6, spp = 256;
  const PrtBake exact = bake_prt(plane.scene, *plane.tracer, plane.raster,
                                 options_for(PrtMode::kUnshadowed, bands, spp));
  const PrtBake mc = bake_prt(plane.scene, *plane.tracer, plane.raster,
                              options_for(PrtMode::kShadowed, bands, spp));
  const sh::SphereQuadrature rule = sh::sphere_quadrature(96);
  std::vector<double> variance(size_t(sh::coefficient_count(bands)), 0.0);
  for (size_t i = 0; i < variance.size(); ++i) {
    double m1 = 0.0, m2 = 0.0;
    for (size_t q = 0; q < rule.directions.size(); ++q) {
      const glm::dvec3& w = rule.directions[q];
      const double pdf = std::max(w.y, 0.0) / kPi;  // the plane faces +y
      const double y = sh::evaluate(bands, w)[i];
      m1 += rule.weights[q] * pdf * y;
      m2 += rule.weights[q] * pdf * y * y;
    }
    variance[i] = std::max(m2 - m1 * m1, 0.0);
  }
  double worst = 0.0;
  for (const atlas::TexelSample& s : plane.raster.samples)
    for (int l = 0; l < bands; ++l)
      for (int m = -l; m <= l; ++m) {
        const int i = sh::index(l, m);
        const double bound = kZ * std::sqrt(variance[size_t(i)] / spp) + 1e-6;
        const double d = std::abs(double(mc.texel_transfer.pixel(s.x, s.y)[i * 3]) -
                                  double(exact.texel_transfer.pixel(s.x, s.y)[i * 3]));
        EXPECT_LE(d, bound) << "texel " << s.x << "," << s.y << " coefficient " << i;
        worst = std::max(worst, d / bound);
      }
  RecordProperty("worst_error_over_bound", std::to_string(worst));
}

using test::ChartedCornell;

// Under a constant sky (only c_0 ≠ 0) every ray's weight is Y00 > 0: blocking rays can only
// lower the transfer and bounced light can only add to it, texel by texel and vertex by
// vertex (same seed, so the interreflected bake starts from the shadowed one).
TEST(PrtBaker, ShadowedIsBelowUnshadowedAndInterreflectedAbove) {
  const ChartedCornell cornell;
  auto bake = [&](PrtMode mode) {
    return bake_prt(cornell.scene, *cornell.tracer, cornell.raster, options_for(mode, 3, 32));
  };
  const PrtBake un = bake(PrtMode::kUnshadowed), sh = bake(PrtMode::kShadowed),
                in = bake(PrtMode::kInterreflected);
  const bake::ShLight sky = constant_sky(3, 1.0f);
  int shadowed = 0, brighter = 0;
  for (const atlas::TexelSample& s : cornell.raster.samples) {
    const double u = apply(un.texel_transfer.pixel(s.x, s.y), sky);
    const double d = apply(sh.texel_transfer.pixel(s.x, s.y), sky);
    const double b = apply(in.texel_transfer.pixel(s.x, s.y), sky);
    EXPECT_LE(d, u + 1e-6);
    EXPECT_GE(b, d - 1e-6);
    shadowed += d < 0.9 * u;
    brighter += b > 1.05 * d;
  }
  // Not vacuous: the box shadows most of its inside, and bounces brighten it.
  EXPECT_GT(shadowed, int(cornell.raster.covered() / 2));
  EXPECT_GT(brighter, int(cornell.raster.covered() / 2));
  const size_t p = 3 * 9;
  for (size_t i = 0; i < un.vertex_transfer.size(); ++i)
    for (size_t v = 0; v < un.vertex_transfer[i].size() / p; ++v) {
      const double u = apply(&un.vertex_transfer[i][v * p], sky);
      const double d = apply(&sh.vertex_transfer[i][v * p], sky);
      const double b = apply(&in.vertex_transfer[i][v * p], sky);
      EXPECT_LE(d, u + 1e-6);
      EXPECT_GE(b, d - 1e-6);
    }
}

// Flat normals (the winding's) on every mesh, then a 64² atlas applied: the furnace
// scenes' texel raster.
atlas::TexelRaster flat_shaded_atlas(Scene& scene) {
  for (Mesh& mesh : scene.meshes)
    for (size_t k = 0; k < mesh.positions.size(); k += 3) {
      const vec3 n = glm::normalize(glm::cross(mesh.positions[k + 1] - mesh.positions[k],
                                               mesh.positions[k + 2] - mesh.positions[k]));
      mesh.normals.insert(mesh.normals.end(), {n, n, n});
    }
  atlas::AtlasOptions atlas_options;
  atlas_options.resolution = 64;
  const atlas::Atlas atlas = atlas::build_atlas(scene, atlas_options);
  atlas::apply_atlas(scene, atlas);
  return atlas::rasterize_texels(scene, atlas.width, atlas.height);
}

// Mean of a sample, its spread (standard deviation) and the mean's standard error.
struct SampleMean {
  explicit SampleMean(const std::vector<double>& v) {
    mean = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
    double var = 0.0;
    for (double x : v) var += (x - mean) * (x - mean);
    var /= double(v.size() - 1);
    spread = std::sqrt(var);
    error = std::sqrt(var / double(v.size()));
  }
  double mean = 0.0, spread = 0.0, error = 0.0;
};

// Every patch's bounce share (its red transfer over T0 = 1, less the 1) must average
// `expected` within 5 standard errors of the mean over patches plus `allowance` (what the
// shooting may leave unshot).
void expect_mean_bounce_share(const std::vector<float>& transfer, double expected,
                              double allowance) {
  std::vector<double> share(transfer.size() / 3);
  for (size_t k = 0; k < share.size(); ++k) share[k] = double(transfer[k * 3]) - 1.0;
  const SampleMean m(share);
  EXPECT_NEAR(m.mean, expected, kZ * m.error + allowance)
      << "patches " << share.size() << ", spread " << m.spread;
}

// A closed box of albedo a whose every patch starts with the same transfer T0 (a stand-in
// for direct light): every point then sees only the box, so T = T0 + a·T everywhere and
// T = T0/(1 − a), the bounce share a/(1 − a). Shooting conserves what it shoots (every ray
// lands on the box), so the area-weighted total is exact up to the unshot remainder, which
// the loop bounds by `tolerance` × the initial unshot total: bounce/direct lies in
// [a/(1−a) − tol·a/(1−a), a/(1−a)] up to float rounding.
TEST(PrtShooting, ClosedFurnaceBoxConvergesToAlbedoOverOneMinusAlbedo) {
  const float a = 0.6f;
  Scene scene;
  const int mat = test::add_lambert(scene, Color(a));
  test::add_triangles(scene, test::inward_box(vec3(-1.0f), vec3(1.0f)), mat, "box");
  const atlas::TexelRaster raster = flat_shaded_atlas(scene);
  const RayTracer tracer(scene);
  const double expected = a / (1.0 - a);

  bake::TransferShootingOptions options;
  options.rays = 16;
  options.tolerance = 1e-3;
  options.max_rounds = 1000;
  for (bool texels : {true, false}) {
    SCOPED_TRACE(texels ? "texels" : "vertices");
    const bake::PrtPatches set =
        texels ? bake::texel_patches(scene, raster) : bake::vertex_patches(scene);
    double total_area = 0.0;
    for (const auto& patch : set.patches) total_area += patch.area;
    EXPECT_NEAR(total_area, 24.0, 24.0 * 1e-5);  // the clipped texel areas sum to the box's
    std::vector<float> transfer(set.patches.size() * 3, 1.0f);
    const bake::TransferShootingResult result =
        bake::shoot_transfer(tracer, set.patches, set.receiver, 3, transfer, options);
    EXPECT_LE(result.unshot_fraction, options.tolerance);
    double weighted = 0.0;
    for (size_t k = 0; k < set.patches.size(); ++k)
      weighted += double(set.patches[k].area) * (double(transfer[k * 3]) - 1.0);
    const double ratio = weighted / total_area;
    EXPECT_LE(ratio, expected * (1.0 + 1e-4));
    EXPECT_GE(ratio, expected * (1.0 - options.tolerance) - 1e-4);
    // Patch by patch the bounce share scatters around a/(1 − a) (each receives a few hundred
    // rays per round); the mean over patches must agree within its standard error, which a
    // wrong patch area (a texel's clipped area, a vertex's third) would break at chart
    // borders and corners.
    expect_mean_bounce_share(transfer, expected, expected * options.tolerance);
  }
}

// The closed furnace box with a single-sided panel floating inside (1.6 × 1.6 m, facing +y):
// the path tracer's opaque materials are two-sided, so the panel's back reflects what lands
// on it like its front. Every patch side starts with T0 = 1 (the panel's back through
// back_direct), every direction from any point inside meets some side, all of albedo a:
// T = T0 + a·T again, the bounce share a/(1 − a) on every front. Dropping the light that
// lands on the panel's back (5–9 % of the shot light here) took the texels' mean share to
// 1.33. Tolerance: 5 standard errors of the mean over patches (the spread of the per-patch
// shares over √N, N ≈ 2 200 texels or 42 vertices) plus the unshot remainder, as above. The shares
// of the shot light: nothing escapes or is lost in a closed box, and the backs get their part.
TEST(PrtShooting, SingleSidedPanelInAFurnaceBoxReflectsOnBothSides) {
  const float a = 0.6f;
  Scene scene;
  const int mat = test::add_lambert(scene, Color(a));
  test::add_triangles(scene, test::inward_box(vec3(-1.0f), vec3(1.0f)), mat, "box");
  std::vector<vec3> panel;
  test::push_quad(panel, {-0.8f, 0.0f, 0.8f}, {0.8f, 0.0f, 0.8f}, {0.8f, 0.0f, -0.8f},
                  {-0.8f, 0.0f, -0.8f});
  const int panel_instance = test::add_triangles(scene, panel, mat, "panel");
  const atlas::TexelRaster raster = flat_shaded_atlas(scene);
  const RayTracer tracer(scene);
  const double expected = a / (1.0 - a);
  const size_t box_vertices = scene.meshes[0].vertex_count();

  bake::TransferShootingOptions options;
  options.rays = 16;
  options.tolerance = 1e-3;
  options.max_rounds = 1000;
  for (bool texels : {true, false}) {
    SCOPED_TRACE(texels ? "texels" : "vertices");
    const bake::PrtPatches set =
        texels ? bake::texel_patches(scene, raster) : bake::vertex_patches(scene);
    double total_area = 0.0;
    for (const auto& patch : set.patches) total_area += patch.area;
    EXPECT_NEAR(total_area, 24.0 + 2.56, 26.56 * 1e-5);
    std::vector<float> transfer(set.patches.size() * 3, 1.0f);
    std::vector<float> back(set.patches.size() * 3, 0.0f);
    for (size_t k = 0; k < set.patches.size(); ++k) {
      const bool on_panel =
          texels ? raster.samples[k].instance == panel_instance : k >= box_vertices;
      if (on_panel) std::fill_n(&back[k * 3], 3, 1.0f);
    }
    const bake::TransferShootingResult result =
        bake::shoot_transfer(tracer, set.patches, set.receiver, 3, transfer, options, back);
    EXPECT_LE(result.unshot_fraction, options.tolerance);
    EXPECT_NEAR(result.shares.escaped, 0.0, 1e-9);
    EXPECT_NEAR(result.shares.lost, 0.0, 1e-9);
    EXPECT_GT(result.shares.back, 0.03);  // about 5 % here: not vacuous
    EXPECT_NEAR(result.shares.front + result.shares.back + result.shares.below, 1.0, 1e-6);
    expect_mean_bounce_share(transfer, expected, expected * options.tolerance);
  }
}

// Two closed furnace boxes of albedo a, apart: a bright one (T0 = 1) and a dim one (T0 =
// 1e-4, as Sibenik's nave beside its sunlit town). The absolute stop alone (unshot total ≤
// 1e-3 × the initial) is met before the dim box ever shoots, which leaves its bounce share at
// 0 for a/(1 − a) = 1.5; the relative stop shoots it too. Bound: at the stop the area-weighted
// mean of min(1, Σ|U|/Σ|aT|) is ≤ r (relative_tolerance), so over the dim box, half the
// area, ≤ 2r; what it has yet to receive is Σ A·U/(1 − a) ≤ a·T·2r·A/(1 − a) with T ≤
// 1/(1 − a) (in units of T0): its mean share lies within 2r·a/(1 − a)² (0.075 at r = 0.01)
// below a/(1 − a), plus 5 standard errors of the mean over its patches either side.
TEST(PrtShooting, DimRoomBesideABrightOneConvergesToo) {
  const float a = 0.6f;
  Scene scene;
  const int mat = test::add_lambert(scene, Color(a));
  test::add_triangles(scene, test::inward_box(vec3(-1.0f), vec3(1.0f)), mat, "bright");
  const int dim_instance = test::add_triangles(
      scene, test::inward_box(vec3(3.0f, -1.0f, -1.0f), vec3(5.0f, 1.0f, 1.0f)), mat, "dim");
  const atlas::TexelRaster raster = flat_shaded_atlas(scene);
  const RayTracer tracer(scene);
  const bake::PrtPatches set = bake::texel_patches(scene, raster);
  const float dim = 1e-4f;
  std::vector<float> transfer(set.patches.size() * 3, 1.0f);
  for (size_t k = 0; k < set.patches.size(); ++k)
    if (raster.samples[k].instance == dim_instance) std::fill_n(&transfer[k * 3], 3, dim);

  bake::TransferShootingOptions options;
  options.rays = 16;
  options.tolerance = 1e-3;
  options.relative_tolerance = 0.01;
  options.max_rounds = 1000;
  const bake::TransferShootingResult result =
      bake::shoot_transfer(tracer, set.patches, set.receiver, 3, transfer, options);
  EXPECT_LE(result.unshot_fraction, options.tolerance);
  EXPECT_LE(result.relative_unshot, options.relative_tolerance);
  std::vector<double> share;
  for (size_t k = 0; k < set.patches.size(); ++k)
    if (raster.samples[k].instance == dim_instance)
      share.push_back(double(transfer[k * 3]) / double(dim) - 1.0);
  const SampleMean m(share);
  const double expected = a / (1.0 - a);
  const double unshot_bound = 2.0 * options.relative_tolerance * a / ((1.0 - a) * (1.0 - a));
  EXPECT_LE(m.mean, expected + kZ * m.error) << "patches " << share.size();
  EXPECT_GE(m.mean, expected - unshot_bound - kZ * m.error) << "patches " << share.size();
}

TEST(PrtBaker, SameSeedSameTransferWhateverTheThreads) {
  const ChartedCornell cornell;
  PrtBakeOptions o = options_for(PrtMode::kInterreflected, 2, 8);
  o.threads = 1;
  const PrtBake one = bake_prt(cornell.scene, *cornell.tracer, cornell.raster, o);
  o.threads = 2;
  const PrtBake two = bake_prt(cornell.scene, *cornell.tracer, cornell.raster, o);
  EXPECT_EQ(one.texel_transfer.data, two.texel_transfer.data);
  EXPECT_EQ(one.vertex_transfer, two.vertex_transfer);
}

// A texel's direct transfer depends on nothing but its own sample and the seed (its rays
// are seeded by its atlas coordinates), so a bake of a few texels gives them the values a
// bake of the whole raster does: `illum-bench prt-vs-path` bakes the texels a camera sees
// over many seeds that way, for the relit side's σ (bench/suites/prt_direct_spread.h).
TEST(PrtBaker, ShadowedTexelTransferDoesNotDependOnTheOtherTexels) {
  const ChartedCornell cornell;
  PrtBakeOptions o = options_for(PrtMode::kShadowed, 3, 16);
  o.vertices = false;
  o.dilate = 0;
  const PrtBake whole = bake_prt(cornell.scene, *cornell.tracer, cornell.raster, o);
  atlas::TexelRaster some;
  some.width = cornell.raster.width;
  some.height = cornell.raster.height;
  some.sample_of.assign(cornell.raster.sample_of.size(), -1);
  for (size_t k = 0; k < cornell.raster.samples.size(); k += 3) {
    const atlas::TexelSample& s = cornell.raster.samples[k];
    some.sample_of[size_t(s.y) * size_t(some.width) + size_t(s.x)] = int32_t(some.samples.size());
    some.samples.push_back(s);
  }
  const PrtBake part = bake_prt(cornell.scene, *cornell.tracer, some, o);
  ASSERT_GT(some.samples.size(), 100u);
  const size_t channels = size_t(whole.texel_transfer.channels);
  size_t differ = 0;
  for (const atlas::TexelSample& s : some.samples)
    differ += !std::equal(part.texel_transfer.pixel(s.x, s.y),
                          part.texel_transfer.pixel(s.x, s.y) + channels,
                          whole.texel_transfer.pixel(s.x, s.y));
  EXPECT_EQ(differ, 0u) << "of " << some.samples.size() << " texels";
}

TEST(PrtBaker, RefusesOptionsOutOfRange) {
  auto error = [](const nlohmann::json& j) -> std::string {
    try {
      PrtBakeOptions::from_params(Params(j, "opts"));
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error({{"bands", 1}}).find("bands"), std::string::npos);
  EXPECT_NE(error({{"bands", 9}}).find("bands"), std::string::npos);
  EXPECT_NE(error({{"mode", "nonsense"}}).find("nonsense"), std::string::npos);
  EXPECT_NE(error({{"spp", 0}}).find("spp"), std::string::npos);
  EXPECT_EQ(error({{"bands", 8}, {"mode", "interreflected"}}), "");
  EXPECT_NE(error({{"normal_map_samples", 0}}).find("normal_map_samples"), std::string::npos);
  EXPECT_NE(error({{"normal_map_samples", 5000}}).find("normal_map_samples"), std::string::npos);
  EXPECT_NE(error({{"normal_maps", 3}}).find("normal_maps"), std::string::npos);
  EXPECT_EQ(error({{"normal_maps", false}, {"normal_map_samples", 64}}), "");
  EXPECT_NE(error({{"shoot_relative_tolerance", 0.0}}).find("shoot_relative_tolerance"),
            std::string::npos);
  EXPECT_NE(error({{"shoot_relative_tolerance", 2.0}}).find("shoot_relative_tolerance"),
            std::string::npos);
  EXPECT_THROW(bake::sun_light(4, vec3(0.0f), Color(1.0f)), Error);
  EXPECT_THROW(bake::sun_light(4, vec3(NAN, 1.0f, 0.0f), Color(1.0f)), Error);
  Environment dark;
  EXPECT_THROW(bake::environment_light(4, dark), Error);  // an unlit environment
}

}  // namespace
}  // namespace illum
