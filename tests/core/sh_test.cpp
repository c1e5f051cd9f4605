// core/sh.h and core/sh_rotation.h: the convention (known constants, no Condon–Shortley
// phase), orthonormality by exact quadrature, the fast path against the recurrences,
// rotation (band energy, agreement with re-projecting the rotated function, composition),
// zonal convolution (clamped-cosine factors in closed form against a hemisphere quadrature),
// projections (constant, narrow lobe → Y(d), Monte Carlo within its own standard error) and
// windowing. Exact-quadrature checks use 1e-12: the sums have a few thousand terms, each
// below (2l+1)/(4π) ≤ 3 (l ≤ 16) in size, so their double rounding stays below
// terms × 2⁻⁵³ × 3 ≈ 1e-12 in the worst case and far below it in practice.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/sh.h"
#include "illum/core/sh_rotation.h"

namespace illum::sh {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kExact = 1e-12;

glm::dvec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  glm::dvec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// A uniformly random rotation from a random unit quaternion.
glm::dmat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  double w = g(rng), x = g(rng), y = g(rng), z = g(rng);
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  glm::dmat3 r;  // columns
  r[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
  r[1] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
  r[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  return r;
}

std::vector<double> random_coefficients(int bands, std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  std::vector<double> c(bands * bands);
  for (double& v : c) v = g(rng);
  return c;
}

double band_energy(std::span<const double> c, int l) {
  double e = 0.0;
  for (int m = -l; m <= l; ++m) e += c[index(l, m)] * c[index(l, m)];
  return e;
}

// Legendre polynomial by Bonnet's recurrence (independent of the library's tables).
double legendre(int l, double t) {
  double p0 = 1.0, p1 = t;
  if (l == 0) return p0;
  for (int k = 2; k <= l; ++k) {
    const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return p1;
}

// ∫_{hemisphere around n} g(ω) dω by Gauss–Legendre in t = n·ω ∈ [0, 1] × equally spaced
// azimuths: exact for g a polynomial of degree ≤ `degree` in the direction.
double hemisphere_integral(const glm::dvec3& n, int degree,
                           const std::function<double(const glm::dvec3&)>& g) {
  const GaussLegendre rule = gauss_legendre(degree / 2 + 1);
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(helper, n)), b = glm::cross(n, t);
  const int n_phi = degree + 1;
  double sum = 0.0;
  for (size_t i = 0; i < rule.nodes.size(); ++i) {
    const double z = 0.5 + 0.5 * rule.nodes[i], r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * kPi * j / n_phi;
      const glm::dvec3 w = r * std::cos(phi) * t + r * std::sin(phi) * b + z * n;
      sum += 0.5 * rule.weights[i] * (2.0 * kPi / n_phi) * g(w);
    }
  }
  return sum;
}

TEST(Sh, KnownConstants) {
  EXPECT_NEAR(kY00, 1.0 / (2.0 * std::sqrt(kPi)), 1e-17);
  EXPECT_NEAR(kY1, std::sqrt(3.0 / (4.0 * kPi)), 1e-16);
  EXPECT_NEAR(kY2xy, std::sqrt(15.0 / (4.0 * kPi)), 1e-15);
  EXPECT_NEAR(kY20, std::sqrt(5.0 / (16.0 * kPi)), 1e-16);
  EXPECT_NEAR(kY22, std::sqrt(15.0 / (16.0 * kPi)), 1e-16);
  // At the pole only m = 0 survives, Y_l^0(+z) = √((2l+1)/(4π)); at +x, Y_l^l = √2 K_l^l
  // (2l−1)!! > 0 (no Condon–Shortley phase), Y_l^−l = 0.
  const int bands = 17;
  std::vector<double> y(bands * bands);
  evaluate_recurrence<double>(bands, glm::dvec3(0, 0, 1), y);
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m)
      EXPECT_NEAR(y[index(l, m)], m == 0 ? std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) : 0.0, kExact)
          << l << "," << m;
  evaluate_recurrence<double>(bands, glm::dvec3(1, 0, 0), y);
  for (int l = 1; l < bands; ++l) {
    double k2 = (2.0 * l + 1.0) / (4.0 * kPi), dfact = 1.0;
    for (int i = 1; i <= 2 * l; ++i) k2 /= i;           // (l−m)!/(l+m)! at m = l
    for (int i = 2 * l - 1; i > 1; i -= 2) dfact *= i;  // (2l−1)!!
    EXPECT_NEAR(y[index(l, l)], std::sqrt(2.0 * k2) * dfact, kExact) << l;
    EXPECT_NEAR(y[index(l, -l)], 0.0, kExact) << l;
  }
}

