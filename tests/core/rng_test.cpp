// PCG32: range, uniformity (chi-square), bounded integers, jumps and stream independence.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "chi_square.h"
#include "illum/core/error.h"
#include "illum/core/rng.h"

namespace illum {
namespace {

using test::chi_square_test;
using test::kSignificance;

TEST(Rng, UnitFloatNeverReachesOne) {
  EXPECT_EQ(u32_to_unit_float(0u), 0.0f);
  EXPECT_LT(u32_to_unit_float(0xffffffffu), 1.0f);
  EXPECT_EQ(u32_to_unit_float(0xffffffffu), 1.0f - 0x1p-24f);
  Rng rng(1);
  for (int i = 0; i < 100000; ++i) {
    const float f = rng.next_float();
    ASSERT_GE(f, 0.0f);
    ASSERT_LT(f, 1.0f);
  }
}

TEST(Rng, FloatsAreUniform) {
  const int bins = 1000, n = 1 << 20;
  std::vector<double> observed(bins, 0.0), expected(bins, static_cast<double>(n) / bins);
  Rng rng(2024, 5);
  for (int i = 0; i < n; ++i) observed[static_cast<size_t>(rng.next_float() * bins)] += 1.0;
  const auto r = chi_square_test(observed, expected);
  EXPECT_GT(r.p_value, kSignificance) << r.statistic;
}

TEST(Rng, SuccessivePairsAreUniform) {
  // Serial test: (x_i, x_{i+1}) uniform on a 32 × 32 grid.
  const int side = 32, n = 1 << 20;
  std::vector<double> observed(side * side, 0.0),
      expected(side * side, static_cast<double>(n) / (side * side));
  Rng rng(77);
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<size_t>(rng.next_float() * side),
               b = static_cast<size_t>(rng.next_float() * side);
    observed[a * side + b] += 1.0;
  }
  EXPECT_GT(chi_square_test(observed, expected).p_value, kSignificance);
}

TEST(Rng, BoundedIsUniformAndInRange) {
  for (uint32_t bound : {1u, 7u, 700u, 0xc0000000u}) {
    SCOPED_TRACE(bound);
    Rng rng(bound);
    const int bins = 7, n = 700000;
    std::vector<double> observed(bins, 0.0);
    for (int i = 0; i < n; ++i) {
      const uint32_t v = rng.next_bounded(bound);
      ASSERT_LT(v, bound);
      observed[v % bins] += 1.0;
    }
    if (bound % bins != 0) continue;  // residues mod 7 are equally likely only for multiples of 7
    const std::vector<double> expected(bins, static_cast<double>(n) / bins);
    EXPECT_GT(chi_square_test(observed, expected).p_value, kSignificance);
  }
  // With bound = 3·2^30 a plain modulo would return values below 2^30 half of the time
  // (2^32 mod bound = 2^30, so those residues get two chances); with rejection they are a
  // third. Binomial(n, 1/3): 5 sd is a two-sided level of about 6e-7.
  Rng rng(3);
  const int n = 200000;
  int low = 0;
  for (int i = 0; i < n; ++i) low += rng.next_bounded(0xc0000000u) < 0x40000000u ? 1 : 0;
  EXPECT_NEAR(low, n / 3.0, 5.0 * std::sqrt(n * (1.0 / 3.0) * (2.0 / 3.0)));
  EXPECT_THROW(rng.next_bounded(0), InternalError);
}

TEST(Rng, DeterministicAndSeedDependent) {
  Rng a(5, 9), b(5, 9), c(6, 9), d(5, 10);
  int same_c = 0, same_d = 0;
  for (int i = 0; i < 1000; ++i) {
    const uint32_t x = a.next_u32();
    ASSERT_EQ(x, b.next_u32());
    same_c += x == c.next_u32();
    same_d += x == d.next_u32();
  }
  EXPECT_LT(same_c, 2);  // coincidences have probability 2^-32 each
  EXPECT_LT(same_d, 2);
}

TEST(Rng, AdvanceMatchesStepping) {
  Rng stepped(42, 3), jumped(42, 3);
  for (int i = 0; i < 12345; ++i) stepped.next_u32();
  jumped.advance(12345);
  EXPECT_EQ(stepped.next_u32(), jumped.next_u32());
  // A negative jump goes back.
  Rng back = jumped;
  const uint32_t first = back.next_u32();
  back.next_u32();
  back.advance(-2);
  EXPECT_EQ(back.next_u32(), first);
}

TEST(Rng, StreamsAreUncorrelated) {
  // Pearson correlation of two streams with the same seed: sd 1/√n under independence;
  // 5 sd is a two-sided level of about 6e-7.
  const int n = 200000;
  Rng a(7, 1), b(7, 2);
  double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
  for (int i = 0; i < n; ++i) {
    const double x = a.next_float(), y = b.next_float();
    sa += x;
    sb += y;
    sab += x * y;
    saa += x * x;
    sbb += y * y;
  }
  const double cov = sab / n - (sa / n) * (sb / n);
  const double r = cov / std::sqrt((saa / n - sa * sa / n / n) * (sbb / n - sb * sb / n / n));
  EXPECT_LT(std::abs(r), 5.0 / std::sqrt(n));
}

TEST(Rng, HashMixSpreadsInputs) {
  EXPECT_NE(hash_mix(1, 2, 3), hash_mix(3, 2, 1));
  EXPECT_NE(hash_mix(0), hash_mix(1));
  EXPECT_EQ(hash_mix(5, 6), hash_mix(5, 6, 0));
  // Avalanche: flipping one input bit flips about half of the 64 output bits. Over 64
  // flips the count is Binomial(4096, 1/2): sd 32, 5 sd tolerance.
  int flipped = 0;
  for (int bit = 0; bit < 64; ++bit)
    flipped += std::popcount(hash_mix(12345) ^ hash_mix(12345 ^ (1ull << bit)));
  EXPECT_NEAR(flipped, 2048, 5 * 32);
}

}  // namespace
}  // namespace illum
