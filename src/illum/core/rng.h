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

// The top 24 bits of `bits` as a float in [0, 1): exact, evenly spaced, and at most
// 1 − 2⁻²⁴, so rounding can never produce 1.0.
inline float u32_to_unit_float(uint32_t bits) {
  return static_cast<float>(bits >> 8u) * 0x1p-24f;
}

}  // namespace illum