TEST(Sh, BandOneIsAPermutationOfTheDirection) {
  std::mt19937_64 rng(1);
  for (int k = 0; k < 100; ++k) {
    const glm::dvec3 w = random_direction(rng);
    std::vector<double> y(4);
    evaluate_recurrence<double>(2, w, y);
    EXPECT_NEAR(y[0], kY00, 1e-16);
    EXPECT_NEAR(y[1], kY1 * w.y, 1e-15);
    EXPECT_NEAR(y[2], kY1 * w.z, 1e-15);
    EXPECT_NEAR(y[3], kY1 * w.x, 1e-15);
    const glm::dvec4 l1 = evaluate_l1(w);
    // A few ulp: the closed form and the recurrence round differently, and clang contracts
    // a·b + c into fma where gcc does not (the asan build differed by 1 ulp).
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(l1[i], y[i], 4e-16);
  }
}

TEST(Sh, FastPathMatchesRecurrence) {
  std::mt19937_64 rng(2);
  for (int k = 0; k < 200; ++k) {
    const glm::dvec3 w = random_direction(rng);
    for (int bands = 1; bands <= 4; ++bands) {
      std::vector<double> fast(bands * bands), slow(bands * bands);
      evaluate<double>(bands, w, fast);
      evaluate_recurrence<double>(bands, w, slow);
      for (int i = 0; i < bands * bands; ++i) EXPECT_NEAR(fast[i], slow[i], 1e-15) << i;
      // The float instantiation: the same values to float rounding (a few ulps of ≤ 1.1).
      std::vector<float> fast_f(bands * bands), slow_f(bands * bands);
      evaluate<float>(bands, glm::vec3(w), fast_f);
      evaluate_recurrence<float>(bands, glm::vec3(w), slow_f);
      for (int i = 0; i < bands * bands; ++i) {
        EXPECT_NEAR(fast_f[i], slow[i], 1e-6) << i;
        EXPECT_NEAR(slow_f[i], slow[i], 1e-6) << i;
      }
    }
  }
}

TEST(Sh, GaussLegendreIntegratesPolynomialsExactly) {
  for (int n : {1, 2, 5, 9, 33}) {
    const GaussLegendre rule = gauss_legendre(n);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += rule.weights[i] * std::pow(rule.nodes[i], k);
      EXPECT_NEAR(sum, k % 2 ? 0.0 : 2.0 / (k + 1), kExact) << n << " nodes, t^" << k;
    }
  }
}

// ∫ Y_i Y_j = δ_ij for every pair up to l = 8 (and l = 16), by the rule of degree 2·lmax.
TEST(Sh, OrthonormalByQuadrature) {
  for (int bands : {9, 17}) {
    const SphereQuadrature rule = sphere_quadrature(2 * (bands - 1));
    const int n = bands * bands;
    std::vector<double> gram(n * n, 0.0), y(n);
    for (size_t k = 0; k < rule.directions.size(); ++k) {
      evaluate<double>(bands, rule.directions[k], y);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j <= i; ++j) gram[i * n + j] += rule.weights[k] * y[i] * y[j];
    }
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j <= i; ++j) {
        const double e = std::abs(gram[i * n + j] - (i == j ? 1.0 : 0.0));
        worst = std::max(worst, e);
        ASSERT_LT(e, kExact) << "bands " << bands << " <" << i << "," << j << ">";
      }
    RecordProperty("worst_error_bands_" + std::to_string(bands), fmt::format("{:.2e}", worst));
  }
}

