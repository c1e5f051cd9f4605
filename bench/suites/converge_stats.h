// The arithmetic of `illum-bench converge` (equal-noise comparison), kept apart from the
// rendering so it can be unit-tested (tests/bench/converge_stats_test.cpp).
//
// Variance estimator. Two renders A and B of the same settings with independent seeds have,
// per pixel and channel, E[(A − B)²] / 2 = σ² (the variance of one render), whatever the
// renderer's mean: no reference enters the numerator, so neither the reference's own noise
// nor a bias between renderers counts as noise. The reference R (a long render of the same
// renderer) only normalises, as a relative variance:
//   v = mean over pixels and channels of ((A − B)² / 2) / (R² + ε),   ε = (f · mean R)²
// with f = kRelativeFloor (dark pixels, below 1% of the image mean, are weighted as if they
// were that bright, so a few near-black pixels cannot dominate). v does not change when a
// renderer's whole image is scaled, so a residual unit mismatch between illum and a peer
// does not enter the efficiency ratio. Efficiency = 1 / (v · seconds per render).
#pragma once

#include <cstddef>

namespace illum {
class Image;
}

namespace illum::bench {

inline constexpr double kRelativeFloor = 0.01;

struct RelativeVariance {
  double value = 0.0;    // v above
  double epsilon = 0.0;  // ε above
  size_t terms = 0;      // pixels × channels
};

// v from two independent renders and the reference (all the same size, RGB used). Throws
// illum::Error on a size mismatch, an empty image, a non-finite value or a black reference.
RelativeVariance relative_variance(const Image& a, const Image& b, const Image& reference,
                                   double floor_fraction = kRelativeFloor);

// 1 / (v · seconds); throws illum::Error unless both are positive and finite.
double efficiency(double relative_variance, double seconds);

// The reference's own relative variance, from a render's v at `spp` samples per pixel and
// the reference's sample count: per-pixel variance falls as 1/spp, so v_ref ≈ v · spp /
// reference_spp. It biases v's denominator by about 3·v_ref (E[1/R²] for a noisy R), so the
// bench warns above kMaxReferenceVariance (a 3% bias).
inline constexpr double kMaxReferenceVariance = 0.01;
double reference_relative_variance(double relative_variance, int spp, int reference_spp);

// Mean over pixels and RGB channels.
double image_mean(const Image& image);

// --- illum's units to Cycles' (derivation in bench/peers/README.md) --------------------------
// Cycles point light of power P (W, radius 0) has radiant intensity P / (4π) W/sr.
double cycles_point_power(double intensity_w_per_sr);
// Cycles 3.4's IES texture on a point light scales the light's P/(4π) by this factor per
// unit of the profile's candela values (measured on Blender 3.4.1: `blender -b --python
// bench/peers/cycles_peer.py -- --calibrate-ies`, README). A spot of intensity I is a point
// light whose profile is 1 inside the cone and 0 outside, of power 4π·I / kCyclesIesScale.
inline constexpr double kCyclesIesScale = 0.070665;
double cycles_ies_spot_power(double intensity_w_per_sr);
// Cycles counts bounces after the first hit (0 = direct light only); illum's max_bounces
// counts the camera's first hit too (0 = emitters seen directly, 1 = direct light), so
// Cycles' limit is one less. Throws illum::Error for max_bounces < 1 (not expressible).
int cycles_max_bounces(int illum_max_bounces);

}  // namespace illum::bench
