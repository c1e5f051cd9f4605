// The extra light-map maps (bake/lightmap_extras.h): analytic cases and the offline `ao`
// integrator as the reference.
//
// Tolerances. Texels have their own scrambled Sobol' sequences, so they are independent
// estimates. Where an estimate is a mean of n per-ray values of variance σ², its variance is
// at most 2σ²/n: the rays' directions are a scrambled (0,2)-sequence in base 2, whose
// variance Owen (1997) bounds by (b/(b−1))^(s−1) = 2 times plain Monte Carlo's. Checks are
// |difference| ≤ kZ·(standard error) + (a stated bound on any deterministic bias), kZ = 5.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "../render/render_test_scenes.h"
#include "bake_test_scenes.h"
#include "charted_cornell.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_extras.h"
#include "illum/core/error.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

using bake::LightmapExtras;
using bake::LightmapExtrasOptions;

using test::ChartedCornell;

constexpr double kZ = 5.0;
constexpr double kNetFactor = 2.0;  // Owen's bound for a scrambled (0,2)-sequence, base 2
constexpr double kPiD = std::numbers::pi;

LightmapExtrasOptions all_extras(int rays) {
  LightmapExtrasOptions o;
  o.ao = o.obscurance = o.bent_normal = true;
  o.rays = rays;
  o.seed = 7;
  o.progress = false;
  o.dilate = 0;
  return o;
}

// A raster of hand-placed sample points on the y = 0 floor (normal +y), one texel each.
atlas::TexelRaster floor_points(const std::vector<vec3>& points) {
  atlas::TexelRaster r;
  r.width = static_cast<int>(points.size());
  r.height = 1;
  for (size_t i = 0; i < points.size(); ++i) {
    atlas::TexelSample s;
    s.x = static_cast<int>(i);
    s.position = points[i];
    s.normal = s.geometric_normal = vec3(0, 1, 0);
    r.samples.push_back(s);
    r.sample_of.push_back(static_cast<int32_t>(i));
  }
  return r;
}

struct Stats {
  double mean = 0, sd = 0;  // sd: spread of the values (one per texel)
  size_t n = 0;
};
template <class F>
Stats stats_over(const atlas::TexelRaster& r, F value) {
  double s = 0, s2 = 0;
  for (const atlas::TexelSample& t : r.samples) {
    const double v = value(t);
    s += v;
    s2 += v * v;
  }
  Stats st;
  st.n = r.samples.size();
  st.mean = s / double(st.n);
  st.sd = std::sqrt(std::max(s2 / double(st.n) - st.mean * st.mean, 0.0) * double(st.n) /
                    double(st.n - 1));
  return st;
}

// The floor y = 0 (x ≤ 0) meeting a wall x = 0 at a right angle, both 2·kHalf wide.
constexpr float kHalf = 100.0f;
Scene corner_scene() {
  Scene s;
  const int mat = test::add_lambert(s, Color(0.5f));
  std::vector<vec3> floor, wall;
  test::push_quad(floor, {-2 * kHalf, 0, kHalf}, {0, 0, kHalf}, {0, 0, -kHalf},
                  {-2 * kHalf, 0, -kHalf});
  test::push_quad(wall, {0, 0, -kHalf}, {0, 0, kHalf}, {0, 2 * kHalf, kHalf},
                  {0, 2 * kHalf, -kHalf});
  test::add_triangles(s, floor, mat, "floor");
  test::add_triangles(s, wall, mat, "wall");
  return s;
}