// Addition theorem: Σ_m Y_lm(d)² = (2l+1)/(4π) in every direction, every band.
TEST(Sh, AdditionTheoremHoldsInEveryBand) {
  std::mt19937_64 rng(3);
  const int bands = kMaxBands;
  std::vector<double> y(bands * bands);
  for (int k = 0; k < 50; ++k) {
    evaluate<double>(bands, random_direction(rng), y);
    for (int l = 0; l < bands; ++l)
      EXPECT_NEAR(band_energy(y, l), (2.0 * l + 1.0) / (4.0 * kPi), kExact) << l;
  }
}

TEST(Sh, ProjectionOfAConstantIsBandZeroOnly) {
  const std::vector<double> c =
      project(9, sphere_quadrature(8), [](const glm::dvec3&) { return 2.5; });
  EXPECT_NEAR(c[0], 2.5 * std::sqrt(4.0 * kPi), kExact);
  for (size_t i = 1; i < c.size(); ++i) EXPECT_NEAR(c[i], 0.0, kExact) << i;
}

// A band-limited function projects back onto its own coefficients, and reconstructs.
TEST(Sh, ProjectionOfABandLimitedFunctionIsExact) {
  std::mt19937_64 rng(4);
  const int bands = 9;
  const std::vector<double> c = random_coefficients(bands, rng);
  const auto f = [&](const glm::dvec3& w) { return reconstruct(bands, c, w); };
  const std::vector<double> p = project(bands, sphere_quadrature(2 * (bands - 1)), f);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(p[i], c[i], kExact) << i;
}

// A single direction d: the normalised von Mises–Fisher lobe f = κ e^{κ(d·ω)}/(4π sinh κ)
// tends to the delta at d as κ grows; its coefficients are Λ_l(κ)·Y_lm(d) with
// Λ_l = I_{l+1/2}(κ)/I_{1/2}(κ), from Λ_0 = 1, Λ_1 = coth κ − 1/κ and
// Λ_{l+1} = Λ_{l−1} − (2l+1)/κ · Λ_l (stable upwards for l ≪ κ), and Λ_l → 1: the delta's
// coefficients are Y(d). Degree 200 resolves the lobe to e^{−100} at κ = 200 (its Chebyshev
// coefficients fall as e^{−n²/(2κ)}).
TEST(Sh, NarrowLobeProjectsOntoTheBasisAtItsDirection) {
  std::mt19937_64 rng(5);
  const int bands = 9;
  const SphereQuadrature rule = sphere_quadrature(200);
  for (const double kappa : {50.0, 200.0}) {
    std::vector<double> lambda(bands);
    lambda[0] = 1.0;
    lambda[1] = 1.0 / std::tanh(kappa) - 1.0 / kappa;
    for (int l = 1; l + 1 < bands; ++l)
      lambda[l + 1] = lambda[l - 1] - (2.0 * l + 1.0) / kappa * lambda[l];
    const glm::dvec3 d = random_direction(rng);
    const double norm = kappa / (2.0 * kPi * (1.0 - std::exp(-2.0 * kappa)));
    const std::vector<double> c = project(bands, rule, [&](const glm::dvec3& w) {
      return norm * std::exp(kappa * (glm::dot(w, d) - 1.0));
    });
    const std::vector<double> y = evaluate(bands, d);
    for (int l = 0; l < bands; ++l) {
      // Λ_l = 1 − l(l+1)/(2κ) + r with |r| ≤ l²(l+1)²/(8κ²) + O(κ⁻³) (Hankel's expansion
      // of I_{l+1/2}): the lobe's coefficients approach Y(d); twice that bound for the rest.
      const double ll = l * (l + 1.0);
      EXPECT_NEAR(lambda[l], 1.0 - ll / (2.0 * kappa), ll * ll / (4.0 * kappa * kappa)) << l;
      for (int m = -l; m <= l; ++m)
        EXPECT_NEAR(c[index(l, m)], lambda[l] * y[index(l, m)], kExact)
            << "kappa " << kappa << " l " << l << " m " << m;
    }
  }
}

