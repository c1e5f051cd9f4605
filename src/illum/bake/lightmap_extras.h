// Extra light-map maps beside the basis layers (ALGORITHMS.md item 10, S000 §2.10): ambient
// occlusion, obscurances (plain and with colour bleeding) and bent normals, all estimated
// per texel from one set of cosine-distributed rays. At a texel with sample point x,
// normal n (the TexelSample normal, the front side) and geometric normal n_g, for
// directions ω drawn with pdf cosθ/π around n (those below the geometric surface,
// ω·n_g ≤ 0, count as blocked at distance 0, as in render/ao_integrator.cpp) and d(ω) the
// distance to the first surface along ω from x (∞ if none):
//   ao           A = (1/π)∫_H V(ω) cosθ dω,  V = 1 if d(ω) ≥ distance else 0 — the estimand of
//                the offline `ao` integrator (render/ao_integrator.h) at the same point
//   obscurance   W = (1/π)∫_H ρ(d(ω)) cosθ dω,  ρ(d) = √(d/d_max) for d < d_max, else 1
//                (S000 §2.10.2's transfer function)
//   obscurance_color
//                W_c = (1/π)∫_H R(ω) ρ(d(ω)) cosθ dω per RGB channel, R the diffuse albedo
//                of the surface hit when d < d_max, and R_ave (the area-weighted mean
//                albedo of the scene's surfaces) when no surface lies within d_max: the
//                colour-bleeding obscurance of Méndez et al. that S000 §2.10 names but
//                gives no formula for. An open texel gets R_ave, not 1.
//   bent_normal  B = normalize(∫_H V(ω) ω cosθ dω) (V as for ao): the mean unoccluded
//                direction, world space; n where every direction is blocked.
// The monochrome maps are written as grey RGB. Each estimate is the mean over `rays`
// directions from one scrambled Sobol' sequence per texel (seeded from seed, x, y), so
// texels are independent estimates and the result does not depend on threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/core/image.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

inline constexpr int kMaxExtraRays = 1 << 20;
inline constexpr float kDefaultObscuranceDmax = 0.3f;  // S000 §2.10.4
inline constexpr int kDefaultExtraRays = 180;          // S000 §2.10.4: 3 steps × 60

struct LightmapExtrasOptions {
  bool ao = false;
  bool obscurance = false;  // both obscurance and obscurance_color
  bool bent_normal = false;
  // Occluder search distance of ao and bent_normal in scene units; 0 = 0.1 × the scene's
  // bounding-box diagonal, the `ao` integrator's default.
  float ao_distance = 0.0f;
  float obscurance_dmax = kDefaultObscuranceDmax;  // scene units
  int rays = kDefaultExtraRays;                    // directions per texel
  uint64_t seed = 0;
  int dilate = 4;  // border passes of atlas::dilate, as the basis layers get
  int threads = 0;
  bool progress = true;

  bool any() const { return ao || obscurance || bent_normal; }
  // Sets the flags from a comma-separated list of ao, obscurance, bent_normal (any subset,
  // each at most once). Throws Error naming the unknown or repeated entry.
  void select(const std::string& list);
};

struct LightmapExtras {
  Image ao;                  // raster-sized grey RGB, or empty when not asked for
  Image obscurance;          // grey RGB
  Image obscurance_color;    // RGB
  Image bent_normal;         // RGB = world-space unit xyz (0 where no texel was filled)
  float ao_distance = 0.0f;  // the distance used (the default resolved)
  Color average_albedo{0.0f};
  double seconds = 0.0;
  int64_t rays = 0;
};

// The area-weighted mean diffuse albedo (Material::albedo; textures not sampled) over every
// triangle of every instance: R_ave of obscurance_color.
Color average_albedo(const Scene& scene);

// Bakes the asked-for maps over every covered texel of `raster` (the raster's samples are
// all that is read of it besides its size), then dilates them (bent normals renormalised
// after). Throws Error for out-of-range options or a tracer built from another scene; polls
// Ctrl-C and throws Interrupted.
LightmapExtras bake_lightmap_extras(const Scene& scene, const RayTracer& tracer,
                                    const atlas::TexelRaster& raster,
                                    const LightmapExtrasOptions& options);

// The global-line variant of the obscurance map (S000 §2.10.2): `directions` random global
// directions uniform on the sphere; for each, `lines_per_direction` parallel lines through
// uniform random points of the scene's bounding sphere's disc perpendicular to it. Every
// surface point a line crosses receives, on its texel, one contribution from the line's
// next surface point on the side its normal faces: ρ(d) at distance d, or 1 when that side
// is open (no further hit, or d ≥ d_max), together with a count; the map is the sum over
// the count (the seed's RGB / alpha). Lines of uniform density cross a patch in proportion
// to its projected area, so the count-normalised sum estimates the same cosine-weighted W
// as the per-texel map, but over the whole texel's area and with a random number of
// samples per texel (texels no line crossed stay 0 and have count 0).
struct GlobalLineObscuranceOptions {
  int directions = kDefaultExtraRays;
  int64_t lines_per_direction = 1000;
  float obscurance_dmax = kDefaultObscuranceDmax;
  uint64_t seed = 0;
  int threads = 0;
};
struct GlobalLineObscurance {
  Image obscurance;  // grey RGB, raster-sized
  Image count;       // one channel: contributions per texel
  double seconds = 0.0;
  int64_t rays = 0;  // intersection queries (one per segment of every line)
};
GlobalLineObscurance obscurance_global_lines(const Scene& scene, const RayTracer& tracer,
                                             const atlas::TexelRaster& raster,
                                             const GlobalLineObscuranceOptions& options);

}  // namespace illum::bake