TEST(LightmapExtras, OpenPlaneIsUnoccludedAndUnobscured) {
  // Nothing above the plane: every ray escapes, so ao = obscurance = 1 exactly, the colour
  // obscurance is R_ave (= the plane's albedo), and no estimate has any noise.
  Scene s;
  const int mat = test::add_lambert(s, Color(0.2f, 0.5f, 0.8f));
  test::add_instance(s, test::uv_plane(1.0f, mat));
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 8, 8);
  const LightmapExtras e = bake::bake_lightmap_extras(s, tracer, raster, all_extras(64));
  EXPECT_EQ(e.rays, int64_t(64) * int64_t(raster.covered()));
  for (const atlas::TexelSample& t : raster.samples) {
    EXPECT_EQ(e.ao.rgb(t.x, t.y), Color(1.0f));
    EXPECT_EQ(e.obscurance.rgb(t.x, t.y), Color(1.0f));
    const Color c = e.obscurance_color.rgb(t.x, t.y);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], e.average_albedo[k], 1e-6f);
    EXPECT_GT(e.bent_normal.rgb(t.x, t.y).y, 0.99f);  // the mean of cosine directions: ~n
  }
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.average_albedo[k], (Color(0.2f, 0.5f, 0.8f))[k], 1e-6f);
}

TEST(LightmapExtras, InsideCornerMatchesClosedForms) {
  // A floor point at distance x0 from an infinite perpendicular wall, infinite AO distance:
  // every direction with a component towards the wall hits it, so the unoccluded set is the
  // half hemisphere away from it. For a wedge of opening angle α the cosine-weighted open
  // fraction is (1 − cos α)/2 (the sky-view factor of a plane tilted by π − α), 1/2 at
  // α = 90°. The bent normal is the cosine-weighted mean of that half: (−2/(3π), 1/3, 0)
  // normalised. Obscurance with d_max: directions project uniformly onto the floor's unit
  // disc (a, b) with hit distance x0/a for a > 0, so W = 1 − (1/π)∫_{a0}^1 2√(1−a²)
  // (1 − √(a0/a)) da, a0 = x0/d_max (quadrature below).
  // Finite walls (±100 at x0 = 0.05): rays escape past the wall's sides only within
  // δ = x0/100 of grazing it, a cosine-weighted share below 2δ/π = 3.2e-4 (kFiniteBias).
  const Scene s = corner_scene();
  const RayTracer tracer(s);
  const float x0 = 0.05f;
  std::vector<vec3> points;
  for (int i = 0; i < 64; ++i) points.push_back(vec3(-x0, 0.0f, -40.0f + 80.0f * i / 63.0f));
  const atlas::TexelRaster raster = floor_points(points);
  const int rays = 1024;
  LightmapExtrasOptions o = all_extras(rays);
  o.ao_distance = 1e6f;
  const LightmapExtras e = bake::bake_lightmap_extras(s, tracer, raster, o);
  const double kFiniteBias = 2.0 * (x0 / kHalf) / kPiD;

  const Stats ao = stats_over(raster, [&](const auto& t) { return e.ao.rgb(t.x, t.y).x; });
  const double ao_se = std::sqrt(kNetFactor * 0.25 / (double(rays) * double(ao.n)));
  EXPECT_NEAR(ao.mean, 0.5, kZ * ao_se + kFiniteBias) << "se " << ao_se;

  // Bent normal: the per-texel estimates' spread gives the standard error of their mean;
  // normalising a mean of 1024 directions biases it by O(1/rays), under 1e-3 (kNormBias).
  const double kNormBias = 1e-3;
  const vec3 expected_bent = glm::normalize(vec3(float(-2.0 / (3.0 * kPiD)), 1.0f / 3.0f, 0.0f));
  for (int k = 0; k < 3; ++k) {
    const Stats b =
        stats_over(raster, [&](const auto& t) { return e.bent_normal.rgb(t.x, t.y)[k]; });
    EXPECT_NEAR(b.mean, expected_bent[k],
                kZ * b.sd / std::sqrt(double(b.n)) + kNormBias + kFiniteBias)
        << "bent normal component " << k;
  }

  // Obscurance against the quadrature of its closed form (d_max = 0.3, the default).
  const double a0 = x0 / double(o.obscurance_dmax);
  double w = 0, w2 = 0;
  const int steps = 200000;
  for (int i = 0; i < steps; ++i) {
    const double a = a0 + (1.0 - a0) * (i + 0.5) / steps;
    const double disc = 2.0 * std::sqrt(1.0 - a * a) * (1.0 - a0) / steps / kPiD;
    w += disc * (1.0 - std::sqrt(a0 / a));
    w2 += disc * (1.0 - a0 / a);
  }
  const double expected_w = 1.0 - w, var_w = (1.0 - w2) - expected_w * expected_w;
  const Stats ob = stats_over(raster, [&](const auto& t) { return e.obscurance.rgb(t.x, t.y).x; });
  const double ob_se = std::sqrt(kNetFactor * var_w / (double(rays) * double(ob.n)));
  EXPECT_NEAR(ob.mean, expected_w, kZ * ob_se + 1e-5) << "se " << ob_se;
  std::printf("corner: ao %.5f (1/2), obscurance %.5f (%.5f), bent normal (%.4f, %.4f)\n", ao.mean,
              ob.mean, expected_w, expected_bent.x, expected_bent.y);

  // ω ≡ 1 (d_max → 0): no surface is ever closer than d_max, so W = 1 at every texel.
  o.obscurance_dmax = 1e-7f;
  const LightmapExtras e0 = bake::bake_lightmap_extras(s, tracer, raster, o);
  for (const atlas::TexelSample& t : raster.samples)
    EXPECT_EQ(e0.obscurance.rgb(t.x, t.y), Color(1.0f));
}