TEST(Sh, RotationPreservesBandEnergy) {
  std::mt19937_64 rng(6);
  const int bands = 17;
  for (int k = 0; k < 20; ++k) {
    const ShRotation rotation(bands, random_rotation(rng));
    const std::vector<double> c = random_coefficients(bands, rng);
    const std::vector<double> r = rotation.apply(c);
    for (int l = 0; l < bands; ++l)
      EXPECT_NEAR(band_energy(r, l), band_energy(c, l), kExact * (1.0 + band_energy(c, l))) << l;
  }
}

// The coefficients of g(ω) = f(rᵀω), projected anew by exact quadrature, are M·c.
TEST(Sh, RotationAgreesWithReprojectingTheRotatedFunction) {
  std::mt19937_64 rng(7);
  for (const int bands : {4, 9, 17}) {
    const SphereQuadrature rule = sphere_quadrature(2 * (bands - 1));
    for (int k = 0; k < 3; ++k) {
      const glm::dmat3 r = random_rotation(rng);
      const std::vector<double> c = random_coefficients(bands, rng);
      const std::vector<double> rotated = ShRotation(bands, r).apply(c);
      const std::vector<double> reprojected = project(bands, rule, [&](const glm::dvec3& w) {
        return reconstruct(bands, c, glm::transpose(r) * w);
      });
      for (size_t i = 0; i < c.size(); ++i)
        ASSERT_NEAR(rotated[i], reprojected[i], 1e-11) << "bands " << bands << " i " << i;
    }
  }
}

TEST(Sh, RotationComposesAndTurnsLobesWithTheRotation) {
  std::mt19937_64 rng(8);
  const int bands = 9;
  const glm::dmat3 a = random_rotation(rng), b = random_rotation(rng);
  const std::vector<double> c = random_coefficients(bands, rng);
  const std::vector<double> ab = ShRotation(bands, a * b).apply(c);
  const std::vector<double> a_then_b = ShRotation(bands, a).apply(ShRotation(bands, b).apply(c));
  for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(ab[i], a_then_b[i], kExact) << i;
  // A zonal lobe around d, rotated, is the same lobe around a·d.
  const std::vector<double> factors = clamped_cosine_factors(bands);
  const glm::dvec3 d = random_direction(rng);
  const std::vector<double> turned = ShRotation(bands, a).apply(zonal_along(bands, factors, d));
  const std::vector<double> expected = zonal_along(bands, factors, a * d);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(turned[i], expected[i], kExact) << i;
  // The identity.
  const std::vector<double> same = ShRotation(bands, glm::dmat3(1.0)).apply(c);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_EQ(same[i], c[i]) << i;
}

TEST(Sh, RotationAppliesToFloatAndRgbCoefficients) {
  std::mt19937_64 rng(9);
  const int bands = 5;
  const ShRotation rotation(bands, random_rotation(rng));
  const std::vector<double> c = random_coefficients(bands, rng);
  const std::vector<double> expected = rotation.apply(c);
  std::vector<float> cf(c.begin(), c.end()), rf(c.size());
  rotation.apply<float>(cf, rf);
  std::vector<glm::vec3> rgb(c.size()), out(c.size());
  for (size_t i = 0; i < c.size(); ++i) rgb[i] = glm::vec3(float(c[i]), 2.0f * float(c[i]), 0.0f);
  rotation.apply<glm::vec3>(rgb, out);
  for (size_t i = 0; i < c.size(); ++i) {
    // float rounding of 2l+1 ≤ 9 products of terms ≲ 4: well under 1e-5.
    EXPECT_NEAR(rf[i], expected[i], 1e-5) << i;
    EXPECT_NEAR(out[i].y, 2.0 * expected[i], 2e-5) << i;
    EXPECT_EQ(out[i].z, 0.0f) << i;
  }
}

