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
#include "illum/core/rng.h"
#include "illum/core/sobol_dimension1.h"

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
  // Moves past the pair the next next_1d() or next_2d() would use without computing it, for
  // a value the caller would not use: the dimensions after it stay the same as if it had
  // been drawn, so paths that skip and paths that draw still line up.
  void skip() { dim_ += 2; }

  // Raw scrambled Sobol' value of `index` in dimension `dim` with scramble seed `seed`:
  // component dim % 2 of pair dim / 2, with that pair's index shuffle and scramble.
  static float sample(uint32_t index, int dim, uint32_t seed);

 private:
  struct PairSeeds {
    uint32_t shuffle;
    uint32_t component[2];
  };
  const PairSeeds& pair_seeds(int pair);
  void hash_pair_seeds(int pair);
  float fallback_1d(int dim) const;
  vec2 fallback_2d(int dim) const;

  uint64_t seed_;
  uint32_t seed32_;
  uint32_t index_ = 0, reversed_index_ = 0;
  int dim_ = 0;
  // Seeds of each pair, hashed on first use (bit p of seeds_ready_ set once pair p's are).
  uint32_t seeds_ready_ = 0;
  static_assert(kMaxDimensions / 2 <= 32, "seeds_ready_ has one bit a pair");
  std::array<PairSeeds, kMaxDimensions / 2> pair_seeds_;
};

// The scrambling steps, inline because next_1d() and next_2d() run several times per path
// vertex (out of line they were 15 % of the path tracer's time on the Cornell box).
namespace sobol_detail {

inline uint32_t reverse_bits(uint32_t v) {
  v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
  v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
  v = ((v >> 4u) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4u);
  v = ((v >> 8u) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8u);
  return (v >> 16u) | (v << 16u);
}

// Laine–Karras-style permutation: every step (adding the seed, multiplying by an odd
// number, xor with the value times an even number) changes bit i only as a function of
// bits 0..i, so applied to bit-reversed values it flips each digit according to the
// digits above it — a nested uniform (Owen) scramble with hashed flip decisions.
// Constants: Burley 2020 (the JCGT paper's listing), with an extra seed-dependent odd
// multiply so different seeds are not just shifted versions of each other.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x *= (seed >> 16u) | 1u;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Each step below is the nested scramble reverse → Laine–Karras → reverse; written out so
// that reversals which cancel are skipped. With `reversed_index` = reverse_bits(index):
//   shuffled index  j = reverse(LK(reversed_index, shuffle seed))
//   component 0: the van der Corput point of j is reverse(j), so its scramble is
//                reverse(LK(j, seed 0));
//   component 1: dimension 1 of j in reversed form is the superset transform of j, so its
//                scramble is reverse(LK(superset(j), seed 1)).
inline uint32_t shuffled_index(uint32_t reversed_index, uint32_t shuffle_seed) {
  return reverse_bits(laine_karras_permutation(reversed_index, shuffle_seed));
}
inline float component0(uint32_t shuffled, uint32_t seed0) {
  return u32_to_unit_float(reverse_bits(laine_karras_permutation(shuffled, seed0)));
}
inline float component1(uint32_t shuffled, uint32_t seed1) {
  return u32_to_unit_float(
      reverse_bits(laine_karras_permutation(sobol_dimension1_reversed(shuffled), seed1)));
}

}  // namespace sobol_detail

inline const SobolSampler::PairSeeds& SobolSampler::pair_seeds(int pair) {
  // The per-pair seeds depend on the pixel seed and the pair only, so they are hashed once
  // per sampler (i.e. per pixel and pass) instead of once per sample.
  if (!(seeds_ready_ & (1u << static_cast<uint32_t>(pair)))) hash_pair_seeds(pair);
  return pair_seeds_[static_cast<size_t>(pair)];
}

inline void SobolSampler::start_sample(uint32_t index) {
  index_ = index;
  reversed_index_ = sobol_detail::reverse_bits(index);
  dim_ = 0;
}

inline float SobolSampler::next_1d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim >= kMaxDimensions) return fallback_1d(dim);
  const PairSeeds& seeds = pair_seeds(dim / 2);
  return sobol_detail::component0(sobol_detail::shuffled_index(reversed_index_, seeds.shuffle),
                                  seeds.component[0]);
}

inline vec2 SobolSampler::next_2d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim >= kMaxDimensions) return fallback_2d(dim);
  const PairSeeds& seeds = pair_seeds(dim / 2);
  const uint32_t j = sobol_detail::shuffled_index(reversed_index_, seeds.shuffle);
  return {sobol_detail::component0(j, seeds.component[0]),
          sobol_detail::component1(j, seeds.component[1])};
}

}  // namespace illum
