// Sobol' dimension 1 evaluated with bit operations, for the sampler (sampler.cpp) and its
// test (tests/core/sampler_test.cpp checks it against the generator matrix column by column).
#pragma once

#include <cstdint>

namespace illum {

// Sobol' dimension 1 (primitive polynomial x + 1) in bit-reversed form. Its direction
// numbers satisfy v_k = v_{k-1} xor (v_{k-1} >> 1), v_0 = 2^31, so column k of the generator
// matrix holds binomial(k, i) mod 2 at digit i (bit 31 − i): Pascal's triangle mod 2, which
// by Lucas' theorem is 1 exactly when the bits of i are a subset of those of k. Digit i of
// the point is therefore the xor of the index bits k ⊇ i — a superset-sum (Möbius)
// transform over the 5-bit bit positions, five shift/mask/xor steps instead of a loop over
// up to 32 index bits (the loop was the sampler's largest cost). The result has digit i at
// bit i, i.e. it is the bit reversal of the fixed-point value.
inline uint32_t sobol_dimension1_reversed(uint32_t index) {
  index ^= (index >> 1u) & 0x55555555u;
  index ^= (index >> 2u) & 0x33333333u;
  index ^= (index >> 4u) & 0x0f0f0f0fu;
  index ^= (index >> 8u) & 0x00ff00ffu;
  index ^= (index >> 16u) & 0x0000ffffu;
  return index;
}

}  // namespace illum
