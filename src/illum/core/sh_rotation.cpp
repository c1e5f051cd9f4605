#include "illum/core/sh_rotation.h"

#include <cmath>

#include "illum/core/error.h"
#include "illum/core/sh.h"

namespace illum::sh {

namespace {

// Band 1 is (Y_1^−1, Y_1^0, Y_1^1) ∝ (y, z, x): the axis each m stands for.
constexpr int kAxisOfM[3] = {1, 2, 0};

// One band's block with signed indices.
struct Block {
  int l;
  std::vector<double>* values;
  double operator()(int m, int m_in) const { return (*values)[(m + l) * (2 * l + 1) + (m_in + l)]; }
  double& at(int m, int m_in) { return (*values)[(m + l) * (2 * l + 1) + (m_in + l)]; }
};

// Ivanic & Ruedenberg's P: band 1's row i combined with band l − 1's row a, for column b.
double p_term(const Block& r1, const Block& prev, int i, int a, int b, int l) {
  if (b == l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
  if (b == -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
  return r1(i, 0) * prev(a, b);
}

}  // namespace

ShRotation::ShRotation(int bands, const glm::dmat3& r) : bands_(bands), blocks_(bands) {
  check_bands(bands, "SH rotation");
  // A proper rotation: rᵀr = I and det r = +1, to well within double rounding of a matrix
  // built from unit vectors (a reflection would need the parity (−1)^l on top).
  const glm::dmat3 gram = glm::transpose(r) * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      ILLUM_CHECK(std::abs(gram[i][j] - (i == j ? 1.0 : 0.0)) < 1e-6,
                  "SH rotation: matrix is not orthonormal");
  ILLUM_CHECK(glm::determinant(r) > 0.0, "SH rotation: matrix is a reflection");

  blocks_[0] = {1.0};
  if (bands < 2) return;
  blocks_[1].resize(9);
  Block r1{1, &blocks_[1]};
  for (int m = -1; m <= 1; ++m)
    for (int n = -1; n <= 1; ++n)
      r1.at(m, n) = r[kAxisOfM[n + 1]][kAxisOfM[m + 1]];  // glm: r[column][row]

  for (int l = 2; l < bands; ++l) {
    blocks_[l].assign((2 * l + 1) * (2 * l + 1), 0.0);
    Block cur{l, &blocks_[l]};
    const Block prev{l - 1, &blocks_[l - 1]};
    for (int m = -l; m <= l; ++m) {
      const int am = std::abs(m);
      const double d = m == 0 ? 1.0 : 0.0;
      for (int n = -l; n <= l; ++n) {
        const double denom =
            std::abs(n) < l ? double(l + n) * (l - n) : double(2 * l) * (2 * l - 1);
        const double u = std::sqrt(double(l + m) * (l - m) / denom);
        const double v =
            0.5 * std::sqrt((1.0 + d) * (l + am - 1.0) * (l + am) / denom) * (1.0 - 2.0 * d);
        const double w = -0.5 * std::sqrt((l - am - 1.0) * (l - am) / denom) * (1.0 - d);
        double value = 0.0;
        if (u != 0.0) value += u * p_term(r1, prev, 0, m, n, l);
        if (v != 0.0) {
          double big_v;
          if (m == 0)
            big_v = p_term(r1, prev, 1, 1, n, l) + p_term(r1, prev, -1, -1, n, l);
          else if (m > 0)
            big_v = p_term(r1, prev, 1, m - 1, n, l) * std::sqrt(m == 1 ? 2.0 : 1.0) -
                    (m == 1 ? 0.0 : p_term(r1, prev, -1, -m + 1, n, l));
          else
            big_v = (m == -1 ? 0.0 : p_term(r1, prev, 1, m + 1, n, l)) +
                    p_term(r1, prev, -1, -m - 1, n, l) * std::sqrt(m == -1 ? 2.0 : 1.0);
          value += v * big_v;
        }
        if (w != 0.0) {
          const double big_w =
              m > 0 ? p_term(r1, prev, 1, m + 1, n, l) + p_term(r1, prev, -1, -m - 1, n, l)
                    : p_term(r1, prev, 1, m - 1, n, l) - p_term(r1, prev, -1, -m + 1, n, l);
          value += w * big_w;
        }
        cur.at(m, n) = value;
      }
    }
  }
}

std::vector<double> ShRotation::apply(std::span<const double> in) const {
  std::vector<double> out(bands_ * bands_);
  apply<double>(in, out);
  return out;
}

}  // namespace illum::sh
