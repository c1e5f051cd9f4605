// Irradiance probes (S003 ch. 7): a regular grid of points fitted to the
// scene's bounds; at each, the incident radiance L(p, ω) over the whole sphere projected on
// SH-L2 (9 coefficients per colour channel) by Monte Carlo with the path tracer's own
// estimator (render/path_radiance.h), turned into irradiance by zonal convolution with the
// clamped cosine (core/sh.h, Ramamoorthi–Hanrahan), plus a Source ambient cube and a
// validity flag. Lookups (trilinear, validity-weighted): probe_lookup.h; folder:
// baked/probe_file.h.
//
// Per probe, per sample k (one scrambled Sobol' sequence per probe, seeded from the seed and
// the probe's grid index, dimensions drawn in the path tracer's order):
//   - next-event estimation at p as at a path vertex whose "BSDF" is the SH basis over the
//     whole sphere: sample_direct(p, ...) with the MIS weight against the probe's own
//     direction pdf 1/(4π);
//   - one uniform direction ω on the sphere; L = PathRadiance::incident(ray from p along ω,
//     vertex {p, bounce 0, not specular, pdf 1/(4π)}): what a camera ray from p would see, with
//     emitters it finds MIS-weighted against the next-event sample above;
//   - both add Y_i(ω)·L/pdf to coefficient i.
// The probe's radiance coefficients L_i are the means; irradiance E_i = Λ_l L_i (Λ_0 = π,
// Λ_1 = 2π/3, Λ_2 = π/4), so that E(n) = Σ E_i Y_i(n) is the band-limited irradiance on a
// surface with normal n at p. The per-probe standard error of each coefficient is kept for
// the tests (from the sample spread of the per-sample contributions).
//
// Ambient cube (Source, S003 ch. 7): cube[f] = max(E(d_f), 0)/π for the six axis directions
// d_f = +x, −x, +y, −y, +z, −z, i.e. the SH irradiance sampled at the faces, so the
// renderer's Σ n_i² cube[face of sign n_i] (shaders/lighting.glsl) is exact along the axes.
// Derived from the SH rather than projected separately: one estimate, no second noise, and
// band 2's cross terms (xy, yz, zx), which the cube's basis cannot hold, vanish at the axes
// (the off-axis difference is bounded in ambient_cube_error_bound, tested). /π: the renderer
// multiplies a cube by the albedo, so it holds E/π (a white Lambertian surface's radiance).
//
// Validity: among the spp uniform directions, the share whose first hit is a back face
// (ray direction · geometric normal > 0). A probe is invalid (weight 0) when that share
// exceeds `backface_threshold` (default 0.25). Why 0.25: a probe outside every closed solid
// sees back faces only of open, one-sided surfaces, usually none; a probe inside a closed
// solid sees nothing but back faces (share 1), and a probe on a wall sees about half;
// the probe that is outside but sees 25% of its sphere as the back of some surface is
// dominated by geometry seen from behind, whose light is not what the room around it
// receives. DDGI (Majercik et al. 2019) uses the same 0.25 for its inside-geometry test.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/baked/probe_file.h"
#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

// The probe records and grid are the probe folder's (baked/probe_file.h).
using baked::kDefaultBackfaceThreshold;
using baked::kMaxProbeBytes;
using baked::kProbeBands;
using baked::kProbeCoefficients;
using baked::ProbeGrid;
using baked::ProbeRecord;
using baked::static_part;

inline constexpr int kMaxProbeSpp = 1 << 20;
// Default spacing: the longest side of the bounds over this many probes.
inline constexpr int kDefaultProbesAlongLongestSide = 16;

// The grid over `bounds` with `spacing` (0: the longest side / 16): n = max(1, round(side /
// spacing)) probes per axis, centred in the bounds, so the outermost probes lie between a
// quarter and three quarters of a spacing inside the bounds (off the walls of a room).
// Throws Error for a spacing ≤ 0 or not finite, empty or non-finite bounds, and for a grid
// whose records would exceed kMaxProbeBytes (the message gives the probes and the bytes).
ProbeGrid make_probe_grid(const Bounds3& bounds, float spacing);

struct ProbeBakeOptions {
  float spacing = 0.0f;  // metres between probes; 0: make_probe_grid's default
  int spp = 256;         // sphere samples per probe (1..kMaxProbeSpp)
  int max_bounces = 8;   // the path tracer's: 0 shows only emitters seen from the probe
  uint64_t seed = 0;
  float backface_threshold = kDefaultBackfaceThreshold;  // in [0, 1]
  int threads = 0;
  bool progress = true;
  // Keys: spacing (> 0 or 0), spp, max_bounces (0..1024), seed, backface_threshold.
  static ProbeBakeOptions from_params(const Params& params);
};

// Probes at arbitrary points (the grid bake and the tests). standard_errors, when not null,
// receives per probe the standard error of each irradiance coefficient (27 floats, [i][rgb]).
struct ProbeBakeStats {
  double seconds = 0.0;
  int64_t rays = 0;
  int64_t invalid = 0;
};
std::vector<ProbeRecord> bake_probes_at(const Scene& scene, const RayTracer& tracer,
                                        const std::vector<vec3>& points,
                                        const ProbeBakeOptions& options,
                                        std::vector<float>* standard_errors = nullptr,
                                        ProbeBakeStats* stats = nullptr);

struct ProbeBake {
  ProbeGrid grid;
  std::vector<ProbeRecord> probes;  // grid.count() records (MPI: on the root only)
  ProbeBakeStats stats;
};
// Bakes the grid over the scene's bounds. Polls Ctrl-C and throws Interrupted; throws
// Error for a scene without any light (every probe would be black: nothing to bake) or
// bad options. `tracer` must be built from `scene`.
ProbeBake bake_probes(const Scene& scene, const RayTracer& tracer, const ProbeBakeOptions& options);

// E(n) = Σ E_i Y_i(n) of a record's (or any 27-float) irradiance coefficients.
Color irradiance_from_sh(const float* irradiance, const vec3& n);
// The ambient cube of 27 irradiance coefficients (see the header comment), into cube[18].
void ambient_cube_from_sh(const float* irradiance, float* cube);
// Σ n_i² cube[face of n_i's sign]: what the renderer shows (before the albedo).
Color evaluate_ambient_cube(const float* cube, const vec3& n);
// For irradiance E(n) = a + b·n + nᵀQn (any SH-L2, written in the monomials) with E ≥ 0 at
// the axes, |π·cube(n) − E(n)| ≤ (|b_x| + |b_y| + |b_z|)/4 + |Q_xy| + |Q_yz| + |Q_zx| per
// channel for every unit n: the cube keeps a and Q's diagonal exactly and b only along
// the axes (Σ b_i n_i (|n_i| − 1), |n_i|(1 − |n_i|) ≤ ¼) and drops Q's off-diagonal terms
// (|2 Q_ij n_i n_j| ≤ |Q_ij|(n_i² + n_j²) ≤ |Q_ij|).
Color ambient_cube_error_bound(const float* irradiance);

}  // namespace illum::bake
