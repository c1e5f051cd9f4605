// Edge-avoiding à-trous denoiser for baked light-maps (Dammertz et al. 2010, "Edge-Avoiding
// À-Trous Wavelet Transform for fast Global Illumination Filtering"; Schied et al. 2017,
// SVGF, for the variance-guided luminance weight), run in texel space over the covered
// texels of an atlas::TexelRaster.
//
// Each of `iterations` passes replaces every covered texel by a weighted mean of the 5×5
// covered texels 2^pass texels apart (B3-spline kernel 1/16, 1/4, 3/8, 1/4, 1/16), so five
// passes reach ±62 texels at the cost of 125 taps. The weight of texel j seen from texel i is
// the kernel's times
//   normal      max(n_i·n_j, 0)^normal_power                       (interpolated normals)
//   plane       exp(−½ (max(|n_i·Δp|, |n_j·Δp|) / (plane_sigma·h))²)  Δp = p_j − p_i
//   reach       0 when |Δp| > reach·(tap distance in texels + 1)·h
//   luminance   exp(−|g_i − g_j| / (luminance_sigma·√(v_i + v_j)))
// where h is the larger world-space size of a texel of i's and j's triangles (the largest
// singular value of uv1 → world), g is the guide luminance and v its variance (3×3
// prefiltered, as SVGF). The geometric terms are what keeps charts apart: the atlas pads
// charts only a few texels apart but the taps jump up to 32 texels, so a tap that lands in
// another chart must be refused by where its texel lies in the world, not by the gap. The
// luminance term refuses differences that the texels' noise cannot explain (shadow edges);
// √(v_i + v_j) is the standard deviation of g_i − g_j, which makes every weight symmetric
// in i and j. The variance is filtered along (Σw²v/(Σw)²), so later, wider passes stop at
// smaller differences.
#pragma once

#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/core/image.h"
#include "illum/scene/scene.h"

namespace illum::bake {

struct LightmapDenoiseOptions {
  int iterations = 5;            // passes (0..10); pass k reads taps 2^k texels apart
  float luminance_sigma = 3.0f;  // > 0: larger smooths across larger light differences
  float normal_power = 128.0f;   // ≥ 0: SVGF's σ_n
  float plane_sigma = 0.5f;      // > 0: distance from the tangent plane, in texels
  float reach = 2.0f;            // > 0: slack of the world-distance bound over the tap distance

  void validate() const;  // throws Error naming the bad field
};

// Filters the covered texels of every layer in place; uncovered texels are left untouched
// (dilate afterwards). `layers` are RGB images of the raster's size made from `scene` (the
// scene supplies each texel's triangle, for the texel's world size). The guide is
// g = Σ_k guide_weights[k]·luminance(layers[k]); `variance` (one channel, raster size) holds
// the variance of the guide's estimate at each covered texel. One set of weights, computed
// from the guide, filters all layers, so directional layers stay consistent with each other.
// Deterministic (each texel's sums run in a fixed order whatever the threads); throws
// Interrupted when interrupt_requested() between passes, and Error for mismatched sizes,
// non-finite guide weights or bad options.
void denoise_lightmap(const Scene& scene, const atlas::TexelRaster& raster,
                      std::vector<Image>& layers, const Image& variance,
                      const std::vector<float>& guide_weights,
                      const LightmapDenoiseOptions& options);

}  // namespace illum::bake
