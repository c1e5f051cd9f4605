// Unidirectional path tracer: the reference every other renderer is checked against
// (ALGORITHMS.md A.3). Next-event estimation at every non-delta vertex with multiple
// importance sampling (power heuristic) against BSDF sampling for area and environment
// lights; delta lights (point, spot, directional) by next-event estimation only; Russian
// roulette after `rr_depth` bounces; every material and light type.
//
// `bounces` selects paths by k, the number of non-delta (diffuse or glossy) scattering
// vertices between the light and the camera; specular vertices (mirror, conductor, glass)
// do not count, so a mirror shows what it reflects under the same rule:
//   all        every k (full global illumination)
//   direct     k ≤ 1: emission seen directly (k = 0) plus light that scattered once (k = 1)
//   indirect1  k = 2 only: light that bounced off exactly one surface before reaching the
//              first (camera-visible, non-specular) surface — the single indirect bounce a
//              light propagation volume with one propagation step models.
// MIS pairs (a light sample and the BSDF-sampled hit of the same emitter) always share k,
// so each mode is an unbiased estimate of its own subset of light paths.
//
// The transport itself lives in path_radiance.h, shared with the light-map baker.
#pragma once

#include <atomic>
#include <cstdint>

#include "illum/render/integrator.h"
#include "illum/render/tile_renderer.h"

namespace illum {

class PathIntegrator final : public Integrator {
 public:
  enum class Bounces { kAll, kDirect, kIndirect1 };
  // Params: `max_bounces` (path vertices after the camera, default 8, 0..1024; 0 shows only
  // emitters), `bounces` ("all" | "direct" | "indirect1", default "all"), `rr_depth`
  // (bounces before Russian roulette starts, default 3).
  explicit PathIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

  struct Stats {
    RenderStats render;
    int64_t rays = 0;  // closest-hit plus shadow rays
  };
  // Counters of the last render() (for benchmarks).
  const Stats& stats() const { return stats_; }

 private:
  int max_bounces_ = 8;
  Bounces bounces_ = Bounces::kAll;
  int rr_depth_ = 3;
  Stats stats_;
};

}  // namespace illum
