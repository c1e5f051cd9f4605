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

// Folded into a back side's Sobol' scramble, so it never shares its front's sequence.
constexpr uint64_t kBackStream = 0x6261636b0000ull;

struct Hop {
  int32_t patch;
  float factor;  // weight × A_j / rays, divided by A_k when applied
  bool back;     // lands on the patch's back side
};

// A shooter's rays by where they went (TransferShotShares).
struct RayOutcomes {
  int64_t front = 0, back = 0, escaped = 0, lost = 0, below = 0;
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
                                      const TransferShootingOptions& options,
                                      std::span<const float> back_direct) {
  const size_t n = patches.size(), p = static_cast<size_t>(payload);
  ILLUM_CHECK(payload > 0 && payload % 3 == 0 && transfer.size() == n * p && options.rays > 0);
  ILLUM_CHECK(back_direct.empty() || back_direct.size() == n * p);
  TransferShootingResult result;
  // A side: 0 .. n−1 the patches' fronts, n + s the back side in slot s (of patch
  // back_patch[s]). U = albedo ∘ (received, not yet shot), per side.
  std::vector<float> unshot(transfer.size());
  std::vector<double> size(n);
  std::vector<int32_t> back_slot(n, -1);
  std::vector<uint32_t> back_patch;
  std::vector<float> back_unshot;  // [slot][payload]: apart, so growing it never moves `unshot`
  // Per slot: Σ over receipts of Σ|albedo ∘ received| (≥ Σ|albedo ∘ all received|: a bound
  // that keeps a back side to one float; it can only make its ratio below look smaller).
  std::vector<double> back_reflected;
  double initial = 0.0;
  for (size_t k = 0; k < n; ++k) {
    for (size_t i = 0; i < p; ++i)
      unshot[k * p + i] = patches[k].albedo[int(i % 3)] * transfer[k * p + i];
    size[k] = unshot_size({&unshot[k * p], p}, patches[k].area);
    initial += size[k];
  }
  for (size_t k = 0; k < back_direct.size() / p; ++k) {
    const float* d = &back_direct[k * p];
    if (std::all_of(d, d + p, [](float v) { return v == 0.0f; })) continue;
    back_slot[k] = int32_t(back_patch.size());
    back_patch.push_back(uint32_t(k));
    for (size_t i = 0; i < p; ++i) back_unshot.push_back(patches[k].albedo[int(i % 3)] * d[i]);
    back_reflected.push_back(unshot_size({&back_unshot[back_unshot.size() - p], p}, 1.0f));
    size.push_back(unshot_size({&back_unshot[back_unshot.size() - p], p}, patches[k].area));
    initial += size.back();
  }
  if (!(initial > 0.0)) return result;
  const auto patch_of = [&](size_t side) { return side < n ? side : back_patch[side - n]; };
  const auto unshot_of = [&](size_t side) {
    return side < n ? &unshot[side * p] : &back_unshot[(side - n) * p];
  };

  // A side's unshot against all it reflects, min(1, Σ|U| / Σ|albedo ∘ T|), averaged over the
  // sides that hold light, by area (so 1 never stops the loop early or late).
  const auto relative_unshot = [&] {
    double weighted = 0.0, area = 0.0;
    for (size_t k = 0; k < size.size(); ++k) {
      const TransferPatch& patch = patches[patch_of(k)];
      double held = 0.0;
      if (k < n) {
        for (size_t i = 0; i < p; ++i)
          held += std::abs(double(patch.albedo[int(i % 3)]) * double(transfer[k * p + i]));
      } else {
        held = back_reflected[k - n];
      }
      if (!(held > 0.0)) continue;
      weighted += double(patch.area) * std::min(1.0, size[k] / double(patch.area) / held);
      area += double(patch.area);
    }
    return area > 0.0 ? weighted / area : 0.0;
  };

  std::vector<float> shot;
  double shot_power = 0.0;
  while (true) {
    double total = 0.0, largest = 0.0;
    for (double s : size) {
      total += s;
      largest = std::max(largest, s);
    }
    result.unshot_fraction = total / initial;
    result.relative_unshot = relative_unshot();
    if ((result.unshot_fraction <= options.tolerance &&
         result.relative_unshot <= options.relative_tolerance) ||
        result.rounds >= options.max_rounds)
      break;
    std::vector<uint32_t> shooters;
    for (size_t k = 0; k < size.size(); ++k)
      if (size[k] > 0.0 && size[k] >= kShooterShare * largest) shooters.push_back(uint32_t(k));
    const uint64_t round = uint64_t(result.rounds);

    for (size_t b0 = 0; b0 < shooters.size(); b0 += kShooterBatch) {
      const size_t batch = std::min(kShooterBatch, shooters.size() - b0);
      std::vector<std::vector<Hop>> hops(batch);
      std::vector<int64_t> traced(batch, 0);
      std::vector<RayOutcomes> outcomes(batch);
      parallel_for(
          int64_t(batch),
          [&](int64_t begin, int64_t end) {
            for (int64_t s = begin; s < end; ++s) {
              if (interrupt_requested()) return;
              const uint32_t side = shooters[b0 + size_t(s)];
              const bool from_back = side >= n;
              const TransferPatch& from = patches[patch_of(side)];
              const vec3 normal = from_back ? -from.normal : from.normal;
              const vec3 geometric = from_back ? -from.geometric_normal : from.geometric_normal;
              const Frame frame = Frame::from_normal(normal);
              // A front keeps the sequence it had before back sides existed.
              SobolSampler sampler(from_back ? hash_mix(options.seed, side, round ^ kBackStream)
                                             : hash_mix(options.seed, side, round));
              const float share = from.area / float(options.rays);
              auto& out = hops[size_t(s)];
              RayOutcomes& count = outcomes[size_t(s)];
              for (int r = 0; r < options.rays; ++r) {
                sampler.start_sample(uint32_t(r));
                const vec3 dir = frame.to_world(sample_cosine_hemisphere(sampler.next_2d()));
                if (glm::dot(dir, geometric) <= 0.0f) {  // into its own surface
                  ++count.below;
                  continue;
                }
                const Ray ray{offset_ray_origin(from.position, geometric, dir), dir, 0.0f, kInf};
                Hit hit;
                ++traced[size_t(s)];
                if (!tracer.intersect(ray, &hit)) {
                  ++count.escaped;
                  continue;
                }
                const TransferReceipt receipt = receiver(ray, hit);
                bool landed = false;
                for (int c = 0; c < receipt.count; ++c)
                  if (receipt.patch[c] >= 0 && receipt.weight[c] > 0.0f) {
                    out.push_back({receipt.patch[c], receipt.weight[c] * share, receipt.back});
                    landed = true;
                  }
                if (!landed)
                  ++count.lost;
                else
                  ++(receipt.back ? count.back : count.front);
              }
            }
          },
          8);
      if (interrupt_requested()) throw Interrupted{};
      // Every shooter of the batch gives up its unshot transfer before any receipt lands,
      // so light it receives in this batch stays unshot for the next round.
      shot.assign(batch * p, 0.0f);
      for (size_t s = 0; s < batch; ++s) {
        const size_t side = shooters[b0 + s];
        float* u = unshot_of(side);
        std::copy_n(u, p, &shot[s * p]);
        std::fill_n(u, p, 0.0f);
        result.rays += traced[s];
        // The first coefficient's RGB sum × area: the shot power under a constant sky.
        const double power =
            double(patches[patch_of(side)].area) *
            (double(shot[s * p]) + double(shot[s * p + 1]) + double(shot[s * p + 2]));
        const double per_ray = power / double(options.rays);
        const RayOutcomes& c = outcomes[s];
        shot_power += power;
        result.shares.front += per_ray * double(c.front);
        result.shares.back += per_ray * double(c.back);
        result.shares.escaped += per_ray * double(c.escaped);
        result.shares.lost += per_ray * double(c.lost);
        result.shares.below += per_ray * double(c.below);
      }
      for (size_t s = 0; s < batch; ++s) {
        const float* u = &shot[s * p];
        for (const Hop& hop : hops[s]) {
          const TransferPatch& to = patches[size_t(hop.patch)];
          if (!(to.area > 0.0f)) continue;
          const float f = hop.factor / to.area;
          float* v;
          if (hop.back) {
            // The back side's slot, made on its first receipt (in shooter order: the same
            // slots whatever the thread count).
            int32_t& slot = back_slot[size_t(hop.patch)];
            if (slot < 0) {
              slot = int32_t(back_patch.size());
              back_patch.push_back(uint32_t(hop.patch));
              back_unshot.resize(back_unshot.size() + p, 0.0f);
              back_reflected.push_back(0.0);
              size.push_back(0.0);
            }
            v = &back_unshot[size_t(slot) * p];
            double held = 0.0;
            for (size_t i = 0; i < p; ++i) {
              const float d = to.albedo[int(i % 3)] * (f * u[i]);
              v[i] += d;
              held += std::abs(double(d));
            }
            back_reflected[size_t(slot)] += held;
            continue;
          }
          float* t = &transfer[size_t(hop.patch) * p];
          v = &unshot[size_t(hop.patch) * p];
          for (size_t i = 0; i < p; ++i) {
            const float d = f * u[i];
            t[i] += d;
            v[i] += to.albedo[int(i % 3)] * d;
          }
        }
      }
    }
    for (size_t k = 0; k < size.size(); ++k)
      size[k] = unshot_size({unshot_of(k), p}, patches[patch_of(k)].area);
    ++result.rounds;
  }
  result.back_sides = int64_t(back_patch.size());
  if (shot_power > 0.0) {
    TransferShotShares& s = result.shares;
    for (double* v : {&s.front, &s.back, &s.escaped, &s.lost, &s.below}) *v /= shot_power;
  }
  return result;
}

}  // namespace illum::bake
