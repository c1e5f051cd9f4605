// Goodness-of-fit helpers for the sampling tests: histograms over a 2-D parameter grid,
// expected counts from numerically integrating a pdf over each cell, and Pearson's
// chi-square test with its p-value from the regularized incomplete gamma function.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

namespace illum::test {

// Significance level for every goodness-of-fit test in tests/core: a correct warp fails
// with probability 1e-4 per test (all tests are seeded, so a pass is reproducible; the
// threshold bounds how unlucky a seed could have been). A wrong warp in the negative
// tests gives p-values many orders of magnitude below it.
inline constexpr double kSignificance = 1e-4;

// Regularized upper incomplete gamma Q(a, x) = Γ(a, x) / Γ(a): a power series for
// P = 1 − Q when x < a + 1, a continued fraction (modified Lentz) for Q otherwise.
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(log_prefix));
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return std::exp(log_prefix) * h;
}

struct ChiSquareResult {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 1.0;
};

// Pearson's test of observed against expected counts. Cells expecting fewer than
// `min_expected` samples are pooled (the chi-square approximation needs about five per
// cell); a sample in a cell of zero expected count fails outright.
inline ChiSquareResult chi_square_test(const std::vector<double>& observed,
                                       const std::vector<double>& expected,
                                       double min_expected = 5.0) {
  ChiSquareResult r;
  double pooled_obs = 0.0, pooled_exp = 0.0;
  std::vector<std::pair<double, double>> cells;  // (observed, expected)
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] <= 0.0) {
      if (observed[i] > 0.0) {
        r.statistic = std::numeric_limits<double>::infinity();
        r.p_value = 0.0;
        return r;
      }
      continue;
    }
    if (expected[i] < min_expected) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
    } else {
      cells.emplace_back(observed[i], expected[i]);
    }
  }
  if (pooled_exp >= min_expected || cells.empty()) {
    if (pooled_exp > 0.0) cells.emplace_back(pooled_obs, pooled_exp);
  } else if (pooled_exp > 0.0) {
    // Too little for a cell of its own: merge into the smallest regular cell.
    auto smallest = std::min_element(cells.begin(), cells.end(), [](const auto& a, const auto& b) {
      return a.second < b.second;
    });
    smallest->first += pooled_obs;
    smallest->second += pooled_exp;
  }
  for (const auto& [o, e] : cells) r.statistic += (o - e) * (o - e) / e;
  r.dof = static_cast<int>(cells.size()) - 1;
  r.p_value = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
  return r;
}

// A grid of nx × ny cells over [x0, x1) × [y0, y1) in some parameterization of the
// warp's output (e.g. (cos θ, φ) for directions).
struct Grid {
  int nx, ny;
  double x0, x1, y0, y1;
  int cell_count() const { return nx * ny; }
  // Cell index of (x, y), or -1 outside the grid.
  int cell(double x, double y) const {
    const auto i = static_cast<int>(std::floor((x - x0) / (x1 - x0) * nx));
    const auto j = static_cast<int>(std::floor((y - y0) / (y1 - y0) * ny));
    // Points exactly on the upper edge (e.g. cos θ = 1) belong to the last cell.
    const int ci = (x == x1) ? nx - 1 : i, cj = (y == y1) ? ny - 1 : j;
    if (ci < 0 || ci >= nx || cj < 0 || cj >= ny) return -1;
    return cj * nx + ci;
  }
};

// N × ∫cell density, by the midpoint rule on sub × sub points per cell. `density` is the
// pdf expressed in the grid's parameters (pdf × Jacobian of the parameterization).
inline std::vector<double> expected_counts(const Grid& g,
                                           const std::function<double(double, double)>& density,
                                           double n, int sub = 4) {
  std::vector<double> out(static_cast<size_t>(g.cell_count()));
  const double dx = (g.x1 - g.x0) / (g.nx * sub), dy = (g.y1 - g.y0) / (g.ny * sub);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      double sum = 0.0;
      for (int b = 0; b < sub; ++b)
        for (int a = 0; a < sub; ++a)
          sum += density(g.x0 + (i * sub + a + 0.5) * dx, g.y0 + (j * sub + b + 0.5) * dy);
      out[static_cast<size_t>(j * g.nx + i)] = n * sum * dx * dy;
    }
  return out;
}

}  // namespace illum::test
