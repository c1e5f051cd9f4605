// Mean and standard error of a stream of Monte Carlo samples, for checks of the form
// |estimate − expected| ≤ kZ · standard error.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace illum::test {

// 5 standard errors: a false failure below 1e-6 per check for a normal estimate.
inline constexpr double kZ = 5.0;

struct RunningStat {
  double sum = 0, sum2 = 0;
  int64_t n = 0;
  void add(double x) {
    sum += x;
    sum2 += x * x;
    ++n;
  }
  double mean() const { return sum / static_cast<double>(n); }
  double standard_error() const {
    const double m = mean();
    return std::sqrt(std::max(sum2 / static_cast<double>(n) - m * m, 0.0) / static_cast<double>(n));
  }
};

}  // namespace illum::test