TEST(Sh, ClampedCosineFactorsInClosedForm) {
  const std::vector<double> f = clamped_cosine_factors(17);
  EXPECT_NEAR(f[0], kPi, 1e-15);
  EXPECT_NEAR(f[1], 2.0 * kPi / 3.0, 1e-15);
  EXPECT_NEAR(f[2], kPi / 4.0, 1e-15);
  EXPECT_NEAR(f[3], 0.0, 1e-15);
  EXPECT_NEAR(f[4], -kPi / 24.0, 1e-15);
  EXPECT_NEAR(f[6], kPi / 64.0, 1e-15);
  // Against 2π ∫_0^1 t P_l(t) dt by Gauss–Legendre on [0, 1] (exact: degree l + 1), with the
  // test's own Legendre polynomials, and against the general zonal routine.
  const GaussLegendre rule = gauss_legendre(10);
  const std::vector<double> general = zonal_factors(
      17, [](double t) { return std::max(t, 0.0); }, 10);
  for (int l = 0; l < 17; ++l) {
    double integral = 0.0;
    for (size_t i = 0; i < rule.nodes.size(); ++i) {
      const double t = 0.5 + 0.5 * rule.nodes[i];
      integral += 0.5 * rule.weights[i] * t * legendre(l, t);
    }
    EXPECT_NEAR(f[l], 2.0 * kPi * integral, kExact) << l;
    EXPECT_NEAR(general[l], f[l], kExact) << l;
  }
}

// The cosine lobe max(n·ω, 0) around any n has coefficients Λ_l Y_lm(n) (Funk–Hecke), and
// irradiance from band-limited radiance is the convolution: both against a hemisphere
// quadrature that is exact for these polynomials.
TEST(Sh, CosineLobeCoefficientsAndIrradiance) {
  std::mt19937_64 rng(10);
  const int bands = 9;
  const std::vector<double> factors = clamped_cosine_factors(bands);
  for (int k = 0; k < 5; ++k) {
    const glm::dvec3 n = random_direction(rng);
    const std::vector<double> lobe = zonal_along(bands, factors, n);
    for (int i = 0; i < bands * bands; ++i) {
      const double direct = hemisphere_integral(
          n, bands, [&](const glm::dvec3& w) { return glm::dot(n, w) * evaluate(bands, w)[i]; });
      EXPECT_NEAR(lobe[i], direct, kExact) << i;
    }
    const std::vector<double> radiance = random_coefficients(3, rng);
    std::vector<double> irradiance = radiance;
    convolve(3, factors, irradiance);
    const double e = hemisphere_integral(
        n, 3, [&](const glm::dvec3& w) { return glm::dot(n, w) * reconstruct(3, radiance, w); });
    EXPECT_NEAR(reconstruct(3, irradiance, n), e, kExact);
  }
}

// A general zonal kernel: factors from the 1-D integral agree with √(4π/(2l+1))·k_l from the
// kernel's own projection onto Y_l^0 (k(t) = t² + t⁵, band-limited to l ≤ 5).
TEST(Sh, ZonalFactorsFromKernelMatchItsZonalCoefficients) {
  const int bands = 7;
  const auto kernel = [](double t) { return t * t + t * t * t * t * t; };
  const std::vector<double> c =
      project(bands, sphere_quadrature(12), [&](const glm::dvec3& w) { return kernel(w.z); });
  std::vector<double> zonal(bands);
  for (int l = 0; l < bands; ++l) {
    zonal[l] = c[index(l, 0)];
    for (int m = -l; m <= l; ++m)
      if (m != 0) {
        EXPECT_NEAR(c[index(l, m)], 0.0, kExact);
      }
  }
  const std::vector<double> from_coefficients = zonal_factors_from_coefficients(zonal);
  const std::vector<double> from_kernel = zonal_factors(bands, kernel, 6);
  for (int l = 0; l < bands; ++l) EXPECT_NEAR(from_kernel[l], from_coefficients[l], kExact) << l;
  EXPECT_NEAR(from_kernel[6], 0.0, kExact);
}

// Most negative value of the band-limited delta at +z (ringing) relative to its peak.
double negative_lobe_ratio(int bands, std::span<const double> sigma) {
  std::vector<double> c = evaluate(bands, glm::dvec3(0, 0, 1));
  convolve(bands, sigma, c);
  const double peak = reconstruct(bands, c, glm::dvec3(0, 0, 1));
  double lowest = 0.0;
  for (int i = 0; i <= 2000; ++i) {
    const double theta = kPi * i / 2000.0;
    lowest =
        std::min(lowest, reconstruct(bands, c, glm::dvec3(std::sin(theta), 0.0, std::cos(theta))));
  }
  return -lowest / peak;
}

