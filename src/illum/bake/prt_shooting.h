// Progressive-refinement shooting of SH transfer vectors between patches (S002 §5.4.3,
// CaSHL's bounce transfer, the analogue of CaLight's radiosity loop, §3.3): each patch holds
// its transfer T (E/π per unit of light, prt_baker.h) and an unshot part U, the outgoing
// transfer albedo ∘ (received, not yet shot). A round picks the patches whose unshot size
// A·Σ|U| is at least a quarter of the largest (S002: "the patch with the largest or a
// reasonably large un-shot transfer function", size by the sum of the absolute values of
// the SH coefficients, weighted by area as the shot power is), and each shoots `rays`
// cosine-distributed rays; a ray that hits the front of patch k's surface adds
// (A_j / (rays·A_k))·U_j × weight to T_k and albedo_k ∘ that to U_k. In expectation that is
// F_kj·U_j, the form factor from k to j (E_k/π = Σ_j F_kj L_j), so T converges to the
// interreflected transfer. Rounds end when the unshot total is below `tolerance` × the
// initial (direct) total and the patches' mean relative unshot below `relative_tolerance`
// (below), or after `max_rounds`.
//
// Two-sided, as the path tracer's opaque materials (render/bsdf.h): a ray that hits the back
// of a surface lands on that patch's back side, which has an unshot part of its own
// (albedo_k ∘ what it received) and shoots it about the reversed normals like a front. Only
// the front's T is returned (the SHL-map holds one side); the back sides exist so light
// that reaches them is reflected on instead of lost (Sibenik: 4–27 % of the light shot by
// the nave's floor, carpet, columns and walls hit backs — single-sided and intersecting
// geometry — and the relit interreflection was 5–20 % darker than the path tracer, docs/
// prt.md). A back side starts unlit (the direct transfer is the front's) and is created
// the first time something lands on it, so closed scenes pay nothing.
//
// Not the radiosity baker's bake/progressive_shooting.h: both are
// Southwell iterations (an unshot part, the shooter by magnitude × area, a stop at a share
// of the initial unshot total), but the transport differs. progressive_shooting.h hands a
// group's power to every receiver through a point-to-disk form factor and one visibility
// ray each (O(patches) rays a shot, receivers are cells of a texel grid); this loop traces
// `rays` Monte-Carlo rays per shooter, in rounds of many shooters, and a hit may land on
// several patches (vertex patches receive by barycentric weight: no grid). Moving PRT onto
// that module would swap the estimator (its error and cost), not share code; what is
// common is a dozen lines of bookkeeping. The names here start with Transfer so both live
// in one library.
//
// Deterministic: each shooter's rays come from its own scrambled Sobol' sequence (seed,
// patch, round) and the receipts are applied in shooter order, whatever the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

struct TransferPatch {
  vec3 position{0.0f};
  vec3 normal{0.0f, 0.0f, 1.0f};            // unit, shooting hemisphere (cosine about it)
  vec3 geometric_normal{0.0f, 0.0f, 1.0f};  // unit; rays below it are not shot
  float area = 0.0f;  // world m²; a patch of 0 area neither shoots nor receives
  Color albedo{0.0f};
};

// Where a hit lands: up to 3 patches with weights summing to 1 (a texel: one; a vertex
// hat basis: the triangle's three corners by barycentric weight), on their back sides when
// `back` (the ray met the surface against its winding). count = 0: nowhere (a surface
// without patches).
struct TransferReceipt {
  int count = 0;
  int32_t patch[3] = {-1, -1, -1};
  float weight[3] = {0.0f, 0.0f, 0.0f};
  bool back = false;
};
using TransferReceiver = std::function<TransferReceipt(const Ray& ray, const Hit& hit)>;

struct TransferShootingOptions {
  int rays = 256;
  double tolerance = 1e-3;
  // and when the area-weighted mean over patch sides of min(1, unshot / all they reflect,
  // Σ|c| each) is at most this: the absolute total alone stops while a dim part of the
  // scene (Sibenik's nave, lit through windows, beside a sunlit town) still holds a large
  // share of its light unshot. 1: off.
  double relative_tolerance = 0.05;
  int max_rounds = 64;
  uint64_t seed = 0;
};

// Where the shot light went, as shares of the light shot (the first coefficient's RGB sum ×
// the shooter's area share, summed over rays: the power a constant sky's bounce carries).
struct TransferShotShares {
  double front = 0.0;    // landed on patches' fronts
  double back = 0.0;     // landed on patches' back sides (reflected on from there)
  double escaped = 0.0;  // left the scene
  double lost = 0.0;     // hit a surface that has no patch
  double below = 0.0;    // drawn below the geometric surface: not shot (as the path tracer)
};

struct TransferShootingResult {
  int rounds = 0;
  double unshot_fraction =
      0.0;  // unshot total / initial total at the end (0 when nothing to shoot)
  double relative_unshot = 0.0;  // mean of each side's unshot / what it reflects, by area
  int64_t rays = 0;
  int64_t back_sides = 0;  // patches whose back side received light
  TransferShotShares shares;
};

// `transfer` holds patches.size() × payload floats ([patch][payload], payload = 3 × SH
// coefficient count, [i][rgb]): the direct transfer on entry, the interreflected on return.
// `back_direct`, empty or laid out as `transfer`: the direct transfer of the patches' back
// sides (about the reversed normals), which they reflect on; empty: the backs start unlit.
// Throws Interrupted on Ctrl-C.
TransferShootingResult shoot_transfer(const RayTracer& tracer,
                                      std::span<const TransferPatch> patches,
                                      const TransferReceiver& receiver, int payload,
                                      std::vector<float>& transfer,
                                      const TransferShootingOptions& options,
                                      std::span<const float> back_direct = {});

}  // namespace illum::bake
