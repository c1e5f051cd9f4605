// Normal-mapped PRT transfer (bake/prt_normal_map.h, S002 §5.7): a constant tilted map
// against the clamped cosine about the tilted normal cut to the surface's hemisphere, a flat
// map and `normal_maps=false` against no map, and a checker of two tilts against the mean of
// the two transfers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bake_test_scenes.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/core/sh.h"

namespace illum {
namespace {

using bake::PrtBake;
using bake::PrtBakeOptions;
using bake::PrtMode;

constexpr double kZ = 5.0;  // standard errors allowed for a Monte-Carlo estimate
constexpr int kSide = 16;   // raster side; uv0 runs over kSide periods of the map

// Tangent-space normals (unit) the tests' maps encode.
const vec3 kTiltA = glm::normalize(vec3(0.55f, -0.35f, 0.6f));  // ~53° off, +x and −bitangent
const vec3 kTiltB = glm::normalize(vec3(-0.6f, 0.2f, 0.7f));    // ~43° off, the other side

// A linear RGB texture of `side`² texels, texel (x, y) encoding normal(x, y) as (m + 1)/2.
template <typename F>
int add_normal_map(Scene& scene, int side, F normal) {
  Texture tex;
  tex.srgb = false;
  tex.image = Image(side, side, 3);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const vec3 m = normal(x, y);
      tex.image.set_rgb(x, y, Color(0.5f * (m + 1.0f)));
    }
  scene.textures.push_back(std::move(tex));
  return int(scene.textures.size()) - 1;
}

// The open 2 m plane facing +y (geometric normal +y, tangent +x), uv1 over a kSide² raster
// and uv0 = kSide·uv1, so texel (x, y) covers the map's period [x, x+1]×[y, y+1]. Its vertex
// normals are `surface` (+y: bitangent n × t = −z), so the interpolated normal may differ
// from the geometric one.
struct MappedPlane {
  explicit MappedPlane(int normal_texture, const vec3& surface = vec3(0, 1, 0)) {
    const int mat = test::add_lambert(scene, Color(0.5f));
    scene.materials[size_t(mat)].normal_texture = normal_texture;
    Mesh mesh = test::uv_plane(1.0f, mat);
    for (const vec2& uv : mesh.uv1) mesh.uv0.push_back(float(kSide) * uv);
    mesh.normals.assign(4, surface);
    test::add_instance(scene, std::move(mesh));
  }
  template <typename F>
  MappedPlane(int side, F normal, const vec3& surface = vec3(0, 1, 0)) : MappedPlane(0, surface) {
    scene.materials[0].normal_texture = add_normal_map(scene, side, normal);
  }
  PrtBake bake(PrtMode mode, int bands, int spp, bool normal_maps = true) {
    if (!tracer) {
      tracer = std::make_unique<RayTracer>(scene);
      raster = atlas::rasterize_texels(scene, kSide, kSide);
    }
    PrtBakeOptions o;
    o.mode = mode;
    o.bands = bands;
    o.spp = spp;
    o.seed = 11;
    o.progress = false;
    o.normal_maps = normal_maps;
    return bake_prt(scene, *tracer, raster, o);
  }
  Scene scene;
  std::unique_ptr<RayTracer> tracer;
  atlas::TexelRaster raster;
};

// World normal of tangent-space m on the plane whose interpolated normal is n: m.x·t + m.y·b
// + m.z·n, t the mesh tangent +x made orthogonal to n, b = n × t.
glm::dvec3 world_of(const vec3& m, const glm::dvec3& n = glm::dvec3(0, 1, 0)) {
  const glm::dvec3 t = glm::normalize(glm::dvec3(1, 0, 0) - n.x * n);
  return glm::normalize(double(m.x) * t + double(m.y) * glm::cross(n, t) + double(m.z) * n);
}

// The exact transfer about the perturbed normal p cut to the plane's hemisphere (+y, the
// geometric normal) and the interpolated normal n's,
// T_i = (1/π) ∫_{ω·y > 0, ω·n > 0} max(p·ω, 0) Y_i(ω) dω, and the per-ray variance of the
// baker's estimator (rays cosine-distributed about p, each weighing Y_i(ω)[ω·y > 0][ω·n > 0]):
// E_p[Y_i² 1] − T_i². Midpoint rule in (cos θ, φ) about +y: the integrand is smooth on the
// hemisphere except for the kink of the clamp, an O(h²) error (~1e-6 here).
struct CutTransfer {
  std::vector<double> mean, variance;
};
CutTransfer cut_transfer(int bands, const glm::dvec3& p,
                         const glm::dvec3& n = glm::dvec3(0, 1, 0)) {
  const int nu = 400, nphi = 800, count = sh::coefficient_count(bands);
  CutTransfer out{std::vector<double>(size_t(count), 0.0), std::vector<double>(size_t(count), 0.0)};
  const double dw = (1.0 / nu) * (2.0 * kPi / nphi);
  for (int a = 0; a < nu; ++a) {
    const double u = (a + 0.5) / nu, s = std::sqrt(1.0 - u * u);
    for (int b = 0; b < nphi; ++b) {
      const double phi = (b + 0.5) * 2.0 * kPi / nphi;
      const glm::dvec3 w(s * std::cos(phi), u, s * std::sin(phi));
      const double c = glm::dot(p, w);
      if (c <= 0.0 || glm::dot(n, w) <= 0.0) continue;
      const std::vector<double> y = sh::evaluate(bands, w);
      for (int i = 0; i < count; ++i) {
        out.mean[size_t(i)] += dw * c / kPi * y[size_t(i)];
        out.variance[size_t(i)] += dw * c / kPi * y[size_t(i)] * y[size_t(i)];
      }
    }
  }
  for (int i = 0; i < count; ++i)
    out.variance[size_t(i)] =
        std::max(out.variance[size_t(i)] - out.mean[size_t(i)] * out.mean[size_t(i)], 0.0);
  return out;
}

// The checks of test (a) for one plane and its exact cut transfer.
void check_tilted(MappedPlane& plane, const CutTransfer& exact) {
  const int bands = 4, spp = 4096;  // untraced rays: cheap
  const PrtBake baked = plane.bake(PrtMode::kUnshadowed, bands, spp);
  const bake::ShLight sun = bake::sun_light(bands, vec3(-0.3f, -1.0f, 0.5f), Color(1.0f));
  double sun_exact = 0.0, sun_sigma = 0.0;
  for (size_t i = 0; i < exact.mean.size(); ++i) {
    sun_exact += exact.mean[i] * sun.coefficients[i].x;
    sun_sigma += std::abs(sun.coefficients[i].x) * std::sqrt(exact.variance[i]);
  }
  double worst = 0.0;
  const auto check = [&](const float* t, const std::string& where) {
    double relit = 0.0;
    for (size_t i = 0; i < exact.mean.size(); ++i) {
      const double bound = kZ * std::sqrt(exact.variance[i] / spp) + 1e-5;
      EXPECT_NEAR(t[i * 3], exact.mean[i], bound) << where << " coefficient " << i;
      worst = std::max(worst, std::abs(t[i * 3] - exact.mean[i]) / bound);
      EXPECT_EQ(t[i * 3], t[i * 3 + 2]);  // grey
      relit += double(t[i * 3]) * sun.coefficients[i].x;
    }
    EXPECT_NEAR(relit, sun_exact, kZ * sun_sigma / std::sqrt(spp) + 1e-5) << where << " sun";
  };
  ASSERT_EQ(baked.texels, plane.raster.covered());
  for (const atlas::TexelSample& s : plane.raster.samples)
    check(baked.texel_transfer.pixel(s.x, s.y), fmt::format("texel {},{}", s.x, s.y));
  const size_t stride = 3 * exact.mean.size();
  for (size_t v = 0; v < 4; ++v)
    check(&baked.vertex_transfer[0][v * stride], fmt::format("vertex {}", v));
  std::printf("tilted: Y00 %.4f cut, %.4f uncut; worst error %.3f of its bound\n", exact.mean[0],
              0.2821, worst);
}

// (a) A constant tilted map, baked unshadowed, on the plane with straight vertex normals and
// with vertex normals leaning 35° to −x (the tilt leans to +x, so the interpolated normal's
// horizon cuts the lobe where the geometric one does not): every texel and vertex against
// the exact cut transfer, coefficient by coefficient within kZ standard errors √(Var/N) of N = spp
// rays (all K normal samples are the same normal, so the K blocks are one run of the Sobol'
// sequence: scrambled Sobol' beats independent samples, the bound is on the safe side), and
// relit under a sun's SH projection, Σ T_i L_i, whose per-ray variance is the quadratic form
// Σ_ij L_i L_j Cov(Y_i, Y_j) ≤ (Σ_i |L_i| σ_i)² (Cauchy–Schwarz).
TEST(PrtNormalMap, TiltedMapMatchesTheCosineAboutTheTiltCutToTheSurface) {
  const float lean = radians(35.0f);
  for (const vec3 surface : {vec3(0, 1, 0), vec3(-std::sin(lean), std::cos(lean), 0)}) {
    SCOPED_TRACE(fmt::format("vertex normals ({}, {}, {})", surface.x, surface.y, surface.z));
    MappedPlane plane(
        4, [](int, int) { return kTiltA; }, surface);
    const glm::dvec3 n = glm::normalize(glm::dvec3(surface));
    const glm::dvec3 p = world_of(kTiltA, n);
    const CutTransfer cut = cut_transfer(4, p, n);
    // Not vacuous: each cut removes a visible part of the tilted lobe (Y00: the uncut lobe's
    // coefficient is Λ0/π·Y00 = Y00 = 0.2821; the geometric normal's cut alone leaves more).
    EXPECT_LT(cut.mean[0], 0.2821 * 0.97);
    if (surface.x != 0.0f) {
      EXPECT_LT(cut.mean[0], 0.97 * cut_transfer(4, p).mean[0]);
    }
    check_tilted(plane, cut);
  }
}

// (b) A flat map (every texel (0.5, 0.5, 1): m = (0, 0, 1)) perturbs nothing, and a tilted
// map with normal_maps=false is ignored: both bake bit for bit what a plane without a map
// bakes, shadowed and unshadowed, texels and vertices.
TEST(PrtNormalMap, FlatMapAndMapsOffBakeAsWithoutAMap) {
  MappedPlane none(kNoTexture);
  MappedPlane flat(4, [](int, int) { return vec3(0.0f, 0.0f, 1.0f); });
  MappedPlane tilted(4, [](int, int) { return kTiltA; });
  for (PrtMode mode : {PrtMode::kUnshadowed, PrtMode::kShadowed}) {
    SCOPED_TRACE(bake::to_string(mode));
    const PrtBake plain = none.bake(mode, 3, 64);
    for (const PrtBake& other : {flat.bake(mode, 3, 64), tilted.bake(mode, 3, 64, false)}) {
      EXPECT_EQ(other.texel_transfer.data, plain.texel_transfer.data);
      EXPECT_EQ(other.vertex_transfer, plain.vertex_transfer);
    }
    // Not vacuous: with maps on, the tilted plane bakes something else.
    EXPECT_NE(tilted.bake(mode, 3, 64).texel_transfer.data, plain.texel_transfer.data);
  }
}

// (c) A checker of the two tilts, one square a quarter of a period, bakes at every texel the
// mean of the two constant maps' transfers: the 16 footprint points are a (0, 4, 2)-net over
// the texel's period, 4 in each quarter, so 8 read each tilt. The difference of the
// estimates has a standard deviation at most σ_X + σ_Y (the bakes share their seeds, so they
// are not independent): the checker's, K blocks of N/K rays, half about each tilt, has
// σ_X² = (σ_A² + σ_B²)/(2N); the mean of the two bakes of N rays, σ_Y ≤ (σ_A + σ_B)/(2√N).
// Bilinear lookup blends the tilts within half a map texel of a square's edge (0.4 % of the
// period for a 1024² map): a footprint point there (about one texel in 16 gets one, two in a
// texel about once in 500 texels) moves its block of N/K rays, bounded by 2|T_A − T_B|/K.
// Vertices are left out: a vertex's footprint, its hat over several periods, is not
// balanced between the tilts by 16 points.
TEST(PrtNormalMap, CheckerOfTwoTiltsBakesTheMeanOfTheirTransfers) {
  const int side = 1024, bands = 3, spp = 4096, k = 16;
  MappedPlane checker(
      side, [&](int x, int y) { return (x < side / 2) != (y < side / 2) ? kTiltA : kTiltB; });
  MappedPlane a(4, [](int, int) { return kTiltA; });
  MappedPlane b(4, [](int, int) { return kTiltB; });
  const PrtBake mixed = checker.bake(PrtMode::kUnshadowed, bands, spp);
  const PrtBake ta = a.bake(PrtMode::kUnshadowed, bands, spp);
  const PrtBake tb = b.bake(PrtMode::kUnshadowed, bands, spp);
  const CutTransfer ea = cut_transfer(bands, world_of(kTiltA));
  const CutTransfer eb = cut_transfer(bands, world_of(kTiltB));
  double worst = 0.0, spread = 0.0;
  for (const atlas::TexelSample& s : checker.raster.samples) {
    const float* m = mixed.texel_transfer.pixel(s.x, s.y);
    const float* pa = ta.texel_transfer.pixel(s.x, s.y);
    const float* pb = tb.texel_transfer.pixel(s.x, s.y);
    for (size_t i = 0; i < ea.mean.size(); ++i) {
      const double sx = std::sqrt((ea.variance[i] + eb.variance[i]) / (2.0 * spp));
      const double sy =
          (std::sqrt(ea.variance[i]) + std::sqrt(eb.variance[i])) / (2.0 * std::sqrt(spp));
      const double blend = 2.0 * std::abs(ea.mean[i] - eb.mean[i]) / k;
      const double bound = kZ * (sx + sy) + blend + 1e-5;
      const double d = std::abs(double(m[i * 3]) - 0.5 * (double(pa[i * 3]) + double(pb[i * 3])));
      EXPECT_LE(d, bound) << "texel " << s.x << "," << s.y << " coefficient " << i;
      worst = std::max(worst, d / bound);
      spread = std::max(spread, std::abs(ea.mean[i] - eb.mean[i]) / 2.0 / bound);
    }
  }
  // Not vacuous: a texel that read one tilt only would be off by |T_A − T_B|/2, several bounds.
  EXPECT_GT(spread, 2.0);
  RecordProperty("worst_error_over_bound", std::to_string(worst));
  std::printf("checker: worst error %.3f of its bound, tilt difference / 2 up to %.2f bounds\n",
              worst, spread);
}

}  // namespace
}  // namespace illum
