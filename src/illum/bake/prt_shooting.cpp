#include "illum/bake/prt_shooting.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"

namespace illum::bake {

namespace {

// Shooters are traced in batches so the receipts held at once stay bounded
// (batch × rays entries), whatever the patch count.
constexpr size_t kShooterBatch = 4096;
// A round shoots every patch whose unshot size is at least this share of the largest.
constexpr double kShooterShare = 0.25;

struct Hop {
  int32_t patch;
  float factor;  // weight × A_j / rays, divided by A_k when applied
};

double unshot_size(std::span<const float> u, float area) {
  double sum = 0.0;
  for (float v : u) sum += std::abs(double(v));
  return sum * double(area);
}

}  // namespace

TransferShootingResult shoot_transfer(const RayTracer& tracer,
                                      std::span<const TransferPatch> patches,
                                      const TransferReceiver& receiver, int payload,
                                      std::vector<float>& transfer,
                                      const TransferShootingOptions& options) {
  const size_t n = patches.size(), p = static_cast<size_t>(payload);
  ILLUM_CHECK(payload > 0 && payload % 3 == 0 && transfer.size() == n * p && options.rays > 0);
  TransferShootingResult result;
  // U = albedo ∘ T: what each patch reflects of the light it received and has not shot.
  std::vector<float> unshot(transfer.size());
  std::vector<double> size(n);
  double initial = 0.0;
  for (size_t k = 0; k < n; ++k) {
    for (size_t i = 0; i < p; ++i)
      unshot[k * p + i] = patches[k].albedo[int(i % 3)] * transfer[k * p + i];
    size[k] = unshot_size({&unshot[k * p], p}, patches[k].area);
    initial += size[k];
  }
  if (!(initial > 0.0)) return result;

  std::vector<float> shot;
  while (true) {
    double total = 0.0, largest = 0.0;
    for (double s : size) {
      total += s;
      largest = std::max(largest, s);
    }
    result.unshot_fraction = total / initial;
    if (result.unshot_fraction <= options.tolerance || result.rounds >= options.max_rounds) break;
    std::vector<uint32_t> shooters;
    for (size_t k = 0; k < n; ++k)
      if (size[k] > 0.0 && size[k] >= kShooterShare * largest) shooters.push_back(uint32_t(k));
    const uint64_t round = uint64_t(result.rounds);

    for (size_t b0 = 0; b0 < shooters.size(); b0 += kShooterBatch) {
      const size_t batch = std::min(kShooterBatch, shooters.size() - b0);
      std::vector<std::vector<Hop>> hops(batch);
      std::vector<int64_t> traced(batch, 0);
      parallel_for(
          int64_t(batch),
          [&](int64_t begin, int64_t end) {
            for (int64_t s = begin; s < end; ++s) {
              if (interrupt_requested()) return;
              const uint32_t j = shooters[b0 + size_t(s)];
              const TransferPatch& from = patches[j];
              const Frame frame = Frame::from_normal(from.normal);
              SobolSampler sampler(hash_mix(options.seed, j, round));
              const float share = from.area / float(options.rays);
              auto& out = hops[size_t(s)];
              for (int r = 0; r < options.rays; ++r) {
                sampler.start_sample(uint32_t(r));
                const vec3 dir = frame.to_world(sample_cosine_hemisphere(sampler.next_2d()));
                if (glm::dot(dir, from.geometric_normal) <= 0.0f) continue;  // into its own surface
                const Ray ray{offset_ray_origin(from.position, from.geometric_normal, dir), dir,
                              0.0f, kInf};
                Hit hit;
                ++traced[size_t(s)];
                if (!tracer.intersect(ray, &hit)) continue;
                const TransferReceipt receipt = receiver(ray, hit);
                for (int c = 0; c < receipt.count; ++c)
                  if (receipt.patch[c] >= 0 && receipt.weight[c] > 0.0f)
                    out.push_back({receipt.patch[c], receipt.weight[c] * share});
              }
            }
          },
          8);
      if (interrupt_requested()) throw Interrupted{};
      // Every shooter of the batch gives up its unshot transfer before any receipt lands,
      // so light it receives in this batch stays unshot for the next round.
      shot.assign(batch * p, 0.0f);
      for (size_t s = 0; s < batch; ++s) {
        const size_t j = shooters[b0 + s];
        std::copy_n(&unshot[j * p], p, &shot[s * p]);
        std::fill_n(&unshot[j * p], p, 0.0f);
        result.rays += traced[s];
      }
      for (size_t s = 0; s < batch; ++s) {
        const float* u = &shot[s * p];
        for (const Hop& hop : hops[s]) {
          const TransferPatch& to = patches[size_t(hop.patch)];
          if (!(to.area > 0.0f)) continue;
          const float f = hop.factor / to.area;
          float* t = &transfer[size_t(hop.patch) * p];
          float* v = &unshot[size_t(hop.patch) * p];
          for (size_t i = 0; i < p; ++i) {
            const float d = f * u[i];
            t[i] += d;
            v[i] += to.albedo[int(i % 3)] * d;
          }
        }
      }
    }
    for (size_t k = 0; k < n; ++k) size[k] = unshot_size({&unshot[k * p], p}, patches[k].area);
    ++result.rounds;
  }
  return result;
}

}  // namespace illum::bake