// Two facing planes a gap D apart: at a point of the lower one, a cosine-distributed ray
// with cos θ = c hits the upper plane at D/c, and c has density 2c, so with c0 = D/d_max
//   W = ∫ρ(D/c)·2c dc = c0² + (4/3)√c0·(1 − c0^{3/2}),  E[ρ²] = c0² + 2c0(1 − c0).
// Texels more than d_max + one texel from the planes' edges see exactly this.
struct Parallel {
  Scene scene;
  float gap = 0.1f, d_max = 0.3f, half = 2.0f;
  double w() const {
    const double c0 = gap / d_max;
    return c0 * c0 + 4.0 / 3.0 * std::sqrt(c0) * (1.0 - std::pow(c0, 1.5));
  }
  double var() const {
    const double c0 = gap / d_max;
    return c0 * c0 + 2.0 * c0 * (1.0 - c0) - w() * w();
  }
  bool central(const atlas::TexelSample& t, float texel) const {
    return std::abs(t.position.x) < half - d_max - texel &&
           std::abs(t.position.z) < half - d_max - texel;
  }
};
Parallel parallel_planes() {
  Parallel p;
  const int mat = test::add_lambert(p.scene, Color(0.5f));
  test::add_instance(p.scene, test::uv_plane(p.half, mat));
  std::vector<vec3> top;
  const float h = p.half;
  test::push_quad(top, {-h, p.gap, -h}, {h, p.gap, -h}, {h, p.gap, h}, {-h, p.gap, h});
  test::add_triangles(p.scene, top, mat, "top");  // no uv1: not in the raster
  return p;
}

