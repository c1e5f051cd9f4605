// Path-traced light-maps (ALGORITHMS.md items 5, 8, 9): for every covered texel of an
// atlas, the irradiance arriving at the texel's surface point, estimated with the path
// tracer's own light transport (next-event estimation + MIS, Russian roulette), in one of
// three bases the real-time renderer displays (realtime/renderer.h, Lightmap):
//   plain  1 layer:  E/π = (1/π)∫_H L(ω) (n·ω) dω, RGB (albedo × layer = outgoing radiance
//                    of a Lambertian surface)
//   rnm    3 layers: (1/π)∫_H L(ω) max(b_i·ω, 0) dω for the Source basis in tangent space
//                    b_0 = (√(2/3), 0, 1/√3), b_{1,2} = (−1/√6, ±1/√2, 1/√3) (S003 ch. 7)
//   sh     4 layers: radiance SH-L1 c_i = ∫_H L(ω) Y_i(ω) dω in tangent space, order Y00,
//                    Y1−1 (y), Y10 (z), Y11 (x) (core SH convention)
//   dominant 3 layers: ambient A, directional colour C, dominant direction d (tangent
//                    space), made from the sh layers after the bake (lightmap_basis.h,
//                    dominant_from_sh): E/π(n) ≈ A + C·max(0, n·d), exact on the normal
// H is the hemisphere around the texel's normal; tangent space is the TexelSample frame.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_basis.h"
#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

struct LightmapBakeOptions {
  LightmapBasis basis = LightmapBasis::kPlain;
  LightmapContent content = LightmapContent::kAll;
  int spp = 256;  // hemisphere samples per texel
  // Path vertices after the texel's point, counted as the path tracer counts them after
  // the camera: 0 = direct light only (emitters seen from the texel); N = what the path
  // tracer with max_bounces N + 1 computes at a point it sees.
  int max_bounces = 8;
  int dilate = 4;     // border post-processing iterations (atlas::dilate)
  uint64_t seed = 0;  // same seed + same thread count → same maps
  // Edge-aware à-trous denoising of the covered texels before dilation
  // (lightmap_denoiser.h). Off here, so a caller that fills this struct gets the raw Monte
  // Carlo estimate (unbiased, what the estimator tests check), bit-identical to a baker
  // without a denoiser; from_params, which the CLI and files go through, turns it on.
  bool denoise = false;
  // Seam stitching after dilation (lightmap_seams.h: stitch_seams), every layer (for
  // dominant: the SH-L1 sums it is made from). Off here like `denoise`; from_params turns
  // it on (key stitch).
  bool stitch = false;
  // With stitch: also join coplanar neighbours meeting in part (T-junctions, near
  // neighbours: lightmap_coplanar.h). Key stitch_coplanar (default true).
  bool stitch_coplanar = true;
  // The denoiser's luminance_sigma: light differences up to about this many standard
  // deviations of the difference's noise are smoothed over, larger ones kept as edges.
  // 3 ≈ SVGF's σ_l = 4 (which divides by one texel's deviation, not the difference's):
  // lower keeps sharper shadows and more noise (lightmap_denoiser.h, bake/README.md).
  float denoise_strength = 3.0f;
  int threads = 0;       // 0 = all cores
  bool progress = true;  // progress bar with ETA on a terminal
  // Wall-clock budget in seconds (0 = none; the CLI's --time). With a budget the texels are
  // baked in passes that double every texel's sample count (1, 2, 4, … up to spp, which
  // must then be a power of two) and the bake stops before a pass whose predicted duration
  // (the previous pass's, scaled by its sample count) would end past the budget. The first
  // pass always runs. A budget that is never reached gives the raw layers of the bake
  // without one bit for bit (the same sums in the same order); the variance runs are summed
  // in another order, so the variance, and through it a denoised map, agree to rounding.
  // Refused across several MPI ranks (the passes would depend on the ranks).
  double time_budget_s = 0.0;

  // Keys: basis, content, spp (1..1<<20), max_bounces (0..1024), dilate (0..64), seed,
  // denoise (bool, default true), denoise_strength (0.1..100), stitch (bool, default true),
  // stitch_coplanar (bool, default true). Throws Error for out-of-range values or unknown
  // names.
  static LightmapBakeOptions from_params(const Params& params);
};

struct LightmapBake {
  LightmapBasis basis = LightmapBasis::kPlain;
  LightmapContent content = LightmapContent::kAll;
  std::vector<Image> layers;  // layer_count(basis) RGB images of the raster's size
  // One channel, raster size: at each covered texel the variance of the estimate of the
  // guide luminance (plain: layer 0's, rnm: the mean of the three layers', sh: c0's,
  // dominant: E/π on the normal's, c2/(π√(3/4π)), the plain layer's quantity),
  // before denoising, from the spread of the means of 2 (spp < 8) or 4 runs of consecutive
  // samples (spp = 1: the squared estimate); 0 at uncovered texels. Filled whether or not
  // the bake is denoised.
  Image variance;
  bool denoised = false;
  double denoise_seconds = 0.0;  // part of `seconds`
  double stitch_seconds = 0.0;   // part of `seconds`
  int64_t seam_edges = 0;        // seam edges stitched (0 without stitching)
  int64_t coplanar_edges = 0;    // coplanar edge pairs joined (lightmap_coplanar.h)
  double seconds = 0.0;
  int64_t rays = 0;
  size_t texels = 0;  // covered texels baked
  int spp = 0;        // samples taken per texel: options.spp, or fewer when stopped by time
  bool stopped_by_time = false;
  int passes = 1;  // sample passes baked (1 without a time budget)
};

// Bakes every covered texel of `raster` (made from `scene`, whose meshes carry uv1),
// denoises the covered texels if asked, and dilates the result. Polls
// interrupt_requested() (Ctrl-C) and throws Interrupted like the renderers. `tracer` must
// be built from the same `scene`.
LightmapBake bake_lightmap(const Scene& scene, const RayTracer& tracer,
                           const atlas::TexelRaster& raster, const LightmapBakeOptions& options);

}  // namespace illum::bake