TEST(Sh, WindowingReducesTheNegativeLobeOfAProjectedDelta) {
  const int bands = 9;
  const std::vector<double> none = window_factors(bands, Window::kNone, bands);
  const double plain = negative_lobe_ratio(bands, none);
  EXPECT_GT(plain, 0.05);  // the truncated delta rings
  for (const Window w : {Window::kHanning, Window::kLanczos}) {
    const std::vector<double> sigma = window_factors(bands, w, bands);
    EXPECT_EQ(sigma[0], 1.0);
    for (int l = 1; l < bands; ++l) EXPECT_LT(sigma[l], sigma[l - 1]) << to_string(w) << l;
    const double windowed = negative_lobe_ratio(bands, sigma);
    EXPECT_LT(windowed, 0.5 * plain) << to_string(w);
    RecordProperty(std::string("negative_lobe_") + to_string(w), fmt::format("{:.4f}", windowed));
  }
  RecordProperty("negative_lobe_none", fmt::format("{:.4f}", plain));
  // Known values: Hanning at l = w/2 is 1/2, Lanczos is 2/π there; nothing at l ≥ w.
  EXPECT_NEAR(window_factors(5, Window::kHanning, 4)[2], 0.5, 1e-15);
  EXPECT_NEAR(window_factors(5, Window::kLanczos, 4)[2], 2.0 / kPi, 1e-15);
  EXPECT_EQ(window_factors(5, Window::kHanning, 4)[4], 0.0);
  EXPECT_EQ(window_from_string("lanczos"), Window::kLanczos);
  EXPECT_THROW(window_from_string("hamming"), Error);
  EXPECT_THROW(window_factors(5, Window::kHanning, 0.0), Error);
  EXPECT_THROW(window_factors(5, Window::kHanning, std::nan("")), Error);
}

// Monte-Carlo projection of a band-limited f: each coefficient within 4 standard deviations
// of the exact one, where the standard deviation σ_i/√N comes from the exact variance of
// the estimator (σ_i² = 4π ∫ f² Y_i² dω − c_i², by quadrature); and the reported standard
// error within 4 of its own standard deviations of σ_i/√N (relative standard deviation of a
// sample variance: √((μ4/σ⁴ − 1)/N)/2 for the standard deviation, μ4 by quadrature too).
// At 4σ the chance that one of the 9 + 9 checks fails by chance is below 10⁻³; the seed is
// fixed.
TEST(Sh, MonteCarloProjectionWithinItsStandardError) {
  std::mt19937_64 rng(11);
  const int bands = 3, n = 20000;
  std::vector<double> truth = random_coefficients(bands, rng);
  truth[0] += 4.0;
  const auto f = [&](const glm::dvec3& w) { return reconstruct(bands, truth, w); };
  const MonteCarloProjection mc = project_monte_carlo(bands, f, n, 1234);
  const SphereQuadrature rule = sphere_quadrature(4 * (bands - 1) + 4 * (bands - 1));
  for (int i = 0; i < bands * bands; ++i) {
    const auto moment = [&](int p) {  // E[(4π f Y_i − c_i)^p] under the uniform pdf
      double s = 0.0;
      for (size_t k = 0; k < rule.directions.size(); ++k) {
        const double x = 4.0 * kPi * f(rule.directions[k]) * evaluate(bands, rule.directions[k])[i];
        s += rule.weights[k] / (4.0 * kPi) * std::pow(x - truth[i], p);
      }
      return s;
    };
    const double variance = moment(2), mu4 = moment(4);
    const double sigma = std::sqrt(variance / n);
    EXPECT_NEAR(mc.coefficients[i], truth[i], 4.0 * sigma) << i;
    const double se_sd = sigma * 0.5 * std::sqrt((mu4 / (variance * variance) - 1.0) / n);
    EXPECT_NEAR(mc.standard_errors[i], sigma, 4.0 * se_sd) << i;
  }
}