TEST(LightmapExtras, ObscuranceBetweenParallelPlanesPerTexelAndGlobalLines) {
  const Parallel p = parallel_planes();
  const RayTracer tracer(p.scene);
  const int size = 32;
  const float texel = 2.0f * p.half / size;
  const atlas::TexelRaster raster = atlas::rasterize_texels(p.scene, size, size);
  LightmapExtrasOptions o = all_extras(256);
  o.obscurance_dmax = p.d_max;
  const LightmapExtras e = bake::bake_lightmap_extras(p.scene, tracer, raster, o);
  double s = 0;
  size_t n = 0;
  for (const atlas::TexelSample& t : raster.samples)
    if (p.central(t, texel)) {
      s += e.obscurance.rgb(t.x, t.y).x;
      ++n;
    }
  ASSERT_GT(n, 100u);
  const double se = std::sqrt(kNetFactor * p.var() / (256.0 * double(n)));
  EXPECT_NEAR(s / double(n), p.w(), kZ * se) << "per texel, se " << se;

  // Global lines: all lines of one direction cross the gap at the same angle, so
  // directions, not lines, are the independent samples. Each run of one direction gives a
  // (Σρ, count) pair over the central texels; the pooled ratio Σ_k Σρ_k / Σ_k count_k has
  // the delta-method variance Σ_k (Σρ_k − R·count_k)² / (Σ_k count_k)².
  std::vector<double> sums, counts;
  for (int k = 0; k < 300; ++k) {
    bake::GlobalLineObscuranceOptions g;
    g.directions = 1;
    g.lines_per_direction = 200;
    g.obscurance_dmax = p.d_max;
    g.seed = uint64_t(k);
    const bake::GlobalLineObscurance gl = bake::obscurance_global_lines(p.scene, tracer, raster, g);
    double ss = 0, cc = 0;
    for (const atlas::TexelSample& t : raster.samples)
      if (p.central(t, texel)) {
        const double c = gl.count.pixel(t.x, t.y)[0];
        ss += c * gl.obscurance.rgb(t.x, t.y).x;
        cc += c;
      }
    sums.push_back(ss);
    counts.push_back(cc);
  }
  double ss = 0, cc = 0;
  for (size_t k = 0; k < sums.size(); ++k) ss += sums[k], cc += counts[k];
  const double ratio = ss / cc;
  double v = 0;
  for (size_t k = 0; k < sums.size(); ++k) v += std::pow(sums[k] - ratio * counts[k], 2);
  const double gl_se = std::sqrt(v) / cc;
  EXPECT_NEAR(ratio, p.w(), kZ * gl_se) << "global lines, se " << gl_se;
  std::printf("parallel planes: W = %.5f; per texel %.5f (se %.5f), global lines %.5f (se %.5f)\n",
              p.w(), s / double(n), se, ratio, gl_se);
}

