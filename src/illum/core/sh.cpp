#include "illum/core/sh.h"

#include <array>
#include <cmath>
#include <numbers>

#include "illum/core/error.h"
#include "illum/core/rng.h"

namespace illum::sh {

namespace {

constexpr double kPi = std::numbers::pi;

// Coefficients of the normalised associated Legendre recurrence for N_l^m = K_l^m P_l^m(z)
// / sin^m θ (no Condon–Shortley phase), built once in double:
//   N_0^0 = 1/√(4π),   N_m^m = √((2m+1)/(2m)) · N_{m−1}^{m−1}
//   N_{m+1}^m = √(2m+3) · z · N_m^m
//   N_l^m = a_lm · (z · N_{l−1}^m − b_lm · N_{l−2}^m),
//     a_lm = √((4l² − 1)/(l² − m²)),  b_lm = √(((l−1)² − m²)/(4(l−1)² − 1))
// (each follows from the unnormalised recurrence (l−m) P_l^m = (2l−1) z P_{l−1}^m −
// (l+m−1) P_{l−2}^m by dividing through by the ratio of the K's).
struct LegendreTable {
  std::array<double, kMaxBands> diagonal{};     // N_m^m
  std::array<double, kMaxBands> subdiagonal{};  // √(2m+3)
  std::array<double, kMaxBands * kMaxBands> a{}, b{};
  LegendreTable() {
    diagonal[0] = 1.0 / std::sqrt(4.0 * kPi);
    for (int m = 1; m < kMaxBands; ++m)
      diagonal[m] = diagonal[m - 1] * std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int m = 0; m < kMaxBands; ++m) subdiagonal[m] = std::sqrt(2.0 * m + 3.0);
    for (int l = 2; l < kMaxBands; ++l)
      for (int m = 0; m + 2 <= l; ++m) {
        const double l2 = double(l) * l, lm1 = double(l - 1) * (l - 1), m2 = double(m) * m;
        a[l * kMaxBands + m] = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
        b[l * kMaxBands + m] = std::sqrt((lm1 - m2) / (4.0 * lm1 - 1.0));
      }
  }
};

const LegendreTable& legendre_table() {
  static const LegendreTable table;
  return table;
}

// A uniform double in [0, 1) from 53 random bits.
double next_unit_double(Rng& rng) {
  const uint64_t hi = rng.next_u32() >> 5, lo = rng.next_u32() >> 6;  // 27 + 26 bits
  return static_cast<double>((hi << 26) | lo) * 0x1p-53;
}

// P_l(t) for l < bands by Bonnet's recurrence (zonal factors only).
void legendre_polynomials(int bands, double t, double* p) {
  p[0] = 1.0;
  if (bands > 1) p[1] = t;
  for (int l = 2; l < bands; ++l)
    p[l] = ((2.0 * l - 1.0) * t * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
}

}  // namespace

template <class T>
void evaluate_recurrence(int bands, const glm::vec<3, T>& w, std::span<T> out) {
  check_bands(bands, "SH evaluation");
  ILLUM_CHECK(out.size() >= static_cast<size_t>(bands * bands), "SH output of {} for {} bands",
              out.size(), bands);
  const LegendreTable& table = legendre_table();
  const T z = w.z;
  const T sqrt2 = static_cast<T>(std::numbers::sqrt2);
  T c = 1, s = 0;  // cos(mφ)·sin^m θ, sin(mφ)·sin^m θ
  for (int m = 0; m < bands; ++m) {
    // Walk up band by band along this m: N_l^m for l = m, m+1, ...
    T n_prev2 = 0, n_prev = static_cast<T>(table.diagonal[m]);
    for (int l = m; l < bands; ++l) {
      T n;
      if (l == m)
        n = n_prev;
      else if (l == m + 1)
        n = static_cast<T>(table.subdiagonal[m]) * z * n_prev;
      else
        n = static_cast<T>(table.a[l * kMaxBands + m]) *
            (z * n_prev - static_cast<T>(table.b[l * kMaxBands + m]) * n_prev2);
      if (l > m) {
        n_prev2 = n_prev;
        n_prev = n;
      }
      if (m == 0) {
        out[index(l, 0)] = n;
      } else {
        out[index(l, m)] = sqrt2 * n * c;
        out[index(l, -m)] = sqrt2 * n * s;
      }
    }
    const T c_next = w.x * c - w.y * s;
    s = w.x * s + w.y * c;
    c = c_next;
  }
}

template <class T>
void evaluate(int bands, const glm::vec<3, T>& w, std::span<T> out) {
  if (bands > 3) return evaluate_recurrence(bands, w, out);
  check_bands(bands, "SH evaluation");
  ILLUM_CHECK(out.size() >= static_cast<size_t>(bands * bands), "SH output of {} for {} bands",
              out.size(), bands);
  out[0] = static_cast<T>(kY00);
  if (bands < 2) return;
  const T y1 = static_cast<T>(kY1);
  out[1] = y1 * w.y;
  out[2] = y1 * w.z;
  out[3] = y1 * w.x;
  if (bands < 3) return;
  const T y2 = static_cast<T>(kY2xy);
  out[4] = y2 * w.x * w.y;
  out[5] = y2 * w.y * w.z;
  out[6] = static_cast<T>(kY20) * (3 * w.z * w.z - 1);
  out[7] = y2 * w.x * w.z;
  out[8] = static_cast<T>(kY22) * (w.x * w.x - w.y * w.y);
}

template void evaluate<float>(int, const glm::vec3&, std::span<float>);
template void evaluate<double>(int, const glm::dvec3&, std::span<double>);
template void evaluate_recurrence<float>(int, const glm::vec3&, std::span<float>);
template void evaluate_recurrence<double>(int, const glm::dvec3&, std::span<double>);

std::vector<double> evaluate(int bands, const glm::dvec3& w) {
  check_bands(bands, "SH evaluation");
  std::vector<double> y(bands * bands);
  evaluate<double>(bands, w, y);
  return y;
}

GaussLegendre gauss_legendre(int n) {
  ILLUM_CHECK(n >= 1 && n <= 4096, "Gauss-Legendre order {}", n);
  GaussLegendre rule;
  rule.nodes.resize(n);
  rule.weights.resize(n);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Tricomi's estimate of the i-th largest root, then Newton on P_n.
    double t = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      // P_n' = n (t P_n − P_{n−1}) / (t² − 1)
      dp = n * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / dp;
      t -= step;
      if (std::abs(step) < 1e-15) break;
    }
    const double weight = 2.0 / ((1.0 - t * t) * dp * dp);
    rule.nodes[n - 1 - i] = t;
    rule.nodes[i] = -t;
    rule.weights[i] = rule.weights[n - 1 - i] = weight;
  }
  return rule;
}

