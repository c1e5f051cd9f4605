#include "illum/core/sampler.h"

#include "illum/core/error.h"
#include "illum/core/rng.h"
#include "illum/core/sobol_dimension1.h"

namespace illum {

namespace {

uint32_t reverse_bits(uint32_t v) {
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
uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x *= (seed >> 16u) | 1u;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

uint32_t seed_for(uint32_t seed, uint32_t pair, uint32_t purpose) {
  return static_cast<uint32_t>(hash_mix(seed, pair, purpose) >> 32u);
}

// Purposes of the per-pair seeds (component scrambles use 0 and 1).
constexpr uint32_t kShuffle = 2;

// Each step below is the nested scramble reverse → Laine–Karras → reverse; written out so
// that reversals which cancel are skipped. With `reversed_index` = reverse_bits(index):
//   shuffled index  j = reverse(LK(reversed_index, shuffle seed))
//   component 0: the van der Corput point of j is reverse(j), so its scramble is
//                reverse(LK(j, seed 0));
//   component 1: dimension 1 of j in reversed form is the superset transform of j, so its
//                scramble is reverse(LK(superset(j), seed 1)).
uint32_t shuffled_index(uint32_t reversed_index, uint32_t shuffle_seed) {
  return reverse_bits(laine_karras_permutation(reversed_index, shuffle_seed));
}
float component0(uint32_t shuffled, uint32_t seed0) {
  return u32_to_unit_float(reverse_bits(laine_karras_permutation(shuffled, seed0)));
}
float component1(uint32_t shuffled, uint32_t seed1) {
  return u32_to_unit_float(
      reverse_bits(laine_karras_permutation(sobol_dimension1_reversed(shuffled), seed1)));
}

}  // namespace

float SobolSampler::sample(uint32_t index, int dim, uint32_t seed) {
  ILLUM_CHECK(dim >= 0, "negative sampler dimension {}", dim);
  const auto pair = static_cast<uint32_t>(dim) / 2u;
  const auto component = static_cast<uint32_t>(dim) % 2u;
  const uint32_t j = shuffled_index(reverse_bits(index), seed_for(seed, pair, kShuffle));
  const uint32_t component_seed = seed_for(seed, pair, component);
  return component == 0 ? component0(j, component_seed) : component1(j, component_seed);
}

const SobolSampler::PairSeeds& SobolSampler::pair_seeds(int pair) {
  // The per-pair seeds depend on the pixel seed and the pair only, so they are hashed once
  // per sampler (i.e. per pixel and pass) instead of once per sample.
  PairSeeds& seeds = pair_seeds_[static_cast<size_t>(pair)];
  const uint32_t bit = 1u << static_cast<uint32_t>(pair);
  if (!(seeds_ready_ & bit)) {
    const auto p = static_cast<uint32_t>(pair);
    seeds = {seed_for(seed32_, p, kShuffle), {seed_for(seed32_, p, 0), seed_for(seed32_, p, 1)}};
    seeds_ready_ |= bit;
  }
  return seeds;
}

SobolSampler::SobolSampler(uint64_t seed)
    : seed_(seed), seed32_(static_cast<uint32_t>(hash_mix(seed) >> 32u)) {}

void SobolSampler::start_sample(uint32_t index) {
  index_ = index;
  reversed_index_ = reverse_bits(index);
  dim_ = 0;
}

float SobolSampler::next_1d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim < kMaxDimensions) {
    const PairSeeds& seeds = pair_seeds(dim / 2);
    return component0(shuffled_index(reversed_index_, seeds.shuffle), seeds.component[0]);
  }
  return u32_to_unit_float(
      static_cast<uint32_t>(hash_mix(seed_, index_, static_cast<uint64_t>(dim)) >> 32u));
}

vec2 SobolSampler::next_2d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim < kMaxDimensions) {
    const PairSeeds& seeds = pair_seeds(dim / 2);
    const uint32_t j = shuffled_index(reversed_index_, seeds.shuffle);
    return {component0(j, seeds.component[0]), component1(j, seeds.component[1])};
  }
  const uint64_t h = hash_mix(seed_, index_, static_cast<uint64_t>(dim));
  return {u32_to_unit_float(static_cast<uint32_t>(h >> 32u)),
          u32_to_unit_float(static_cast<uint32_t>(h))};
}

}  // namespace illum
