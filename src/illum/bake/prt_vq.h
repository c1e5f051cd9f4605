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

namespace illum::bake {

inline constexpr int kMaxVqRepresentatives = 1 << 16;

struct VqOptions {
  int representatives = 4096;  // 1..2¹⁶; fewer when there are fewer vectors
  int patience = 3;
  int max_iterations = 200;  // a guard; the seed's rule stops far earlier in practice
  uint64_t seed = 0;         // which vectors start as representatives
};

struct VqCodebook {
  int dimension = 0;
  std::vector<float> representatives;  // count × dimension
  std::vector<uint16_t> indices;       // one per vector: its nearest representative
  int iterations = 0;
  double max_distance = 0.0;  // max over vectors of |v − r(v)| (Euclidean)
  double rms_distance = 0.0;
  int count() const { return dimension ? int(representatives.size() / size_t(dimension)) : 0; }
};

// `vectors` holds n × dimension floats. Throws Error for representatives outside 1..2¹⁶, a
// dimension < 1, or a size not a multiple of the dimension. Deterministic for a seed, whatever
// the thread count. Polls Ctrl-C (throws Interrupted).
VqCodebook vq_compress(std::span<const float> vectors, int dimension, const VqOptions& options);

}  // namespace illum::bake
