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

namespace shooting_detail {

// The state of one run of shoot_progressively, its steps as member functions: choose a
// shooter, gather its group into a source, compute the receivers' form factors, scale them
// to conserve power, hand the power out.
template <class Payload, class Transport>
class Shooter {
 public:
  static constexpr int kTotalRuleHeld = -1;  // no shooter: the total rule holds from now on
  static constexpr int kNothingUnshot = -2;  // no shooter: nothing is left unshot anywhere

  Shooter(const ShootingPatches& set, std::vector<Payload>& total, std::vector<Payload>& unshot,
          const Transport& transport, const ShootingOptions& options)
      : set_(set),
        patches_(set.patches),
        n_(static_cast<int64_t>(set.patches.size())),
        total_(total),
        unshot_(unshot),
        transport_(transport),
        options_(options),
        chunks_((n_ + kChunk - 1) / kChunk),
        chunk_sum_(static_cast<size_t>(chunks_)) {
    by_surface_.resize(static_cast<size_t>(std::max(set.surface_count, 0)));
    for (int64_t i = 0; i < n_; ++i) {
      const int s = patches_[size_t(i)].surface;
      ILLUM_CHECK(s >= 0 && s < set.surface_count, "shooting: patch {} has surface {} of {}", i, s,
                  set.surface_count);
      by_surface_[size_t(s)].push_back(int(i));
    }
    stats.initial_power = sum_chunks([&](int64_t i) { return power_of(i); });
    // Per patch: Σ magnitude of what it was given to shoot (initial unshot, then reflections).
    emitted_.resize(static_cast<size_t>(n_));
    for (int64_t i = 0; i < n_; ++i) emitted_[size_t(i)] = transport_.magnitude(unshot_[size_t(i)]);
    remaining_ = stats.initial_power;
    stop_total_ = options.threshold * stats.initial_power;
    stop_patch_ = stop_total_ / double(n_);
    factor_.resize(static_cast<size_t>(n_));
    std::vector<vec3> positions(static_cast<size_t>(n_));
    for (int64_t i = 0; i < n_; ++i) positions[size_t(i)] = patches_[size_t(i)].position;
    clusters_ = build_receiver_clusters(positions);
    task_rays_.resize(clusters_.tasks.size());
    task_shared_.assign(clusters_.tasks.size(), 0);
    total_rule_held_ = remaining_ <= stop_total_;
  }

  ShootingStats stats;

  // Before a shot: true when the loop ends (converged by both rules, or stopped by
  // max_shots or the time budget); throws Interrupted on Ctrl-C.
  bool stop_before_shot(std::chrono::steady_clock::time_point t0) {
    if (total_rule_held_) {
      stats.relative_unshot = relative_unshot();
      if (stats.relative_unshot <= options_.relative_threshold) {
        stats.converged = true;
        return true;
      }
    }
    if (interrupt_requested()) throw Interrupted{};
    if (options_.max_shots > 0 && stats.shots >= options_.max_shots) return true;
    return options_.time_budget_s > 0.0 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
               options_.time_budget_s;
  }

  // The next shooter, or kTotalRuleHeld / kNothingUnshot.
  int choose_shooter() {
    return total_rule_held_ ? largest_relative_share() : largest_sampled_power();
  }

