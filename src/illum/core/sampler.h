// Low-discrepancy sample points: shuffled, Owen-scrambled Sobol' points padded pairwise
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
//
// Only the first two Sobol' dimensions are used — dimension 0 is the van der Corput
// sequence (bit reversal of the index), dimension 1 comes from the primitive polynomial
// x + 1 (its generator matrix is Pascal's triangle mod 2) — so no direction-number table
// is needed. Together they form a (0,2)-sequence: every aligned block of 2^m points is a
// (0,m,2)-net. Higher dimensions are built by padding: dimensions (2p, 2p+1) form pair p,
// and every pair gets
//   * its own Owen scramble of each component: a Laine–Karras-style hash of the
//     bit-reversed value (each bit flipped by a function of the more significant bits
//     only, i.e. a nested uniform scramble), seeded from the sampler seed, the pair and
//     the component; it keeps the net property;
//   * its own shuffled index: the sample index Owen-scrambled with a seed from the sampler
//     seed and the pair, which permutes every aligned block of 2^m indices within itself,
//     so the first 2^m samples of a pair are still a (0,m,2)-net while different pairs
//     are decorrelated.
// next_1d() and next_2d() each consume one pair (two dimensions); next_1d returns its
// component 0, a scrambled van der Corput sequence, stratified in 1-D.
#pragma once

#include <array>
#include <cstdint>

#include "illum/core/math.h"

namespace illum {

class SobolSampler {
 public:
  // Dimensions served from the padded Sobol' pairs (kMaxDimensions / 2 calls of next_1d
  // or next_2d per sample).
  static constexpr int kMaxDimensions = 64;
  // `seed` scrambles the whole sequence (e.g. hash of pixel and user seed).
  explicit SobolSampler(uint64_t seed = 0);
  // Starts sample `index` of the sequence; dimensions restart at 0.
  void start_sample(uint32_t index);
  // A 1-D value in [0, 1) from the next pair of dimensions. Past kMaxDimensions it falls
  // back to a hashed random number (still deterministic).
  float next_1d();
  // A 2-D point in [0, 1)^2 from the next pair of dimensions (same fallback).
  vec2 next_2d();

  // Raw scrambled Sobol' value of `index` in dimension `dim` with scramble seed `seed`:
  // component dim % 2 of pair dim / 2, with that pair's index shuffle and scramble.
  static float sample(uint32_t index, int dim, uint32_t seed);

 private:
  struct PairSeeds {
    uint32_t shuffle;
    uint32_t component[2];
  };
  const PairSeeds& pair_seeds(int pair);

  uint64_t seed_;
  uint32_t seed32_;
  uint32_t index_ = 0, reversed_index_ = 0;
  int dim_ = 0;
  // Seeds of each pair, hashed on first use (bit p of seeds_ready_ set once pair p's are).
  uint32_t seeds_ready_ = 0;
  static_assert(kMaxDimensions / 2 <= 32, "seeds_ready_ has one bit a pair");
  std::array<PairSeeds, kMaxDimensions / 2> pair_seeds_;
};

}  // namespace illum
