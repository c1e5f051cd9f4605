// Vector quantization of SH transfer vectors (ALGORITHMS.md item 16, S002 §5.6): Lloyd
// clustering ("iterated closest points") of the vectors into at most 2¹⁶ representatives, so
// an SHL-map stores a 16-bit index per texel plus the table. Termination is the seed's: after
// each assignment the largest distance of a vector to its nearest representative is taken
// as the error; the loop stops once `patience` (3) iterations in a row bring no new minimum
// of it, and returns the best state seen (representatives with their assignment).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "illum/baked/prt_file.h"

namespace illum::bake {

// The codebook is the PRT folder's (baked/prt_file.h).
using baked::kMaxVqRepresentatives;
using baked::VqCodebook;

struct VqOptions {
  int representatives = 4096;  // 1..2¹⁶; fewer when there are fewer vectors
  int patience = 3;
  int max_iterations = 200;  // a guard; the seed's rule stops far earlier in practice
  uint64_t seed = 0;         // which vectors start as representatives
};

// `vectors` holds n × dimension floats. Throws Error for representatives outside 1..2¹⁶, a
// dimension < 1, or a size not a multiple of the dimension. Deterministic for a seed, whatever
// the thread count. Polls Ctrl-C (throws Interrupted).
VqCodebook vq_compress(std::span<const float> vectors, int dimension, const VqOptions& options);

}  // namespace illum::bake
