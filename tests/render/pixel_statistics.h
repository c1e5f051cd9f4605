// Statistics for checking Monte Carlo images pixel by pixel: per-pixel means and variances
// from repeated renders with independent seeds (every seed scrambles every pixel's Sobol'
// sequence independently), Student's t quantiles for the tests built on them, and the
// Bonferroni rule that keeps a family of many per-pixel checks at one false-alarm level.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "illum/core/image.h"

namespace illum::test {

// False-alarm probability of one whole family of checks (all pixels of a test, all regions
// and channels): each of n checks in it is run at kFamilyFalseAlarm / n (Bonferroni). Every
// test is seeded, so a pass is reproducible; this bounds how unlucky a seed could have been.
inline constexpr double kFamilyFalseAlarm = 1e-4;

// Regularized incomplete beta I_x(a, b), from its continued fraction (evaluated with the
// modified Lentz method) on the side of x where it converges quickly.
inline double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - incomplete_beta(b, a, 1.0 - x);
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  constexpr double kTiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double f = d;
  for (int m = 1; m < 10000; ++m) {
    for (int odd = 0; odd < 2; ++odd) {
      // Even terms m(b − m)x / ((a + 2m − 1)(a + 2m)), odd ones −(a + m)(a + b + m)x /
      // ((a + 2m)(a + 2m + 1)).
      const double num = odd ? -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))
                             : m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
      d = 1.0 + num * d;
      if (std::abs(d) < kTiny) d = kTiny;
      c = 1.0 + num / c;
      if (std::abs(c) < kTiny) c = kTiny;
      d = 1.0 / d;
      f *= c * d;
      if (odd && std::abs(c * d - 1.0) < 1e-15) return std::exp(log_front) * f / a;
    }
  }
  return std::exp(log_front) * f / a;
}

// P(T > t) for Student's t with nu degrees of freedom, t ≥ 0.
inline double student_t_upper_tail(double t, double nu) {
  return 0.5 * incomplete_beta(0.5 * nu, 0.5, nu / (nu + t * t));
}

// The t with P(T > t) = upper_tail (upper_tail in (0, 0.5)), by bisection.
inline double student_t_quantile(double upper_tail, double nu) {
  double lo = 0.0, hi = 1.0;
  while (student_t_upper_tail(hi, nu) > upper_tail) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_upper_tail(mid, nu) > upper_tail ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Two-sided critical value for one of `checks` t-tests with nu degrees of freedom that
// together keep kFamilyFalseAlarm.
inline double family_t(int checks, double nu) {
  return student_t_quantile(0.5 * kFamilyFalseAlarm / checks, nu);
}

// Welch–Satterthwaite degrees of freedom of a difference of two means whose variances
// (of the mean) v1, v2 were estimated from n1, n2 runs.
inline double welch_dof(double v1, int n1, double v2, int n2) {
  const double num = (v1 + v2) * (v1 + v2);
  const double den = v1 * v1 / (n1 - 1) + v2 * v2 / (n2 - 1);
  return den > 0.0 ? num / den : static_cast<double>(n1 + n2 - 2);
}

// Per-pixel, per-channel mean and variance of the mean over a series of images of one size
// (independent renders: the same estimator with different seeds).
class ImageSeries {
 public:
  void add(const Image& image) {
    if (n_ == 0) {
      width_ = image.width();
      height_ = image.height();
      channels_ = image.channels();
      sum_.assign(image.data().size(), 0.0);
      sum2_.assign(image.data().size(), 0.0);
    }
    for (size_t i = 0; i < sum_.size(); ++i) {
      const double v = image.data()[i];
      sum_[i] += v;
      sum2_[i] += v * v;
    }
    ++n_;
  }
  int count() const { return n_; }
  int width() const { return width_; }
  int height() const { return height_; }
  double mean(int x, int y, int c) const { return sum_[index(x, y, c)] / n_; }
  // s²/n: the variance of mean(), estimated with n − 1 degrees of freedom.
  double variance_of_mean(int x, int y, int c) const {
    const size_t i = index(x, y, c);
    const double m = sum_[i] / n_;
    return std::max(sum2_[i] - n_ * m * m, 0.0) / (static_cast<double>(n_) * (n_ - 1));
  }

 private:
  size_t index(int x, int y, int c) const {
    return (static_cast<size_t>(y) * width_ + x) * channels_ + c;
  }
  int n_ = 0, width_ = 0, height_ = 0, channels_ = 0;
  std::vector<double> sum_, sum2_;
};

// Byte-for-byte equality of two images (EXPECT_EQ on the floats would call −0 and +0 equal
// and NaN unequal to itself).
inline bool identical_bytes(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0;
}

}  // namespace illum::test