SphereQuadrature sphere_quadrature(int degree) {
  ILLUM_CHECK(degree >= 0 && degree <= 2048, "sphere quadrature degree {}", degree);
  const GaussLegendre z_rule = gauss_legendre(degree / 2 + 1);
  const int n_phi = degree + 1;
  SphereQuadrature rule;
  for (size_t i = 0; i < z_rule.nodes.size(); ++i) {
    const double z = z_rule.nodes[i], r = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * kPi * j / n_phi;
      rule.directions.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
      rule.weights.push_back(z_rule.weights[i] * 2.0 * kPi / n_phi);
    }
  }
  return rule;
}

std::vector<double> project(int bands, const SphereQuadrature& rule,
                            const std::function<double(const glm::dvec3&)>& f) {
  check_bands(bands, "SH projection");
  std::vector<double> c(bands * bands, 0.0), y(bands * bands);
  for (size_t k = 0; k < rule.directions.size(); ++k) {
    evaluate<double>(bands, rule.directions[k], y);
    const double v = f(rule.directions[k]) * rule.weights[k];
    for (size_t i = 0; i < c.size(); ++i) c[i] += v * y[i];
  }
  return c;
}

MonteCarloProjection project_monte_carlo(int bands,
                                         const std::function<double(const glm::dvec3&)>& f,
                                         int samples, uint64_t seed) {
  check_bands(bands, "SH projection");
  ILLUM_CHECK(samples >= 2, "Monte-Carlo SH projection needs 2 or more samples, not {}", samples);
  const size_t count = static_cast<size_t>(bands) * bands;
  std::vector<double> sum(count, 0.0), sum_sq(count, 0.0), y(count);
  Rng rng(seed);
  for (int k = 0; k < samples; ++k) {
    const double z = 1.0 - 2.0 * next_unit_double(rng);
    const double phi = 2.0 * kPi * next_unit_double(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const glm::dvec3 w(r * std::cos(phi), r * std::sin(phi), z);
    evaluate<double>(bands, w, y);
    const double v = 4.0 * kPi * f(w);  // f / pdf, pdf = 1/(4π)
    for (size_t i = 0; i < count; ++i) {
      const double x = v * y[i];
      sum[i] += x;
      sum_sq[i] += x * x;
    }
  }
  MonteCarloProjection result;
  result.coefficients.resize(count);
  result.standard_errors.resize(count);
  const double n = samples;
  for (size_t i = 0; i < count; ++i) {
    const double mean = sum[i] / n;
    const double variance = std::max(0.0, (sum_sq[i] - n * mean * mean) / (n - 1.0));
    result.coefficients[i] = mean;
    result.standard_errors[i] = std::sqrt(variance / n);
  }
  return result;
}

double reconstruct(int bands, std::span<const double> coefficients, const glm::dvec3& w) {
  check_bands(bands, "SH reconstruction");
  ILLUM_CHECK(coefficients.size() >= static_cast<size_t>(bands * bands),
              "{} SH coefficients for {} bands", coefficients.size(), bands);
  std::vector<double> y(bands * bands);
  evaluate<double>(bands, w, y);
  double f = 0.0;
  for (size_t i = 0; i < y.size(); ++i) f += coefficients[i] * y[i];
  return f;
}

std::vector<double> clamped_cosine_factors(int bands) {
  check_bands(bands, "clamped-cosine SH factors");
  std::vector<double> factors(bands, 0.0);
  factors[0] = kPi;
  if (bands > 1) factors[1] = 2.0 * kPi / 3.0;
  for (int l = 2; l < bands; l += 2) {
    // l! / (2^l ((l/2)!)²) = C(l, l/2) / 2^l, built as a product to stay in range.
    double central = 1.0;
    for (int k = 1; k <= l / 2; ++k) central *= (l / 2.0 + k) / (4.0 * k);
    const double sign = (l / 2 - 1) % 2 == 0 ? 1.0 : -1.0;
    factors[l] = 2.0 * kPi * sign / ((l + 2.0) * (l - 1.0)) * central;
  }
  return factors;
}

std::vector<double> zonal_factors(int bands, const std::function<double(double)>& kernel,
                                  int nodes) {
  check_bands(bands, "zonal SH factors");
  const GaussLegendre rule = gauss_legendre(nodes);
  std::vector<double> factors(bands, 0.0), p(bands);
  for (const double half : {-0.5, 0.5}) {  // [−1, 0] and [0, 1]: t = half + node/2
    for (size_t k = 0; k < rule.nodes.size(); ++k) {
      const double t = half + 0.5 * rule.nodes[k];
      legendre_polynomials(bands, t, p.data());
      const double v = 2.0 * kPi * kernel(t) * 0.5 * rule.weights[k];
      for (int l = 0; l < bands; ++l) factors[l] += v * p[l];
    }
  }
  return factors;
}

std::vector<double> zonal_factors_from_coefficients(std::span<const double> zonal) {
  std::vector<double> factors(zonal.size());
  for (size_t l = 0; l < zonal.size(); ++l)
    factors[l] = std::sqrt(4.0 * kPi / (2.0 * l + 1.0)) * zonal[l];
  return factors;
}

void convolve(int bands, std::span<const double> factors, std::span<double> coefficients) {
  check_bands(bands, "SH convolution");
  ILLUM_CHECK(factors.size() >= static_cast<size_t>(bands) &&
                  coefficients.size() >= static_cast<size_t>(bands * bands),
              "SH convolution: {} factors, {} coefficients for {} bands", factors.size(),
              coefficients.size(), bands);
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) coefficients[index(l, m)] *= factors[l];
}

