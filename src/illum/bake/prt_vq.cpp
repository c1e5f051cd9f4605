#include "illum/bake/prt_vq.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"

namespace illum::bake {

namespace {

// Nearest representative of every vector (ties: the lower index), and its squared distance.
void assign(std::span<const float> vectors, size_t dim, const std::vector<float>& reps,
            std::vector<uint16_t>& index, std::vector<double>& distance2) {
  const size_t n = index.size(), k = reps.size() / dim;
  parallel_for(
      int64_t(n),
      [&](int64_t begin, int64_t end) {
        for (int64_t v = begin; v < end; ++v) {
          if (interrupt_requested()) return;
          const float* x = &vectors[size_t(v) * dim];
          double best = std::numeric_limits<double>::infinity();
          size_t best_r = 0;
          for (size_t r = 0; r < k; ++r) {
            const float* c = &reps[r * dim];
            double d = 0.0;
            for (size_t i = 0; i < dim && d < best; ++i) {
              const double e = double(x[i]) - double(c[i]);
              d += e * e;
            }
            if (d < best) {
              best = d;
              best_r = r;
            }
          }
          index[size_t(v)] = uint16_t(best_r);
          distance2[size_t(v)] = best;
        }
      },
      64);
  if (interrupt_requested()) throw Interrupted{};
}

}  // namespace

VqCodebook vq_compress(std::span<const float> vectors, int dimension, const VqOptions& options) {
  if (options.representatives < 1 || options.representatives > kMaxVqRepresentatives)
    throw Error(fmt::format("VQ: {} representatives is outside 1..{}", options.representatives,
                            kMaxVqRepresentatives));
  if (dimension < 1 || vectors.size() % size_t(dimension) != 0)
    throw Error(fmt::format("VQ: {} values are not whole vectors of dimension {}", vectors.size(),
                            dimension));
  if (options.patience < 1 || options.max_iterations < 1)
    throw Error("VQ: patience and max_iterations must be ≥ 1");
  const size_t dim = size_t(dimension), n = vectors.size() / dim;
  VqCodebook book;
  book.dimension = dimension;
  if (n == 0) return book;
  const size_t k = std::min(size_t(options.representatives), n);

  // Start: k distinct vectors picked by a seeded partial shuffle (S002: "a subset of O").
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  Rng rng(options.seed);
  for (size_t i = 0; i < k; ++i) std::swap(order[i], order[i + rng.next_bounded(uint32_t(n - i))]);
  std::sort(order.begin(), order.begin() + std::ptrdiff_t(k));
  std::vector<float> reps(k * dim);
  for (size_t r = 0; r < k; ++r) std::copy_n(&vectors[size_t(order[r]) * dim], dim, &reps[r * dim]);

  std::vector<uint16_t> index(n);
  std::vector<double> distance2(n);
  double best_max = std::numeric_limits<double>::infinity();
  int without_progress = 0;
  std::vector<double> sum(k * dim);
  std::vector<size_t> members(k);
  for (int it = 1; it <= options.max_iterations; ++it) {
    assign(vectors, dim, reps, index, distance2);
    book.iterations = it;
    const double max2 = *std::max_element(distance2.begin(), distance2.end());
    if (max2 < best_max) {
      best_max = max2;
      without_progress = 0;
      book.representatives = reps;
      book.indices = index;
      double total = 0.0;
      for (double d : distance2) total += d;
      book.max_distance = std::sqrt(max2);
      book.rms_distance = std::sqrt(total / double(n));
    } else if (++without_progress >= options.patience) {
      break;
    }
    if (max2 == 0.0) break;  // exact: nothing left to improve
    // New representatives: the centres of their clusters (an empty cluster keeps its own).
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(members.begin(), members.end(), 0);
    for (size_t v = 0; v < n; ++v) {
      const size_t r = index[v];
      ++members[r];
      for (size_t i = 0; i < dim; ++i) sum[r * dim + i] += double(vectors[v * dim + i]);
    }
    for (size_t r = 0; r < k; ++r)
      if (members[r])
        for (size_t i = 0; i < dim; ++i)
          reps[r * dim + i] = float(sum[r * dim + i] / double(members[r]));
  }
  return book;
}

}  // namespace illum::bake