// A constant has a zero-variance band-0 estimate (4π·f·Y00 in every sample), so the
// Monte-Carlo projection must give it exactly, and a standard error of 0: any error in the
// pdf shows at once, however small.
TEST(Sh, MonteCarloProjectionOfAConstantIsExactInBandZero) {
  const MonteCarloProjection mc = project_monte_carlo(
      3, [](const glm::dvec3&) { return 1.5; }, 1000, 99);
  EXPECT_NEAR(mc.coefficients[0], 1.5 * std::sqrt(4.0 * kPi), kExact);
  EXPECT_NEAR(mc.standard_errors[0], 0.0, kExact);
}

TEST(Sh, BandCountsOutOfRangeThrow) {
  EXPECT_THROW(evaluate(0, glm::dvec3(0, 0, 1)), Error);
  EXPECT_THROW(evaluate(kMaxBands + 1, glm::dvec3(0, 0, 1)), Error);
  EXPECT_THROW(clamped_cosine_factors(0), Error);
  EXPECT_THROW(ShRotation(kMaxBands + 1, glm::dmat3(1.0)), Error);
  EXPECT_NO_THROW(evaluate(kMaxBands, glm::dvec3(0, 0, 1)));
}

// shaders/sh.glsl's constants, as written, are core/sh.h's to double precision: a digit
// wrong beyond float resolution is invisible to ShGlsl.EveryFunctionMatchesCoreSh (which
// compares evaluations in float), so the text is compared here.
TEST(Sh, GlslConstantsAreTheCoreConstants) {
  std::ifstream in(std::filesystem::path(ILLUM_SOURCE_DIR) / "shaders" / "sh.glsl");
  ASSERT_TRUE(in) << "shaders/sh.glsl";
  const std::vector<double> cosine = clamped_cosine_factors(3);
  const std::map<std::string, double> expected = {
      {"kShY00", kY00},          {"kShY1", kY1},
      {"kShY2xy", kY2xy},        {"kShY20", kY20},
      {"kShY22", kY22},          {"kShCosine0", cosine[0]},
      {"kShCosine1", cosine[1]}, {"kShCosine2", cosine[2]},
      {"kShInvPi", 1.0 / kPi}};
  std::map<std::string, double> found;
  const std::regex constant(R"(const\s+float\s+(\w+)\s*=\s*([-+0-9.eE]+)\s*;)");
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, constant)) found[m[1].str()] = std::stod(m[2].str());
  }
  EXPECT_EQ(found.size(), expected.size()) << "sh.glsl declares other constants than expected";
  for (const auto& [name, value] : expected) {
    ASSERT_TRUE(found.count(name)) << name << " missing from sh.glsl";
    EXPECT_NEAR(found[name], value, 1e-15 * std::abs(value)) << name;
  }
}

// Every SH constant lives in core/sh.h and shaders/sh.glsl: no other source file spells
// out Y00 or Y1 (to 5 digits), so a basis cannot drift from the one definition.
TEST(Sh, NoShConstantOutsideTheOneDefinition) {
  namespace fs = std::filesystem;
  const fs::path root = ILLUM_SOURCE_DIR;
  const std::vector<std::string> literals = {"0.28209", "0.48860", "0.282095", "0.488603",
                                             "1.09254", "0.31539", "0.54627"};
  std::vector<std::string> offenders;
  for (const char* folder : {"src", "shaders", "apps", "bench"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
      if (!entry.is_regular_file()) continue;
      const fs::path& p = entry.path();
      const std::string ext = p.extension().string();
      if (ext != ".h" && ext != ".cpp" && ext != ".glsl" && ext != ".vert" && ext != ".frag" &&
          ext != ".comp")
        continue;
      if (p.filename() == "sh.h" || p.filename() == "sh.glsl") continue;
      std::ifstream in(p);
      std::stringstream text;
      text << in.rdbuf();
      for (const std::string& l : literals)
        if (text.str().find(l) != std::string::npos)
          offenders.push_back(fs::relative(p, root).string() + " (" + l + ")");
    }
  }
  EXPECT_TRUE(offenders.empty()) << ::testing::PrintToString(offenders);
}

}  // namespace
}  // namespace illum::sh