std::vector<double> zonal_along(int bands, std::span<const double> factors, const glm::dvec3& n) {
  std::vector<double> c = evaluate(bands, n);
  convolve(bands, factors, c);
  return c;
}

Window window_from_string(const std::string& name) {
  if (name == "none") return Window::kNone;
  if (name == "hanning") return Window::kHanning;
  if (name == "lanczos") return Window::kLanczos;
  throw Error(fmt::format("unknown SH window '{}' (none, hanning, lanczos)", name));
}

const char* to_string(Window window) {
  switch (window) {
    case Window::kNone:
      return "none";
    case Window::kHanning:
      return "hanning";
    case Window::kLanczos:
      return "lanczos";
  }
  return "?";
}

std::vector<double> window_factors(int bands, Window window, double width) {
  check_bands(bands, "SH window");
  if (!(width > 0.0) || !std::isfinite(width))
    throw Error(fmt::format("SH window width {} must be a positive number", width));
  std::vector<double> sigma(bands, 1.0);
  if (window == Window::kNone) return sigma;
  for (int l = 0; l < bands; ++l) {
    const double x = kPi * l / width;
    if (l >= width)
      sigma[l] = 0.0;
    else if (window == Window::kHanning)
      sigma[l] = 0.5 * (1.0 + std::cos(x));
    else
      sigma[l] = l == 0 ? 1.0 : std::sin(x) / x;
  }
  return sigma;
}

}  // namespace illum::sh