// A camera just off the texel's point along its normal with a tiny field of view sees the
// texel's point (footprint ~1e-7 m), so the `ao` integrator's pixel estimates the baked
// texel's estimand at the same point with the same normal.
double ao_integrator_at(const RayTracer& tracer, const atlas::TexelSample& t, int spp, int samples,
                        uint64_t seed) {
  Camera cam;
  const float scale = 1e-3f;
  cam.position = t.position + scale * t.normal;
  cam.look_at = t.position;
  cam.up = std::abs(t.normal.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
  cam.fov_y = 1e-4f;
  RenderOptions ro;
  ro.width = ro.height = 1;
  ro.spp = spp;
  ro.seed = seed;
  ro.progress = false;
  const auto ao = Integrator::create("ao", Params({{"samples", samples}}, "test"));
  return ao->render(tracer, cam, ro).pixel(0, 0)[0];
}

TEST(LightmapExtras, AoAgreesWithTheAoIntegratorOnCornell) {
  // Both with their default distance (0.1 × the scene's diagonal). Per texel the two
  // estimates of the same p differ by at most kZ·√(2·p(1−p)·(1/n_b + 1/n_i)) (binomial
  // variances, times kNetFactor), p estimated by the pooled mean; where the pooled p is 0
  // or 1 both estimates must be equal. Then the sum of all differences against the sum of
  // the variances, which catches a small shift every texel hides in its own noise.
  const ChartedCornell cornell(32);
  const Scene& s = cornell.scene;
  const RayTracer& tracer = *cornell.tracer;
  const atlas::TexelRaster& raster = cornell.raster;
  const int rays = 256, spp = 4, samples = 64;
  LightmapExtrasOptions o = all_extras(rays);
  o.obscurance = o.bent_normal = false;
  const LightmapExtras e = bake::bake_lightmap_extras(s, tracer, raster, o);
  double diff_sum = 0, var_sum = 0, worst = 0;
  int compared = 0, partial = 0;
  for (size_t i = 0; i < raster.samples.size(); i += 7) {
    const atlas::TexelSample& t = raster.samples[i];
    const double b = e.ao.rgb(t.x, t.y).x;
    const double r = ao_integrator_at(tracer, t, spp, samples, 100 + i);
    const double p = 0.5 * (b + r);
    const double var = kNetFactor * p * (1 - p) * (1.0 / rays + 1.0 / (spp * samples));
    ++compared;
    if (var == 0.0) {
      EXPECT_EQ(b, r) << "texel " << t.x << "," << t.y;
      continue;
    }
    ++partial;
    const double z = (b - r) / std::sqrt(var);
    worst = std::max(worst, std::abs(z));
    EXPECT_LE(std::abs(z), kZ) << "texel " << t.x << "," << t.y << ": baked " << b
                               << ", ao integrator " << r;
    diff_sum += b - r;
    var_sum += var;
  }
  ASSERT_GT(partial, 30);
  const double z_all = diff_sum / std::sqrt(var_sum);
  EXPECT_LE(std::abs(z_all), kZ);
  std::printf("cornell: %d texels compared (%d partly occluded), worst |z| %.2f, pooled z %.2f\n",
              compared, partial, worst, z_all);
}

TEST(LightmapExtras, GlobalLinesAgainstPerTexelOnCornellAtEqualRays) {
  // A measurement (printed; docs/lightmaps.md quotes it): the global-line map and the
  // per-texel map at the same number of ray queries, each against a per-texel reference at
  // 16× the rays, RMSE over texels the lines reached. The check: global lines leave no
  // reached texel outside [0, 1] and reach most texels.
  const ChartedCornell cornell(48);
  const Scene& s = cornell.scene;
  const RayTracer& tracer = *cornell.tracer;
  const atlas::TexelRaster& raster = cornell.raster;
  const int rays = 32;
  LightmapExtrasOptions o = all_extras(rays);
  o.ao = o.bent_normal = false;
  const LightmapExtras per_texel = bake::bake_lightmap_extras(s, tracer, raster, o);
  o.rays = 16 * rays;
  o.seed = 99;
  const LightmapExtras reference = bake::bake_lightmap_extras(s, tracer, raster, o);
  bake::GlobalLineObscuranceOptions g;
  g.directions = bake::kDefaultExtraRays;
  // Tune the line count to the per-texel ray budget: one trial direction tells the rays a
  // line costs on average.
  bake::GlobalLineObscuranceOptions trial = g;
  trial.directions = 4;
  trial.lines_per_direction = 1000;
  const auto t = bake::obscurance_global_lines(s, tracer, raster, trial);
  const double rays_per_line = double(t.rays) / (4.0 * 1000.0);
  g.lines_per_direction = int64_t(double(per_texel.rays) / (rays_per_line * g.directions));
  const auto gl = bake::obscurance_global_lines(s, tracer, raster, g);
  double e_gl = 0, e_pt = 0;
  size_t reached = 0;
  for (const atlas::TexelSample& x : raster.samples) {
    const double ref = reference.obscurance.rgb(x.x, x.y).x;
    if (gl.count.pixel(x.x, x.y)[0] > 0) {
      const double v = gl.obscurance.rgb(x.x, x.y).x;
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0);
      e_gl += (v - ref) * (v - ref);
      e_pt += std::pow(per_texel.obscurance.rgb(x.x, x.y).x - ref, 2);
      ++reached;
    }
  }
  EXPECT_GT(reached, raster.covered() / 2);
  std::printf(
      "cornell %dx%d, %zu texels, d_max 0.3: per texel %d rays: %lld rays %.3fs, RMSE %.4f; "
      "global lines %d dirs x %lld lines: %lld rays %.3fs, RMSE %.4f, %zu texels reached\n",
      raster.width, raster.height, raster.covered(), rays, (long long)per_texel.rays,
      per_texel.seconds, std::sqrt(e_pt / double(reached)), g.directions,
      (long long)g.lines_per_direction, (long long)gl.rays, gl.seconds,
      std::sqrt(e_gl / double(reached)), reached);
}

