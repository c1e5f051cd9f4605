// Rotation of real SH coefficients (convention: sh.h) of any band count, built with the
// recurrences of Ivanic & Ruedenberg (J. Phys. Chem. 100, 1996; corrections 102, 1998):
// band l's matrix from band l − 1's and the 3×3 rotation itself, O(l²) entries of O(1)
// work each, no Euler angles (so no gimbal special cases). Matrices are built and stored in
// double (the recurrence's rounding grows with l; in float it would reach ~1e-5 by l = 16)
// and applied to float or double coefficients.
#pragma once

#include <span>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

namespace illum::sh {

class ShRotation {
 public:
  // The rotation r (applied to directions as r·ω; glm's column-major dmat3) must be proper
  // orthonormal; anything else is an internal error (ILLUM_CHECK). apply() then maps the
  // coefficients of f to those of the rotated function g(ω) = f(rᵀ·ω): a lobe of f around
  // direction d becomes a lobe of g around r·d.
  ShRotation(int bands, const glm::dmat3& r);

  int bands() const { return bands_; }
  // Entry (m, m') of band l's (2l+1)² block: row m is the output coefficient.
  double entry(int l, int m, int m_in) const {
    return blocks_[l][(m + l) * (2 * l + 1) + (m_in + l)];
  }

  // out = M·in over the first bands² coefficients (in and out must not overlap); T is float,
  // double or a glm vector of them (RGB coefficients).
  template <class T>
  void apply(std::span<const T> in, std::span<T> out) const {
    for (int l = 0; l < bands_; ++l) {
      const int base = l * l, size = 2 * l + 1;
      const std::vector<double>& block = blocks_[l];
      for (int row = 0; row < size; ++row) {
        T sum = T(0);
        for (int col = 0; col < size; ++col)
          sum += in[base + col] * scalar_of(sum, block[row * size + col]);
        out[base + row] = sum;
      }
    }
  }
  std::vector<double> apply(std::span<const double> in) const;

 private:
  template <class T>
  static auto scalar_of(const T&, double v) {
    if constexpr (std::is_floating_point_v<T>)
      return static_cast<T>(v);
    else
      return static_cast<typename T::value_type>(v);
  }

  int bands_;
  std::vector<std::vector<double>> blocks_;  // band l: (2l+1)² row-major
};

}  // namespace illum::sh
