// Seeded pseudo-random numbers: PCG32 (O'Neill 2014). Small state, statistically solid,
// and splittable by stream id so each pixel/tile/photon gets an independent sequence that
// does not depend on thread scheduling.
#pragma once

#include <cstdint>

namespace illum {

class Rng {
 public:
  explicit Rng(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL);
  uint32_t next_u32();
  // Uniform float in [0, 1), never 1.0.
  float next_float();
  // Uniform integer in [0, bound).
  uint32_t next_bounded(uint32_t bound);
  void advance(int64_t delta);

 private:
  uint64_t state_, inc_;
};

// A 64-bit mix (splitmix64 finaliser) for deriving seeds from several integers.
uint64_t hash_mix(uint64_t a, uint64_t b = 0, uint64_t c = 0);

// hash_mix(a, b, c) in two steps, hash_mix_last(hash_mix_prefix(a, b), c), for callers that
// hash several c with the same (a, b) (the sampler's per-pair seeds): the prefix is folded
// once. hash_mix itself is defined through these two, so they cannot drift apart.
namespace rng_detail {
inline uint64_t splitmix_finalise(uint64_t z) {
  z = (z ^ (z >> 30u)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27u)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31u);
}
}  // namespace rng_detail
inline uint64_t hash_mix_prefix(uint64_t a, uint64_t b) {
  const uint64_t h = rng_detail::splitmix_finalise(a + 0x9e3779b97f4a7c15ULL);
  return rng_detail::splitmix_finalise(h ^ (b + 0x3c6ef372fe94f82aULL));
}
inline uint64_t hash_mix_last(uint64_t prefix, uint64_t c) {
  return rng_detail::splitmix_finalise(prefix ^ (c + 0xdaa66d2c7ddf743fULL));
}

// The top 24 bits of `bits` as a float in [0, 1): exact, evenly spaced, and at most
// 1 − 2⁻²⁴, so rounding can never produce 1.0.
inline float u32_to_unit_float(uint32_t bits) {
  return static_cast<float>(bits >> 8u) * 0x1p-24f;
}

}  // namespace illum
