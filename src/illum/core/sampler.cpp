#include "illum/core/sampler.h"

#include "illum/core/error.h"

namespace illum {

namespace {

// Purposes of the per-pair seeds (component scrambles use 0 and 1).
constexpr uint32_t kShuffle = 2;

uint32_t seed_for(uint32_t seed, uint32_t pair, uint32_t purpose) {
  return static_cast<uint32_t>(hash_mix(seed, pair, purpose) >> 32u);
}

}  // namespace

float SobolSampler::sample(uint32_t index, int dim, uint32_t seed) {
  ILLUM_CHECK(dim >= 0, "negative sampler dimension {}", dim);
  const auto pair = static_cast<uint32_t>(dim) / 2u;
  const auto component = static_cast<uint32_t>(dim) % 2u;
  const uint32_t j = sobol_detail::shuffled_index(sobol_detail::reverse_bits(index),
                                                  seed_for(seed, pair, kShuffle));
  const uint32_t component_seed = seed_for(seed, pair, component);
  return component == 0 ? sobol_detail::component0(j, component_seed)
                        : sobol_detail::component1(j, component_seed);
}

void SobolSampler::hash_pair_seeds(int pair) {
  // The three seeds are seed_for(seed32_, pair, purpose); hash_mix's first two folds are the
  // same for all three, so they are done once.
  const uint64_t prefix = hash_mix_prefix(seed32_, static_cast<uint32_t>(pair));
  auto seed = [&](uint32_t purpose) {
    return static_cast<uint32_t>(hash_mix_last(prefix, purpose) >> 32u);
  };
  pair_seeds_[static_cast<size_t>(pair)] = {seed(kShuffle), {seed(0), seed(1)}};
  seeds_ready_ |= 1u << static_cast<uint32_t>(pair);
}

SobolSampler::SobolSampler(uint64_t seed)
    : seed_(seed), seed32_(static_cast<uint32_t>(hash_mix(seed) >> 32u)) {}

float SobolSampler::fallback_1d(int dim) const {
  return u32_to_unit_float(
      static_cast<uint32_t>(hash_mix(seed_, index_, static_cast<uint64_t>(dim)) >> 32u));
}

vec2 SobolSampler::fallback_2d(int dim) const {
  const uint64_t h = hash_mix(seed_, index_, static_cast<uint64_t>(dim));
  return {u32_to_unit_float(static_cast<uint32_t>(h >> 32u)),
          u32_to_unit_float(static_cast<uint32_t>(h))};
}

}  // namespace illum
