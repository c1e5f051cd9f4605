// Sampling warps from [0,1)^2 to directions and points, each with its pdf. Directions are
// in a local frame with +z as the pole (use Frame::to_world). Pdfs of directions are per
// steradian, of points per unit area.
#pragma once

#include <vector>

#include "illum/core/math.h"

namespace illum {

vec3 sample_uniform_hemisphere(const vec2& u);
float pdf_uniform_hemisphere();

vec3 sample_cosine_hemisphere(const vec2& u);  // Malley's method on a concentric disk
float pdf_cosine_hemisphere(float cos_theta);

vec3 sample_uniform_sphere(const vec2& u);
float pdf_uniform_sphere();

// Uniform over the cone of directions within `cos_theta_max` of +z (solid angle
// 2π(1 − cos θmax), the seed's spot-light Ω). Needs cos_theta_max < 1; cones wider than a
// hemisphere (negative cos_theta_max) are fine.
vec3 sample_uniform_cone(const vec2& u, float cos_theta_max);
float pdf_uniform_cone(float cos_theta_max);

vec2 sample_concentric_disk(const vec2& u);  // unit disk, Shirley–Chiu
float pdf_concentric_disk();

// Barycentrics (b1, b2) uniform over a triangle (b0 = 1 − b1 − b2); pdf = 1 / area.
// Heitz 2019's low-distortion square-to-triangle map: no square root, and nearby
// samples stay nearby, which keeps the stratification of low-discrepancy points.
vec2 sample_uniform_triangle(const vec2& u);

// Spot-light emission cone: uniform within the cone of half-angle θc (same as the cone warp,
// named for the lights that use it, S004's Ω = 2π(1 − cos θc)).
inline vec3 sample_spot_cone(const vec2& u, float cos_cutoff) {
  return sample_uniform_cone(u, cos_cutoff);
}
inline float pdf_spot_cone(float cos_cutoff) {
  return pdf_uniform_cone(cos_cutoff);
}

// Power heuristic (β = 2) for multiple importance sampling.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// A 1-D piecewise-constant distribution (for light selection, env-map rows/columns).
// Weights must be finite and non-negative; if they are all zero the distribution is
// uniform (so callers never divide by a zero pdf).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const float* weights, int count);
  int count() const { return static_cast<int>(func_.size()); }
  // Mean weight: the integral of the step function over [0,1).
  float integral() const { return integral_; }
  // Continuous sample in [0,1) with its pdf (w.r.t. [0,1)) and the chosen cell.
  float sample_continuous(float u, float* pdf, int* offset) const;
  // Discrete sample: index with probability weight/sum.
  int sample_discrete(float u, float* pmf = nullptr) const;
  float pmf(int index) const;
  // Density (w.r.t. [0,1)) of the continuous distribution inside cell `index`, exactly the
  // value sample_continuous reports for samples in that cell.
  float pdf(int index) const;

 private:
  std::vector<float> func_, cdf_;
  float integral_ = 0.0f;
};

// 2-D piecewise-constant distribution over [0,1)^2 (rows × columns), for importance
// sampling environment maps. `weights` is row-major, weights[y * width + x]; a sample's x
// picks the column and y the row (y = 0 at row 0). Sampling draws the row from the
// marginal (u.y), then the column from that row's conditional (u.x).
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const float* weights, int width, int height);
  vec2 sample_continuous(const vec2& u, float* pdf) const;
  // Density w.r.t. [0,1)^2 at p (clamped into the domain); equals the pdf that
  // sample_continuous reports for a sample at p.
  float pdf(const vec2& p) const;
  bool empty() const { return conditional_.empty(); }

 private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
};

}  // namespace illum