  // The chosen patch's n×n neighbourhood on its surface as one source; false when the group
  // has nothing to shoot (its claims are then dropped).
  bool gather_source(int best) {
    const ShootingPatch& centre = patches_[size_t(best)];
    members_.clear();
    const int lo = -(options_.group_size - 1) / 2, hi = options_.group_size / 2;
    for (int dy = lo; dy <= hi; ++dy)
      for (int dx = lo; dx <= hi; ++dx) {
        const int gx = centre.x + dx, gy = centre.y + dy;
        if (gx < 0 || gy < 0 || gx >= set_.grid_width || gy >= set_.grid_height) continue;
        const int32_t j = set_.patch_at[size_t(gy) * size_t(set_.grid_width) + size_t(gx)];
        if (j >= 0 && patches_[size_t(j)].surface == centre.surface) members_.push_back(j);
      }
    power_ = Payload{};
    source_ = ShotSource{};
    vec3 normal_sum(0.0f);
    double area = 0.0;
    glm::dvec3 position(0.0);
    member_power_.clear();
    member_weight_.clear();
    weight_sum_ = 0.0;
    for (int j : members_) {
      const ShootingPatch& m = patches_[size_t(j)];
      member_power_.push_back(unshot_[size_t(j)] * m.area);
      member_weight_.push_back(transport_.magnitude(member_power_.back()));
      weight_sum_ += member_weight_.back();
      power_ += member_power_.back();
      position += glm::dvec3(m.position) * double(m.area);
      normal_sum += m.normal * m.area;
      area += m.area;
    }
    for (int j : members_) unshot_[size_t(j)] = Payload{};
    if (!(area > 0.0) || !(weight_sum_ > 0.0)) return false;
    source_.position = vec3(position / area);
    source_.normal = glm::length(normal_sum) > 0.0f ? glm::normalize(normal_sum) : centre.normal;
    source_.area = float(area);
    source_.centre = best;
    source_.members = members_;
    centre_surface_ = centre.surface;
    return true;
  }

  // Form factors with visibility (members never receive their own shot) into factor_.
  // Receivers closer than twice the group's size see the members one by one (the group's
  // single interaction is meant for "widely separated" patches, S002 §3.3.4; near a corner a
  // 3×3 group at its centre misplaces the light by up to its own size): their factor is the
  // members' power-weighted mean.
  void form_factors() {
    // Far receivers: the factor from the group's centre (no ray). Per receiver as without
    // clusters: members get nothing, near ones the members' weighted factors, then a ray.
    auto unoccluded = [&](int32_t i) {
      const ShootingPatch& r = patches_[size_t(i)];
      return shooting_form_factor(source_.position, source_.normal, source_.area, r.position,
                                  r.normal);
    };
    auto per_receiver = [&](int32_t i, int64_t* rays) {
      const ShootingPatch& r = patches_[size_t(i)];
      float k = 0.0f;
      if (r.surface == centre_surface_ &&
          std::find(members_.begin(), members_.end(), int(i)) != members_.end()) {
        k = 0.0f;
      } else if (is_near(r)) {
        double sum = 0.0;
        for (size_t m = 0; m < members_.size(); ++m)
          sum += member_weight_[m] * double(member_factor(m, r));
        k = float(sum / weight_sum_);
      } else {
        k = unoccluded(i);
      }
      if (k > 0.0f) {
        ++*rays;
        if (!transport_.visible(source_, int(i))) k = 0.0f;
      }
      return k;
    };
    auto visible = [&](int32_t i) { return transport_.visible(source_, int(i)); };
    const float near2 = near2_();
    parallel_for(
        int64_t(clusters_.tasks.size()),
        [&](int64_t task0, int64_t task1) {
          for (int64_t t = task0; t < task1; ++t)
            task_rays_[size_t(t)] =
                cluster_factors(clusters_, clusters_.tasks[size_t(t)], source_.position,
                                source_.normal, options_.cluster_ratio, near2, per_receiver,
                                unoccluded, visible, factor_.data(), &task_shared_[size_t(t)]);
        },
        1);
    for (size_t t = 0; t < task_rays_.size(); ++t) {
      stats.visibility_tests += task_rays_[t];
      stats.shared_clusters += task_shared_[t];
      task_shared_[t] = 0;
    }
  }

  // The factors' scale that conserves power (if the transport measures its reach), with its
  // statistics.
  float conservation_scale() {
    const double reach = transport_.reach(source_);
    if (!(reach >= 0.0)) return 1.0f;
    const double landed = sum_chunks(
        [&](int64_t i) { return double(factor_[size_t(i)]) * double(patches_[size_t(i)].area); });
    const float scale = landed > 0.0 ? float(reach / landed) : 0.0f;
    if (landed > 0.0) {
      stats.scale_min = std::min(stats.scale_min, double(scale));
      stats.scale_max = std::max(stats.scale_max, double(scale));
      const double w = transport_.magnitude(power_);
      scale_weighted_ += w * double(scale);
      scale_weight_ += w;
    }
    return scale;
  }

