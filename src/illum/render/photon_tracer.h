// Photon tracing (Jensen 2001, ch. 5): photons leave the lights (chosen by power, see
// LightSampler::sample_emission), bounce by BSDF sampling in importance mode, and are
// stored on non-delta surfaces. Russian roulette by albedo: after sampling a BSDF
// component with weight w = f·|cos|/pdf (the component's reflectance), the photon survives
// with probability p = min(1, max(w)) and its power is scaled by w/p, so stored power never
// exceeds the emitted power (energy is never created).
//
// Maps:
//   caustic  L S+ D: stored at the first non-delta hit after ≥ 1 delta bounce from the light.
//   global   L (S|D)* D D: stored at every non-delta hit that follows ≥ 1 non-delta bounce.
//            Direct photons (L D) are left out because direct light is computed by
//            next-event estimation, and L S+ D photons because the caustic map holds them.
//   shadow   (optional, Jensen 1995 / S004 "photons with opposite flux") the photon ray is
//            continued through its first hit; direct photons (L D, positive power) are kept
//            and every further non-delta surface on the same line gets a shadow photon with
//            the negated power.
// Determinism: photon i uses Rng(hash(seed, pass), i), and photons are collected in blocks
// of fixed size concatenated in index order, so the maps do not depend on the thread count.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"
#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
#include "illum/render/photon_map.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

// One photon arriving at a non-delta surface.
struct PhotonEvent {
  vec3 p{0.0f};
  vec3 wi{0.0f};  // unit, towards where the photon came from
  vec3 ng{0.0f};
  Color power{0.0f};
  int depth = 0;             // surfaces hit before this one (0: direct from the light)
  int diffuse_bounces = 0;   // non-delta scatterings before this hit
  int specular_bounces = 0;  // delta scatterings before this hit
};

struct PhotonPathSettings {
  int max_depth = 16;  // scatterings per photon path (a safety net; roulette ends most)
  bool shadow_photons = false;
};

// Traces one photon path from `emission`; calls store(event) at each non-delta hit (return
// false to end the path) and shadow(event) for each shadow photon (negated power already).
// Power in the events is emission.flux × roulette weights.
template <typename Store, typename Shadow>
void trace_photon_path(const RayTracer& tracer, const LightEmission& emission, Rng& rng,
                       const PhotonPathSettings& settings, Store&& store, Shadow&& shadow);

struct PhotonMapSettings {
  int64_t global_photons = 200000;   // photons emitted for the global map (0: none)
  int64_t caustic_photons = 200000;  // photons emitted for the caustic map (0: none)
  PhotonPathSettings path;
  uint64_t seed = 0;
};

struct PhotonMaps {
  PhotonMap global, caustic, shadow;
  int64_t global_emitted = 0, caustic_emitted = 0;
  double trace_seconds = 0.0, build_seconds = 0.0;
};

// Emits the photons of each map (power already divided by the number emitted: φ_p = Φ/N)
// and builds the kd-trees.
PhotonMaps build_photon_maps(const RayTracer& tracer, const LightSampler& lights,
                             const PhotonMapSettings& settings);

// Parallel driver: for i in [0, count), emits one photon with Rng(hash(seed, salt), i) and
// calls trace(i, emission, rng, sink) where sink is a per-block std::vector<T>; returns
// all sinks concatenated in block order (deterministic).
template <typename T, typename Trace>
std::vector<T> trace_photons_parallel(const LightSampler& lights, int64_t count, uint64_t seed,
                                      uint64_t salt, Trace&& trace);

// ---------------------------------------------------------------------------------------

template <typename Store, typename Shadow>
void trace_photon_path(const RayTracer& tracer, const LightEmission& emission, Rng& rng,
                       const PhotonPathSettings& settings, Store&& store, Shadow&& shadow) {
  const Scene& scene = tracer.scene();
  Ray ray = emission.ray;
  // Emission rays start exactly on the emitter: lift them off it (for point-like lights
  // the normal is the direction, and the offset is a harmless step along the ray).
  ray.origin = offset_ray_origin(ray.origin, emission.normal, ray.direction);
  Color power = emission.flux;
  int diffuse = 0, specular = 0;
  for (int depth = 0; depth <= settings.max_depth; ++depth) {
    Hit hit;
    if (!tracer.intersect(ray, &hit)) return;
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    const Bsdf bsdf(scene, si);
    const vec3 wo = -ray.direction;
    if (!bsdf.is_delta()) {
      PhotonEvent ev{si.p, wo, si.ng, power, depth, diffuse, specular};
      if (!store(ev)) return;
    }
    if (depth == 0 && settings.shadow_photons) {
      // Continue the light's straight line behind the first surface.
      Ray through{offset_ray_origin(si.p, si.ng, ray.direction), ray.direction};
      for (int k = 0; k < settings.max_depth; ++k) {
        Hit h2;
        if (!tracer.intersect(through, &h2)) break;
        const SurfaceInteraction s2 = tracer.interaction(through, h2);
        if (!Bsdf(scene, s2).is_delta()) shadow(PhotonEvent{s2.p, wo, s2.ng, -power, 1, 0, 0});
        through.origin = offset_ray_origin(s2.p, s2.ng, through.direction);
      }
    }
    if (depth == settings.max_depth) return;
    const float u_lobe = rng.next_float();
    const vec2 u(rng.next_float(), rng.next_float());
    const std::optional<BsdfSample> s = bsdf.sample(wo, u_lobe, u, TransportMode::kImportance);
    if (!s || is_black(s->weight)) return;
    // Russian roulette by the sampled component's reflectance.
    const float p = std::min(1.0f, max_component(s->weight));
    if (rng.next_float() >= p) return;
    power *= s->weight / p;
    if (s->delta) {
      ++specular;
    } else {
      ++diffuse;
    }
    ray = Ray{offset_ray_origin(si.p, si.ng, s->wi), s->wi};
  }
}

template <typename T, typename Trace>
std::vector<T> trace_photons_parallel(const LightSampler& lights, int64_t count, uint64_t seed,
                                      uint64_t salt, Trace&& trace) {
  constexpr int64_t kBlock = 4096;
  const int64_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::vector<T>> sinks(static_cast<size_t>(blocks));
  const uint64_t base = hash_mix(seed, salt);
  parallel_for(
      blocks,
      [&](int64_t b0, int64_t b1) {
        for (int64_t b = b0; b < b1; ++b) {
          if (interrupt_requested()) return;  // Ctrl-C: the caller throws Interrupted
          std::vector<T>& sink = sinks[static_cast<size_t>(b)];
          for (int64_t i = b * kBlock; i < std::min(count, (b + 1) * kBlock); ++i) {
            Rng rng(base, static_cast<uint64_t>(i));
            const float u_light = rng.next_float();
            const vec2 u_pos(rng.next_float(), rng.next_float());
            const vec2 u_dir(rng.next_float(), rng.next_float());
            const std::optional<LightEmission> e = lights.sample_emission(u_light, u_pos, u_dir);
            if (e) trace(i, *e, rng, sink);
          }
        }
      },
      1);
  if (interrupt_requested()) throw Interrupted{};
  size_t total = 0;
  for (const auto& s : sinks) total += s.size();
  std::vector<T> out;
  out.reserve(total);
  for (auto& s : sinks) out.insert(out.end(), s.begin(), s.end());
  return out;
}

}  // namespace illum
