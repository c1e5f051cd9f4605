#include "illum/core/sampler.h"

#include <array>

#include "illum/core/error.h"
#include "illum/core/rng.h"

namespace illum {

namespace {

uint32_t reverse_bits(uint32_t v) {
  v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
  v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
  v = ((v >> 4u) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4u);
  v = ((v >> 8u) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8u);
  return (v >> 16u) | (v << 16u);
}

// Columns of the generator matrix of Sobol' dimension 1. For the primitive polynomial
// x + 1 (degree s = 1, no inner coefficients) the direction-number recurrence
// m_k = 2^s m_{k-s} xor m_{k-s} with m_1 = 1 becomes v_k = v_{k-1} xor (v_{k-1} >> 1)
// in 32-bit fixed point.
constexpr std::array<uint32_t, 32> make_dimension1_matrix() {
  std::array<uint32_t, 32> v{};
  v[0] = 1u << 31u;
  for (size_t k = 1; k < v.size(); ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1u);
  return v;
}
constexpr std::array<uint32_t, 32> kDimension1 = make_dimension1_matrix();

uint32_t sobol_dimension1(uint32_t index) {
  uint32_t result = 0;
  for (int k = 0; index != 0; index >>= 1u, ++k)
    if (index & 1u) result ^= kDimension1[static_cast<size_t>(k)];
  return result;
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

uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

uint32_t seed_for(uint32_t seed, uint32_t pair, uint32_t purpose) {
  return static_cast<uint32_t>(hash_mix(seed, pair, purpose) >> 32u);
}

// Purposes of the per-pair seeds (component scrambles use 0 and 1).
constexpr uint32_t kShuffle = 2;

}  // namespace

float SobolSampler::sample(uint32_t index, int dim, uint32_t seed) {
  ILLUM_CHECK(dim >= 0, "negative sampler dimension {}", dim);
  const auto pair = static_cast<uint32_t>(dim) / 2u;
  const auto component = static_cast<uint32_t>(dim) % 2u;
  const uint32_t shuffled = nested_uniform_scramble(index, seed_for(seed, pair, kShuffle));
  const uint32_t sobol = component == 0 ? reverse_bits(shuffled) : sobol_dimension1(shuffled);
  return u32_to_unit_float(nested_uniform_scramble(sobol, seed_for(seed, pair, component)));
}

SobolSampler::SobolSampler(uint64_t seed)
    : seed_(seed), seed32_(static_cast<uint32_t>(hash_mix(seed) >> 32u)) {}

void SobolSampler::start_sample(uint32_t index) {
  index_ = index;
  dim_ = 0;
}

float SobolSampler::next_1d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim < kMaxDimensions) return sample(index_, dim, seed32_);
  return u32_to_unit_float(
      static_cast<uint32_t>(hash_mix(seed_, index_, static_cast<uint64_t>(dim)) >> 32u));
}

vec2 SobolSampler::next_2d() {
  const int dim = dim_;
  dim_ += 2;
  if (dim < kMaxDimensions) return {sample(index_, dim, seed32_), sample(index_, dim + 1, seed32_)};
  const uint64_t h = hash_mix(seed_, index_, static_cast<uint64_t>(dim));
  return {u32_to_unit_float(static_cast<uint32_t>(h >> 32u)),
          u32_to_unit_float(static_cast<uint32_t>(h))};
}

}  // namespace illum