TEST(LightmapExtras, ByteIdenticalForOneAndTwoThreads) {
  const ChartedCornell cornell(32);
  const Scene& s = cornell.scene;
  const RayTracer& tracer = *cornell.tracer;
  const atlas::TexelRaster& raster = cornell.raster;
  std::vector<Image> maps[2];
  for (int threads : {1, 2}) {
    LightmapExtrasOptions o = all_extras(16);
    o.threads = threads;
    o.dilate = 2;
    const LightmapExtras e = bake::bake_lightmap_extras(s, tracer, raster, o);
    bake::GlobalLineObscuranceOptions g;
    g.directions = 8;
    g.lines_per_direction = 50;
    g.threads = threads;
    const auto gl = bake::obscurance_global_lines(s, tracer, raster, g);
    maps[threads - 1] = {e.ao,          e.obscurance,  e.obscurance_color,
                         e.bent_normal, gl.obscurance, gl.count};
  }
  for (size_t m = 0; m < maps[0].size(); ++m) {
    const Image &x = maps[0][m], &y = maps[1][m];
    ASSERT_EQ(x.channels(), y.channels());
    for (int j = 0; j < x.height(); ++j)
      for (int i = 0; i < x.width(); ++i)
        for (int c = 0; c < x.channels(); ++c)
          ASSERT_EQ(x.pixel(i, j)[c], y.pixel(i, j)[c])
              << "map " << m << " texel " << i << "," << j;
  }
}

TEST(LightmapExtras, RefusesBadOptionsAndNames) {
  LightmapExtrasOptions o;
  EXPECT_THROW(o.select("ao,fog"), Error);
  EXPECT_THROW(o.select("ao,ao"), Error);
  EXPECT_THROW(o.select(""), Error);
  for (const char* empty_item : {"ao,", ",ao", "ao,,obscurance", ","})
    EXPECT_THROW(o.select(empty_item), Error) << empty_item;
  o.select("bent_normal,ao");
  EXPECT_TRUE(o.ao && o.bent_normal && !o.obscurance);
  Scene s;
  const int mat = test::add_lambert(s, Color(0.5f));
  test::add_instance(s, test::uv_plane(1.0f, mat));
  const RayTracer tracer(s);
  const atlas::TexelRaster raster = atlas::rasterize_texels(s, 4, 4);
  for (auto bad : {+[](LightmapExtrasOptions& x) { x.rays = 0; },
                   +[](LightmapExtrasOptions& x) { x.obscurance_dmax = 0.0f; },
                   +[](LightmapExtrasOptions& x) { x.obscurance_dmax = NAN; },
                   +[](LightmapExtrasOptions& x) { x.ao_distance = -1.0f; }}) {
    LightmapExtrasOptions x = all_extras(4);
    bad(x);
    EXPECT_THROW(bake::bake_lightmap_extras(s, tracer, raster, x), Error);
  }
  bake::GlobalLineObscuranceOptions g;
  g.directions = 0;
  EXPECT_THROW(bake::obscurance_global_lines(s, tracer, raster, g), Error);
  g = {};
  g.obscurance_dmax = -1.0f;
  EXPECT_THROW(bake::obscurance_global_lines(s, tracer, raster, g), Error);
  atlas::TexelRaster broken = raster;
  broken.sample_of.pop_back();
  EXPECT_THROW(
      bake::obscurance_global_lines(s, tracer, broken, bake::GlobalLineObscuranceOptions{}), Error);
}

}  // namespace
}  // namespace illum
