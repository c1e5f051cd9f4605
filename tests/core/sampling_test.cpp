// Chi-square goodness-of-fit tests for every warp in core/sampling.h and for the
// piecewise-constant distributions. Each test bins half a million warped samples over a grid
// in a parameterization of the output and compares the histogram with the counts that
// the warp's own pdf predicts (the pdf integrated numerically over each cell), so a
// sample distribution that disagrees with the pdf the code returns fails the test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "chi_square.h"
#include "illum/core/error.h"
#include "illum/core/rng.h"
#include "illum/core/sampling.h"

namespace illum {
namespace {

using test::chi_square_test;
using test::ChiSquareResult;
using test::expected_counts;
using test::Grid;
using test::kSignificance;

constexpr int kSamples = 1 << 19;  // ≥ 500 expected per cell on the grids below
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The midpoint rule integrates the densities below exactly (they are piecewise linear on
// the grids used), so the pdf integral may differ from 1 only by float rounding of the pdf.
constexpr double kIntegralTolerance = 1e-5;

struct WarpCheck {
  ChiSquareResult chi;
  double pdf_integral = 0.0;  // ∫ density over the grid
  int outside = 0;            // samples outside the grid (i.e. outside the warp's support)
};

// Draws kSamples uniform points, maps each through `to_params` (warp, then the grid's
// parameterization) and tests the histogram against `density` (pdf in grid parameters).
WarpCheck check_warp(const Grid& grid, const std::function<vec2(const vec2&)>& to_params,
                     const std::function<double(double, double)>& density, uint64_t seed = 7) {
  WarpCheck check;
  Rng rng(seed);
  std::vector<double> observed(static_cast<size_t>(grid.cell_count()), 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const vec2 u(rng.next_float(), rng.next_float());
    const vec2 p = to_params(u);
    const int cell = grid.cell(p.x, p.y);
    if (cell < 0)
      ++check.outside;
    else
      observed[static_cast<size_t>(cell)] += 1.0;
  }
  const auto expected = expected_counts(grid, density, kSamples);
  for (double e : expected) check.pdf_integral += e / kSamples;
  check.chi = chi_square_test(observed, expected);
  std::printf("chi2 = %.1f, dof = %d, p = %.3g, integral = %.7f\n", check.chi.statistic,
              check.chi.dof, check.chi.p_value, check.pdf_integral);
  return check;
}

// (cos θ, φ ∈ [0, 2π)) of a direction; dω = d(cos θ) dφ, so the density in these
// parameters is the solid-angle pdf itself.
vec2 direction_params(const vec3& d) {
  EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
  double phi = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x));
  if (phi < 0.0) phi += kTwoPi;
  return {d.z, static_cast<float>(phi)};
}

Grid direction_grid(double z_min, double z_max) {
  return Grid{16, 32, z_min, z_max, 0.0, kTwoPi};
}

void expect_pass(const WarpCheck& c) {
  EXPECT_EQ(c.outside, 0) << "samples outside the support";
  EXPECT_NEAR(c.pdf_integral, 1.0, kIntegralTolerance) << "pdf does not integrate to 1";
  EXPECT_GT(c.chi.p_value, kSignificance)
      << "chi2 = " << c.chi.statistic << ", dof = " << c.chi.dof;
}

// --- the p-value machinery itself --------------------------------------------------------

TEST(ChiSquare, IncompleteGammaMatchesClosedForms) {
  // Q(1/2, x) = erfc(√x) and Q(k, x) = e^{-x} Σ_{i<k} x^i / i! for integer k.
  for (double x : {0.01, 0.3, 1.0, 2.5, 7.0, 30.0}) {
    EXPECT_NEAR(test::gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-12) << x;
    for (int k = 1; k <= 40; k += 13) {
      double sum = 0.0, term = 1.0;
      for (int i = 0; i < k; ++i) {
        sum += term;
        term *= x / (i + 1);
      }
      EXPECT_NEAR(test::gamma_q(k, x), std::exp(-x) * sum, 1e-12) << k << " " << x;
    }
  }
}

// --- warps ---------------------------------------------------------------------------------

TEST(Sampling, UniformHemisphere) {
  expect_pass(check_warp(
      direction_grid(0.0, 1.0),
      [](const vec2& u) { return direction_params(sample_uniform_hemisphere(u)); },
      [](double, double) { return pdf_uniform_hemisphere(); }));
}

TEST(Sampling, CosineHemisphere) {
  expect_pass(check_warp(
      direction_grid(0.0, 1.0),
      [](const vec2& u) { return direction_params(sample_cosine_hemisphere(u)); },
      [](double z, double) { return pdf_cosine_hemisphere(static_cast<float>(z)); }));
}

TEST(Sampling, UniformSphere) {
  expect_pass(check_warp(
      direction_grid(-1.0, 1.0),
      [](const vec2& u) { return direction_params(sample_uniform_sphere(u)); },
      [](double, double) { return pdf_uniform_sphere(); }));
}

TEST(Sampling, UniformConeSeveralAngles) {
  for (float degrees : {1.0f, 10.0f, 45.0f, 90.0f, 150.0f}) {
    SCOPED_TRACE(degrees);
    const float cos_max = std::cos(radians(degrees));
    expect_pass(check_warp(
        direction_grid(cos_max, 1.0),
        [&](const vec2& u) { return direction_params(sample_uniform_cone(u, cos_max)); },
        [&](double, double) { return pdf_uniform_cone(cos_max); }, static_cast<uint64_t>(degrees)));
  }
}

TEST(Sampling, SpotCone) {
  for (float degrees : {5.0f, 30.0f, 60.0f}) {
    SCOPED_TRACE(degrees);
    const float cos_cutoff = std::cos(radians(degrees));
    expect_pass(check_warp(
        direction_grid(cos_cutoff, 1.0),
        [&](const vec2& u) { return direction_params(sample_spot_cone(u, cos_cutoff)); },
        [&](double, double) { return pdf_spot_cone(cos_cutoff); },
        100 + static_cast<uint64_t>(degrees)));
  }
}

TEST(Sampling, ConcentricDisk) {
  // Parameters (r², φ): dA = r dr dφ = ½ d(r²) dφ.
  expect_pass(check_warp(
      Grid{16, 32, 0.0, 1.0, 0.0, kTwoPi},
      [](const vec2& u) {
        const vec2 p = sample_concentric_disk(u);
        double phi = std::atan2(static_cast<double>(p.y), static_cast<double>(p.x));
        if (phi < 0.0) phi += kTwoPi;
        return vec2(glm::dot(p, p), static_cast<float>(phi));
      },
      [](double, double) { return 0.5 * pdf_concentric_disk(); }));
}

TEST(Sampling, UniformTriangle) {
  // A triangle with vertices p0, p1, p2 in 3-D; the header promises pdf = 1 / area.
  const vec3 p0(0.2f, -1.0f, 0.5f), p1(2.0f, 0.3f, -0.4f), p2(-0.7f, 1.1f, 0.9f);
  const float area = 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
  // Parameters (s, t) with s = b1 + b2 and t = b2 / s: the point is
  // p0 + s((1 − t)(p1 − p0) + t(p2 − p0)), so dA = 2·area·s ds dt.
  expect_pass(check_warp(
      Grid{24, 24, 0.0, 1.0, 0.0, 1.0},
      [](const vec2& u) {
        const vec2 b = sample_uniform_triangle(u);
        EXPECT_GE(b.x, 0.0f);
        EXPECT_GE(b.y, 0.0f);
        EXPECT_LE(b.x + b.y, 1.0f + 1e-6f);
        const float s = b.x + b.y;
        return vec2(s, s > 0.0f ? b.y / s : 0.0f);
      },
      [&](double s, double) { return (1.0 / area) * 2.0 * area * s; }));
}

// --- negative tests: the same check must reject wrong warps -------------------------------

TEST(SamplingNegative, UniformSamplesWithCosinePdfFail) {
  const WarpCheck c = check_warp(
      direction_grid(0.0, 1.0),
      [](const vec2& u) { return direction_params(sample_uniform_hemisphere(u)); },
      [](double z, double) { return pdf_cosine_hemisphere(static_cast<float>(z)); });
  EXPECT_LT(c.chi.p_value, kSignificance);
}

TEST(SamplingNegative, DiskWithoutSquareRootFails) {
  // The classic mistake r = u instead of r = √u: the pdf it claims is uniform, the samples
  // crowd the centre.
  const WarpCheck c = check_warp(
      Grid{16, 32, 0.0, 1.0, 0.0, kTwoPi},
      [](const vec2& u) { return vec2(u.x * u.x, static_cast<float>(kTwoPi) * u.y); },
      [](double, double) { return 0.5 * pdf_concentric_disk(); });
  EXPECT_LT(c.chi.p_value, kSignificance);
}

TEST(SamplingNegative, SlightlyWrongConeFails) {
  // A subtler bug: the cone sampled with a 2 % too wide angle but the pdf of the right one
  // (the pdf then integrates to 1 only over the right cone). Samples spill into the band
  // where the claimed density is zero and are spread too thin elsewhere.
  const float cos_max = std::cos(radians(30.0f)), cos_wrong = std::cos(radians(30.6f));
  const WarpCheck c = check_warp(
      direction_grid(cos_wrong, 1.0),
      [&](const vec2& u) { return direction_params(sample_uniform_cone(u, cos_wrong)); },
      [&](double z, double) { return z >= cos_max ? pdf_uniform_cone(cos_max) : 0.0; });
  EXPECT_LT(c.chi.p_value, kSignificance);
}

// --- distributions -------------------------------------------------------------------------

std::vector<float> test_weights(int n, uint64_t seed) {
  Rng rng(seed);
  std::vector<float> w(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    w[static_cast<size_t>(i)] = (i % 7 == 3) ? 0.0f : 0.1f + 3.0f * rng.next_float();
  return w;
}

TEST(Distribution1D, ContinuousMatchesItsPdf) {
  const int n = 37;
  const auto weights = test_weights(n, 3);
  const Distribution1D dist(weights.data(), n);
  const int sub = 3;
  const Grid grid{n * sub, 1, 0.0, 1.0, 0.0, 1.0};
  const WarpCheck c = check_warp(
      grid,
      [&](const vec2& u) {
        float pdf = 0.0f;
        int offset = -1;
        const float x = dist.sample_continuous(u.x, &pdf, &offset);
        EXPECT_GE(x, 0.0f);
        EXPECT_LT(x, 1.0f);
        EXPECT_EQ(offset, static_cast<int>(x * n));
        EXPECT_GT(pdf, 0.0f);
        EXPECT_EQ(pdf, dist.pdf(offset));  // the pdf reported for a sample is the cell's pdf
        return vec2(x, 0.5f);
      },
      [&](double x, double) { return dist.pdf(std::min(static_cast<int>(x * n), n - 1)); });
  expect_pass(c);
  // The pdf is the weights normalized: pmf(i) = w_i / Σw.
  double sum = 0.0;
  for (float w : weights) sum += w;
  for (int i = 0; i < n; ++i) EXPECT_NEAR(dist.pmf(i), weights[static_cast<size_t>(i)] / sum, 1e-6);
}

TEST(Distribution1D, DiscreteMatchesPmf) {
  const int n = 23;
  const auto weights = test_weights(n, 5);
  const Distribution1D dist(weights.data(), n);
  std::vector<double> observed(static_cast<size_t>(n), 0.0), expected(static_cast<size_t>(n));
  Rng rng(13);
  for (int i = 0; i < kSamples; ++i) {
    float pmf = 0.0f;
    const int k = dist.sample_discrete(rng.next_float(), &pmf);
    ASSERT_TRUE(k >= 0 && k < n);
    EXPECT_EQ(pmf, dist.pmf(k));
    observed[static_cast<size_t>(k)] += 1.0;
  }
  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    expected[static_cast<size_t>(i)] = kSamples * static_cast<double>(dist.pmf(i));
    total += dist.pmf(i);
  }
  EXPECT_NEAR(total, 1.0, kIntegralTolerance);
  const auto r = chi_square_test(observed, expected);
  EXPECT_GT(r.p_value, kSignificance) << r.statistic;
}

TEST(Distribution1D, AllZeroWeightsAreUniform) {
  const std::vector<float> zeros(5, 0.0f);
  const Distribution1D dist(zeros.data(), 5);
  float pdf = 0.0f;
  int offset = -1;
  EXPECT_FLOAT_EQ(dist.sample_continuous(0.3f, &pdf, &offset), 0.3f);
  EXPECT_EQ(pdf, 1.0f);
  EXPECT_EQ(offset, 1);
  EXPECT_FLOAT_EQ(dist.pmf(4), 0.2f);
}

TEST(Distribution1D, NegativeWeightIsABug) {
  const std::vector<float> w{1.0f, -1.0f};
  EXPECT_THROW(Distribution1D(w.data(), 2), InternalError);
}

TEST(Distribution2D, ContinuousMatchesItsPdf) {
  const int w = 24, h = 12;
  std::vector<float> weights(static_cast<size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // A smooth bright spot, one all-black row and a black column block.
      const float dx = (x - 15.5f) / 5.0f, dy = (y - 3.5f) / 3.0f;
      float v = 0.05f + std::exp(-(dx * dx + dy * dy));
      if (y == 8 || (x >= 4 && x < 7)) v = 0.0f;
      weights[static_cast<size_t>(y * w + x)] = v;
    }
  const Distribution2D dist(weights.data(), w, h);
  const WarpCheck c = check_warp(
      Grid{2 * w, 2 * h, 0.0, 1.0, 0.0, 1.0},
      [&](const vec2& u) {
        float pdf = 0.0f;
        const vec2 p = dist.sample_continuous(u, &pdf);
        EXPECT_GT(pdf, 0.0f);
        EXPECT_EQ(pdf, dist.pdf(p));  // the pdf reported for a sample is pdf() at the sample
        return p;
      },
      [&](double x, double y) {
        return dist.pdf(vec2(static_cast<float>(x), static_cast<float>(y)));
      },
      21);
  expect_pass(c);
  // Zero-weight cells never get samples and have zero density.
  EXPECT_EQ(dist.pdf(vec2(0.5f, (8.5f) / h)), 0.0f);
  EXPECT_EQ(dist.pdf(vec2(5.5f / w, 0.1f)), 0.0f);
}

TEST(Distribution2D, WrongRowOrderFails) {
  // Negative test for the 2-D check: a pdf that reads the weights upside down.
  const int w = 8, h = 8;
  std::vector<float> weights(static_cast<size_t>(w * h));
  for (int i = 0; i < w * h; ++i)
    weights[static_cast<size_t>(i)] = 1.0f + static_cast<float>(i / w);
  const Distribution2D dist(weights.data(), w, h);
  const WarpCheck c = check_warp(
      Grid{w, h, 0.0, 1.0, 0.0, 1.0},
      [&](const vec2& u) { return dist.sample_continuous(u, nullptr); },
      [&](double x, double y) {
        return dist.pdf(vec2(static_cast<float>(x), static_cast<float>(1.0 - y)));
      });
  EXPECT_LT(c.chi.p_value, kSignificance);
}

TEST(Sampling, PowerHeuristic) {
  EXPECT_FLOAT_EQ(power_heuristic(1.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(power_heuristic(3.0f, 1.0f), 0.9f);
  EXPECT_EQ(power_heuristic(0.0f, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(power_heuristic(2.0f, 5.0f) + power_heuristic(5.0f, 2.0f), 1.0f);
}

}  // namespace
}  // namespace illum
