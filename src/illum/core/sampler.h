// Low-discrepancy sample points: Sobol' (Joe–Kuo direction numbers) with Owen-style
// hash scrambling (Laine–Karras / Burley 2020), so every pixel gets a decorrelated
// sequence and estimates still converge faster than with independent random numbers.
#pragma once

#include <cstdint>

#include "illum/core/math.h"

namespace illum {

class SobolSampler {
 public:
  static constexpr int kMaxDimensions = 64;
  // `seed` scrambles the whole sequence (e.g. hash of pixel and user seed).
  explicit SobolSampler(uint64_t seed = 0);
  // Starts sample `index` of the sequence; dimensions restart at 0.
  void start_sample(uint32_t index);
  // Next dimension of the current sample, in [0, 1). Past kMaxDimensions it falls back to
  // a hashed random number (still deterministic).
  float next_1d();
  vec2 next_2d();

  // Raw scrambled Sobol' value of `index` in dimension `dim` with scramble seed `seed`.
  static float sample(uint32_t index, int dim, uint32_t seed);

 private:
  uint64_t seed_;
  uint32_t index_ = 0;
  int dim_ = 0;
};

}  // namespace illum
