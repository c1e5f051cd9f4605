// Progressive-refinement shooting (Southwell iteration) over light-map patches, generic over
// what a patch shoots (ALGORITHMS.md item 6, S002 §3.3.4; CaSHL §5.3 shoots SH transfer
// vectors with the same loop). One patch per light-map texel; each patch keeps what has
// arrived at it (`total`) and what it has yet to re-emit (`unshot`, an exitance: power per
// area). A shot takes the chosen patch's n×n neighbourhood on its own surface as one source
// (summed unshot power at the area-weighted mean position), hands every receiver in front of
// it the source's power times a point-to-disk form factor if a visibility test passes, and
// lets the receiver re-emit what it reflects. Receivers near the group (closer than
// kNearGroupSizes × its size) are shot at by the members one by one instead.
//
// Shooter choice, as CaLight: the patch of largest unshot power among `samples_per_surface`
// random patches of every surface; only when that patch is below the per-patch threshold, a
// full search; when that finds none either, the total rule holds. Power is
// magnitude(unshot)·area. Then, while the patches' mean relative unshot is above
// relative_threshold (ShootingOptions), the patch of largest area × relative unshot shoots.
//
// Form factor (received exitance per unit source power, without square roots):
//   k = (n_s·d)(−n_r·d) / (|d|² (π|d|² + A_s)),   d = receiver − source.
// The seed's F ≈ (n_s·d)(−n_r·d)A_r/(π|d|⁴) (item 6) is k·A_r with A_s → 0; it diverges as
// 1/|d|² for adjacent patches (two unit squares sharing an edge at right angles: 0.318 where
// the exact value is 0.200). The A_s term is Wallace et al.'s (1989) disk-source form, which
// gives 0.195 there and the seed's form far away, still without a square root.
//
// Determinism: shooter choice is sequential (seeded PCG32 per shot); receivers are updated
// in parallel, each by its own index only; sums run over fixed chunks in a fixed order. The
// result depends on (patches, payloads, options.seed), never on the thread count.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "illum/bake/shooting_clusters.h"
#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/math.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/rng.h"