  // Every receiver gets its share, keeps it in total and re-emits what it reflects.
  void deliver(float scale) {
    parallel_for(n_, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const float k = factor_[size_t(i)] * scale;
        if (k <= 0.0f) continue;
        const ShootingPatch& r = patches_[size_t(i)];
        Payload arriving{};
        if (is_near(r)) {
          for (size_t m = 0; m < members_.size(); ++m) {
            const float km = member_factor(m, r);
            if (km > 0.0f) arriving += member_power_[m] * (km * scale);
          }
        } else {
          arriving = power_ * k;
        }
        total_[size_t(i)] += arriving;
        const Payload reflected = transport_.reflect(int(i), arriving);
        unshot_[size_t(i)] += reflected;
        emitted_[size_t(i)] += transport_.magnitude(reflected);
        if constexpr (requires { transport_.received(int(i), source_, arriving); })
          transport_.received(int(i), source_, arriving);
      }
    });
  }

  // After a shot (or a dropped group): the unshot power left, and whether the total rule
  // holds now.
  void end_shot() {
    remaining_ = sum_chunks([&](int64_t i) { return power_of(i); });
    total_rule_held_ = total_rule_held_ || remaining_ <= stop_total_;
    ++stats.shots;
  }

  // Progress on a log scale of the unshot power between its start and the stop value, in
  // thousandths.
  int progress_permille() const {
    const double log_span =
        std::log(std::max(1.0, stats.initial_power / std::max(stop_total_, 1e-300)));
    return remaining_ > 0.0 && log_span > 0.0
               ? int(1000.0 *
                     std::clamp(std::log(stats.initial_power / remaining_) / log_span, 0.0, 1.0))
               : 1000;
  }

  ShootingStats finish(std::chrono::steady_clock::time_point t0) {
    if (scale_weight_ > 0.0) stats.scale_mean = scale_weighted_ / scale_weight_;
    stats.remaining_power = remaining_;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return stats;
  }

 private:
  static constexpr int64_t kChunk = 4096;  // fixed reduction chunks: sums independent of threads

  double power_of(int64_t i) const {
    return transport_.magnitude(unshot_[size_t(i)]) * double(patches_[size_t(i)].area);
  }
  double relative_of(int64_t i) const {
    const double e = emitted_[size_t(i)];
    return e > 0.0 ? std::min(1.0, transport_.magnitude(unshot_[size_t(i)]) / e) : 0.0;
  }
  template <class PerPatch>
  double sum_chunks(PerPatch&& per_patch) {
    parallel_for(
        chunks_,
        [&](int64_t c0, int64_t c1) {
          for (int64_t c = c0; c < c1; ++c) {
            double s = 0.0;
            for (int64_t i = c * kChunk; i < std::min(n_, (c + 1) * kChunk); ++i) s += per_patch(i);
            chunk_sum_[size_t(c)] = s;
          }
        },
        1);
    double s = 0.0;
    for (double v : chunk_sum_) s += v;
    return s;
  }
  double relative_unshot() {
    const double lit_area = sum_chunks([&](int64_t i) {
      return emitted_[size_t(i)] > 0.0 ? double(patches_[size_t(i)].area) : 0.0;
    });
    const double weighted =
        sum_chunks([&](int64_t i) { return relative_of(i) * double(patches_[size_t(i)].area); });
    return lit_area > 0.0 ? weighted / lit_area : 0.0;
  }

  // The largest of samples_per_surface random patches of every surface; a full search only
  // below the per-patch threshold, as CaLight.
  int largest_sampled_power() {
    Rng rng(hash_mix(options_.seed, uint64_t(stats.shots), 0x5400u));
    double best_power = -1.0;
    int best = -1;
    for (const std::vector<int>& surface : by_surface_) {
      if (surface.empty()) continue;
      for (int k = 0; k < options_.samples_per_surface; ++k) {
        const int i = surface[rng.next_bounded(uint32_t(surface.size()))];
        const double p = power_of(i);
        if (p > best_power) best_power = p, best = i;
      }
    }
    if (!(best_power <= stop_patch_)) return best;
    ++stats.full_searches;
    for (int64_t i = 0; i < n_; ++i) {
      const double p = power_of(i);
      if (p > best_power) best_power = p, best = int(i);
    }
    if (!(best_power <= stop_patch_)) return best;
    total_rule_held_ = true;
    return kTotalRuleHeld;
  }

  // The total rule holds but the mean relative unshot does not: the patch adding most to
  // that mean shoots (a full search; the shot itself visits every patch anyway).
  int largest_relative_share() {
    double best_share = 0.0;
    int best = -1;
    for (int64_t i = 0; i < n_; ++i) {
      const double share = relative_of(i) * double(patches_[size_t(i)].area);
      if (share > best_share) best_share = share, best = int(i);
    }
    if (best < 0) return kNothingUnshot;  // the mean is 0
    ++stats.relative_shots;
    return best;
  }

  float near2_() const { return kNearGroupSizes * kNearGroupSizes * source_.area; }
  float member_factor(size_t m, const ShootingPatch& r) const {
    const ShootingPatch& p = patches_[size_t(members_[m])];
    return shooting_form_factor(p.position, p.normal, p.area, r.position, r.normal);
  }
  bool is_near(const ShootingPatch& r) const {
    const vec3 d = r.position - source_.position;
    return members_.size() > 1 && glm::dot(d, d) < near2_();
  }

  const ShootingPatches& set_;
  const std::vector<ShootingPatch>& patches_;
  const int64_t n_;
  std::vector<Payload>& total_;
  std::vector<Payload>& unshot_;
  const Transport& transport_;
  const ShootingOptions& options_;
  const int64_t chunks_;
  std::vector<double> chunk_sum_;
  std::vector<std::vector<int>> by_surface_;
  std::vector<double> emitted_;
  double remaining_ = 0.0, stop_total_ = 0.0, stop_patch_ = 0.0;
  bool total_rule_held_ = false;
  std::vector<float> factor_;
  ReceiverClusters clusters_;
  std::vector<int64_t> task_rays_, task_shared_;
  // The current shot: its group, their powers and weights, the source.
  std::vector<int> members_;
  std::vector<Payload> member_power_;
  std::vector<double> member_weight_;
  double weight_sum_ = 0.0;
  Payload power_{};
  ShotSource source_;
  int centre_surface_ = 0;
  double scale_weighted_ = 0.0, scale_weight_ = 0.0;
};

}  // namespace shooting_detail

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
  ILLUM_CHECK(total.size() == set.patches.size() && unshot.size() == set.patches.size(),
              "shooting: {} patches but {} totals and {} unshot", set.patches.size(), total.size(),
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
  if (set.patches.empty()) {
    ShootingStats stats;
    stats.converged = true;
    return stats;
  }
  using ShooterT = shooting_detail::Shooter<Payload, Transport>;
  ShooterT shooter(set, total, unshot, transport, options);
  Progress progress(options.label, 1000, options.progress);
  int shown = 0;
  while (!shooter.stop_before_shot(t0)) {
    const int best = shooter.choose_shooter();
    if (best == ShooterT::kTotalRuleHeld) continue;
    if (best == ShooterT::kNothingUnshot) {
      shooter.stats.converged = true;
      break;
    }
    if (!shooter.gather_source(best)) {  // nothing to shoot: what the group claims is dropped
      shooter.end_shot();
      continue;
    }
    shooter.form_factors();
    shooter.deliver(shooter.conservation_scale());
    shooter.end_shot();
    const int now = shooter.progress_permille();
    if (now > shown) progress.advance(now - shown), shown = now;
  }
  progress.finish();
  return shooter.finish(t0);
}

}  // namespace illum::bake
