#include "illum/core/rng.h"

#include "illum/core/error.h"

namespace illum {

namespace {
constexpr uint64_t kPcgMultiplier = 6364136223846793005ULL;
}  // namespace

Rng::Rng(uint64_t seed, uint64_t stream) : state_(0), inc_((stream << 1u) | 1u) {
  // O'Neill's seeding: step once so the seed is mixed through the multiplier before use.
  next_u32();
  state_ += seed;
  next_u32();
}

uint32_t Rng::next_u32() {
  const uint64_t old = state_;
  state_ = old * kPcgMultiplier + inc_;
  // XSH RR output: xorshift the high bits down, then rotate by the top five bits.
  const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
  const auto rot = static_cast<uint32_t>(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

float Rng::next_float() {
  return u32_to_unit_float(next_u32());
}

uint32_t Rng::next_bounded(uint32_t bound) {
  ILLUM_CHECK(bound > 0, "next_bounded needs a positive bound");
  // Rejection of the low values that would make some residues more likely: the
  // threshold is 2^32 mod bound, so the accepted range is a multiple of bound.
  const uint32_t threshold = (0u - bound) % bound;
  for (;;) {
    const uint32_t r = next_u32();
    if (r >= threshold) return r % bound;
  }
}

void Rng::advance(int64_t delta) {
  // Jump ahead in O(log n): compose the affine map s -> m*s + c with itself by
  // repeated squaring (Brown, "Random number generation with arbitrary strides", 1994).
  // A negative delta wraps to a jump of 2^64 - |delta|, the period, i.e. a step back.
  auto steps = static_cast<uint64_t>(delta);
  uint64_t cur_mult = kPcgMultiplier, cur_plus = inc_;
  uint64_t acc_mult = 1, acc_plus = 0;
  while (steps > 0) {
    if (steps & 1u) {
      acc_mult *= cur_mult;
      acc_plus = acc_plus * cur_mult + cur_plus;
    }
    cur_plus = (cur_mult + 1) * cur_plus;
    cur_mult *= cur_mult;
    steps >>= 1u;
  }
  state_ = acc_mult * state_ + acc_plus;
}

uint64_t hash_mix(uint64_t a, uint64_t b, uint64_t c) {
  // splitmix64's finaliser applied after folding in each word, so (a, b, c) and
  // permutations of it give unrelated outputs.
  return hash_mix_last(hash_mix_prefix(a, b), c);
}

}  // namespace illum