namespace illum::bake {

// One patch: a light-map texel's sample point, its front normal (unit) and world area.
// `surface` groups patches into the seed's surfaces (random shooter samples are drawn per
// surface; shooter groups never cross surfaces). (x, y) is the patch's grid cell.
struct ShootingPatch {
  vec3 position{0.0f};
  vec3 normal{0.0f, 0.0f, 1.0f};
  float area = 0.0f;
  int x = 0, y = 0;
  int surface = 0;
};

struct ShootingPatches {
  std::vector<ShootingPatch> patches;
  int grid_width = 0, grid_height = 0;
  std::vector<int32_t> patch_at;  // grid_width·grid_height entries: patch index or −1
  int surface_count = 0;          // surfaces are 0 .. surface_count−1
};

// A shot's source: the group of patches shooting together.
struct ShotSource {
  vec3 position{0.0f};  // area-weighted mean of the members' positions
  vec3 normal{0.0f, 0.0f, 1.0f};
  float area = 0.0f;  // sum of the members' areas
  int centre = 0;     // the chosen patch
  std::span<const int> members;
};

struct ShootingOptions {
  // Stop when the unshot power (Σ magnitude·area) is at most threshold × the initial unshot
  // power. The per-patch threshold of the shooter choice is threshold × initial / patches,
  // so a full search that finds nothing above it implies the total criterion.
  double threshold = 1e-3;
  // ... and when the area-weighted mean over patches of their relative unshot is at most
  // relative_threshold. A patch's relative unshot is min(1, magnitude(unshot) / emitted),
  // emitted being the magnitudes of its initial unshot and of all it has re-emitted since
  // (patches that never held light do not count). The total rule alone is dominated by the
  // brightest region: a closed room 10⁴× dimmer than another holds 10⁻⁴ of the power and is
  // never shot at all (ProgressiveShooting.DimRoomBesideABrightOneConvergesToo). Once the
  // total rule holds, shooters are chosen by area × relative unshot (a full search), so the
  // loop spends its further shots where the mean is. In (0, 1]; 1 turns the rule off.
  double relative_threshold = 0.05;
  int samples_per_surface = 10;  // the seed's [10]
  int group_size = 3;            // the seed's [n = 3]: n×n patches shoot as one
  uint64_t seed = 0;
  int64_t max_shots = 0;       // 0: no limit
  double time_budget_s = 0.0;  // 0: no limit; else stop after the first shot past it
  // Receiver clusters (shooting_clusters.h): a far cluster whose half-diagonal is at most
  // cluster_ratio × its distance from the shooter shares the visibility of its probe rays
  // when they agree. 0: one ray per receiver (the unclustered result).
  float cluster_ratio = 0.0f;
  bool progress = true;
  const char* label = "shooting";
};

struct ShootingStats {
  int64_t shots = 0;
  int64_t visibility_tests = 0;  // rays cast for form factors (probes included)
  int64_t shared_clusters = 0;   // clusters whose receivers shared their probes' visibility
  int64_t full_searches = 0;
  double initial_power = 0.0;
  double remaining_power = 0.0;  // unshot power left (Σ magnitude·area)
  double relative_unshot = 0.0;  // the mean relative unshot above, when the loop stopped
  int64_t relative_shots = 0;    // shots chosen by relative unshot (after the total rule held)
  bool converged = false;        // false: stopped by max_shots or the time budget
  // The conservation scaling's reach / Σ k·A_r per shot (1 without it), its extremes and
  // its mean weighted by the shot's power: how far the form factors' sum was from the
  // hemisphere share that the transport measured.
  double scale_min = 1.0, scale_max = 1.0, scale_mean = 1.0;
  double seconds = 0.0;
};

// Receivers nearer than this many times the square root of a group's area are shot at by
// the group's members one by one.
inline constexpr float kNearGroupSizes = 2.0f;

// Point-to-disk form factor k above (0 when either side faces away).
inline float shooting_form_factor(const vec3& source, const vec3& source_normal, float source_area,
                                  const vec3& receiver, const vec3& receiver_normal) {
  const vec3 d = receiver - source;
  const float cs = glm::dot(source_normal, d);
  const float cr = -glm::dot(receiver_normal, d);
  if (cs <= 0.0f || cr <= 0.0f) return 0.0f;
  const float d2 = glm::dot(d, d);
  return cs * cr / (d2 * (kPi * d2 + source_area));
}

// Transport supplies (all const and safe to call from several threads at once):
//   double magnitude(const Payload&) const            ≥ 0; the shooter choice's measure
//   Payload reflect(int receiver, const Payload& arriving) const   what the receiver re-emits
//   bool visible(const ShotSource&, int receiver) const            ray test source → receiver
//   double reach(const ShotSource&) const
//       share of the source's cosine-weighted hemisphere that lands on patches' front sides;
//       the shot's form factors are scaled so Σ k·A_r equals it (power is conserved: in a
//       closed scene every shot hands out all of its power). Negative: no scaling.
// and optionally
//   void received(int receiver, const ShotSource&, const Payload& arriving) const
//       told of every arrival (after the scaling), e.g. to project it onto directional
//       bases by the source's direction; called in parallel, each receiver by one thread.
// Payload needs Payload{} (zero), +=, and Payload * float.
template <class Payload, class Transport>
ShootingStats shoot_progressively(const ShootingPatches& set, std::vector<Payload>& total,
                                  std::vector<Payload>& unshot, const Transport& transport,
                                  const ShootingOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<ShootingPatch>& patches = set.patches;
  const int64_t n = static_cast<int64_t>(patches.size());
  ILLUM_CHECK(total.size() == patches.size() && unshot.size() == patches.size(),
              "shooting: {} patches but {} totals and {} unshot", patches.size(), total.size(),
              unshot.size());
  if (!(options.threshold >= 0.0) || !std::isfinite(options.threshold))
    throw Error(
        fmt::format("shooting: threshold {} must be a finite number ≥ 0", options.threshold));
  if (!(options.relative_threshold > 0.0 && options.relative_threshold <= 1.0))
    throw Error(fmt::format("shooting: relative_threshold {} must lie in (0, 1]",
                            options.relative_threshold));
  if (options.samples_per_surface < 1 || options.group_size < 1)
    throw Error(fmt::format("shooting: samples_per_surface {} and group_size {} must be ≥ 1",
                            options.samples_per_surface, options.group_size));
  ShootingStats stats;
  if (n == 0) {
    stats.converged = true;
    return stats;
  }

  constexpr int64_t kChunk = 4096;  // fixed reduction chunks: sums independent of threads
  const int64_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> chunk_sum(static_cast<size_t>(chunks));
  auto power_of = [&](int64_t i) {
    return transport.magnitude(unshot[size_t(i)]) * double(patches[size_t(i)].area);
  };
  auto sum_chunks = [&](auto&& per_patch) {
    parallel_for(
        chunks,
        [&](int64_t c0, int64_t c1) {
          for (int64_t c = c0; c < c1; ++c) {
            double s = 0.0;
            for (int64_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) s += per_patch(i);
            chunk_sum[size_t(c)] = s;
          }
        },
        1);
    double s = 0.0;
    for (double v : chunk_sum) s += v;
    return s;
  };

  std::vector<std::vector<int>> by_surface(static_cast<size_t>(std::max(set.surface_count, 0)));
  for (int64_t i = 0; i < n; ++i) {
    const int s = patches[size_t(i)].surface;
    ILLUM_CHECK(s >= 0 && s < set.surface_count, "shooting: patch {} has surface {} of {}", i, s,
                set.surface_count);
    by_surface[size_t(s)].push_back(int(i));
  }

  stats.initial_power = sum_chunks(power_of);
  // Per patch: Σ magnitude of what it was given to shoot (initial unshot, then reflections).
  std::vector<double> emitted(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) emitted[size_t(i)] = transport.magnitude(unshot[size_t(i)]);
  auto relative_of = [&](int64_t i) {
    const double e = emitted[size_t(i)];
    return e > 0.0 ? std::min(1.0, transport.magnitude(unshot[size_t(i)]) / e) : 0.0;
  };
  auto relative_unshot = [&] {
    const double lit_area = sum_chunks([&](int64_t i) {
      return emitted[size_t(i)] > 0.0 ? double(patches[size_t(i)].area) : 0.0;
    });
    const double weighted =
        sum_chunks([&](int64_t i) { return relative_of(i) * double(patches[size_t(i)].area); });
    return lit_area > 0.0 ? weighted / lit_area : 0.0;
  };
  double remaining = stats.initial_power;
  const double stop_total = options.threshold * stats.initial_power;
  const double stop_patch = stop_total / double(n);
  std::vector<float> factor(static_cast<size_t>(n));
  std::vector<vec3> positions(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) positions[size_t(i)] = patches[size_t(i)].position;
  const ReceiverClusters clusters = build_receiver_clusters(positions);
  std::vector<int64_t> task_rays(clusters.tasks.size()), task_shared(clusters.tasks.size(), 0);
  std::vector<int> members;
  std::vector<Payload> member_power;
  double scale_weighted = 0.0, scale_weight = 0.0;
  std::vector<double> member_weight;
  Progress progress(options.label, 1000, options.progress);
  int shown = 0;
  const double log_span =
      std::log(std::max(1.0, stats.initial_power / std::max(stop_total, 1e-300)));

  bool total_rule_held = remaining <= stop_total;
  while (true) {
    if (total_rule_held) {
      stats.relative_unshot = relative_unshot();
      if (stats.relative_unshot <= options.relative_threshold) {
        stats.converged = true;
        break;
      }
    }
    if (interrupt_requested()) throw Interrupted{};
    if (options.max_shots > 0 && stats.shots >= options.max_shots) break;
    if (options.time_budget_s > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
            options.time_budget_s)
      break;

    int best = -1;
    if (!total_rule_held) {
      // Shooter: the largest of samples_per_surface random patches of every surface.
      Rng rng(hash_mix(options.seed, uint64_t(stats.shots), 0x5400u));
      double best_power = -1.0;
      for (const std::vector<int>& surface : by_surface) {
        if (surface.empty()) continue;
        for (int k = 0; k < options.samples_per_surface; ++k) {
          const int i = surface[rng.next_bounded(uint32_t(surface.size()))];
          const double p = power_of(i);
          if (p > best_power) best_power = p, best = i;
        }
      }
      if (best_power <= stop_patch) {  // full search only below the threshold, as CaLight
        ++stats.full_searches;
        for (int64_t i = 0; i < n; ++i) {
          const double p = power_of(i);
          if (p > best_power) best_power = p, best = int(i);
        }
        if (best_power <= stop_patch) {
          total_rule_held = true;
          continue;
        }
      }
    } else {
      // The total rule holds but the mean relative unshot does not: the patch adding most
      // to that mean shoots (a full search; the shot itself visits every patch anyway).
      double best_share = 0.0;
      for (int64_t i = 0; i < n; ++i) {
        const double share = relative_of(i) * double(patches[size_t(i)].area);
        if (share > best_share) best_share = share, best = int(i);
      }
      if (best < 0) {  // nothing unshot anywhere: the mean is 0
        stats.converged = true;
        break;
      }
      ++stats.relative_shots;
    }

    // The chosen patch's n×n neighbourhood on its surface shoots as one source.
    const ShootingPatch& centre = patches[size_t(best)];
    members.clear();
    const int lo = -(options.group_size - 1) / 2, hi = options.group_size / 2;
    for (int dy = lo; dy <= hi; ++dy)
      for (int dx = lo; dx <= hi; ++dx) {
        const int gx = centre.x + dx, gy = centre.y + dy;
        if (gx < 0 || gy < 0 || gx >= set.grid_width || gy >= set.grid_height) continue;
        const int32_t j = set.patch_at[size_t(gy) * size_t(set.grid_width) + size_t(gx)];
        if (j >= 0 && patches[size_t(j)].surface == centre.surface) members.push_back(j);
      }
    Payload power{};
    ShotSource source;
    vec3 normal_sum(0.0f);
    double area = 0.0;
    glm::dvec3 position(0.0);
    member_power.clear();
    member_weight.clear();
    double weight_sum = 0.0;
    for (int j : members) {
      const ShootingPatch& m = patches[size_t(j)];
      member_power.push_back(unshot[size_t(j)] * m.area);
      member_weight.push_back(transport.magnitude(member_power.back()));
      weight_sum += member_weight.back();
      power += member_power.back();
      position += glm::dvec3(m.position) * double(m.area);
      normal_sum += m.normal * m.area;
      area += m.area;
    }
    if (!(area > 0.0) || !(weight_sum > 0.0)) {  // nothing to shoot: drop what they claim
      for (int j : members) unshot[size_t(j)] = Payload{};
      remaining = sum_chunks(power_of);
      total_rule_held = total_rule_held || remaining <= stop_total;
      ++stats.shots;
      continue;
    }
    source.position = vec3(position / area);
    source.normal = glm::length(normal_sum) > 0.0f ? glm::normalize(normal_sum) : centre.normal;
    source.area = float(area);
    source.centre = best;
    source.members = members;
    for (int j : members) unshot[size_t(j)] = Payload{};

    // Form factors with visibility (members never receive their own shot), then (if the
    // transport asks) scaled to conserve power. Receivers closer than twice the group's size
    // see the members one by one (the group's single interaction is meant for "widely
    // separated" patches, S002 §3.3.4; near a corner a 3×3 group at its centre misplaces
    // the light by up to its own size): their factor is the members' power-weighted mean.
    const float near2 = kNearGroupSizes * kNearGroupSizes * source.area;
    auto member_factor = [&](size_t m, const ShootingPatch& r) {
      const ShootingPatch& p = patches[size_t(members[m])];
      return shooting_form_factor(p.position, p.normal, p.area, r.position, r.normal);
    };
    auto is_near = [&](const ShootingPatch& r) {
      const vec3 d = r.position - source.position;
      return members.size() > 1 && glm::dot(d, d) < near2;
    };
    // Far receivers: the factor from the group's centre (no ray). Per receiver as without
    // clusters: members get nothing, near ones the members' weighted factors, then a ray.
    auto unoccluded = [&](int32_t i) {
      const ShootingPatch& r = patches[size_t(i)];
      return shooting_form_factor(source.position, source.normal, source.area, r.position,
                                  r.normal);
    };
    auto per_receiver = [&](int32_t i, int64_t* rays) {
      const ShootingPatch& r = patches[size_t(i)];
      float k = 0.0f;
      if (r.surface == centre.surface &&
          std::find(members.begin(), members.end(), int(i)) != members.end()) {
        k = 0.0f;
      } else if (is_near(r)) {
        double sum = 0.0;
        for (size_t m = 0; m < members.size(); ++m)
          sum += member_weight[m] * double(member_factor(m, r));
        k = float(sum / weight_sum);
      } else {
        k = unoccluded(i);
      }
      if (k > 0.0f) {
        ++*rays;
        if (!transport.visible(source, int(i))) k = 0.0f;
      }
      return k;
    };
    auto visible = [&](int32_t i) { return transport.visible(source, int(i)); };
    parallel_for(
        int64_t(clusters.tasks.size()),
        [&](int64_t task0, int64_t task1) {
          for (int64_t t = task0; t < task1; ++t)
            task_rays[size_t(t)] =
                cluster_factors(clusters, clusters.tasks[size_t(t)], source.position, source.normal,
                                options.cluster_ratio, near2, per_receiver, unoccluded, visible,
                                factor.data(), &task_shared[size_t(t)]);
        },
        1);
    for (size_t t = 0; t < task_rays.size(); ++t) {
      stats.visibility_tests += task_rays[t];
      stats.shared_clusters += task_shared[t];
      task_shared[t] = 0;
    }
    float scale = 1.0f;
    const double reach = transport.reach(source);
    if (reach >= 0.0) {
      const double landed = sum_chunks(
          [&](int64_t i) { return double(factor[size_t(i)]) * double(patches[size_t(i)].area); });
      scale = landed > 0.0 ? float(reach / landed) : 0.0f;
      if (landed > 0.0) {
        stats.scale_min = std::min(stats.scale_min, double(scale));
        stats.scale_max = std::max(stats.scale_max, double(scale));
        const double w = transport.magnitude(power);
        scale_weighted += w * double(scale);
        scale_weight += w;
      }
    }
    parallel_for(n, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const float k = factor[size_t(i)] * scale;
        if (k <= 0.0f) continue;
        const ShootingPatch& r = patches[size_t(i)];
        Payload arriving{};
        if (is_near(r)) {
          for (size_t m = 0; m < members.size(); ++m) {
            const float km = member_factor(m, r);
            if (km > 0.0f) arriving += member_power[m] * (km * scale);
          }
        } else {
          arriving = power * k;
        }
        total[size_t(i)] += arriving;
        const Payload reflected = transport.reflect(int(i), arriving);
        unshot[size_t(i)] += reflected;
        emitted[size_t(i)] += transport.magnitude(reflected);
        if constexpr (requires { transport.received(int(i), source, arriving); })
          transport.received(int(i), source, arriving);
      }
    });
    remaining = sum_chunks(power_of);
    total_rule_held = total_rule_held || remaining <= stop_total;
    ++stats.shots;

    // Progress on a log scale of the unshot power between its start and the stop value.
    const int now =
        remaining > 0.0 && log_span > 0.0
            ? int(1000.0 *
                  std::clamp(std::log(stats.initial_power / remaining) / log_span, 0.0, 1.0))
            : 1000;
    if (now > shown) progress.advance(now - shown), shown = now;
  }
  progress.finish();
  if (scale_weight > 0.0) stats.scale_mean = scale_weighted / scale_weight;
  stats.remaining_power = remaining;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace illum::bake
