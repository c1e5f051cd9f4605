// Real spherical harmonics (SH): the one definition that the bakers, the real-time renderer
// and shaders/sh.glsl share. Rotation is in sh_rotation.h.
//
// Convention
// - Real and orthonormal over the unit sphere: ∫ Y_i(ω) Y_j(ω) dω = δ_ij.
// - Index i = l(l+1) + m for band l ≥ 0 and −l ≤ m ≤ l. "bands" n means every l < n, n²
//   coefficients (n = 2 is "SH-L1", 4 coefficients; n = 3 is "SH-L2", 9).
// - No Condon–Shortley phase. With (x, y, z) = (sinθ cosφ, sinθ sinφ, cosθ),
//     Y_l^0  = K_l^0 P_l(z)
//     Y_l^m  = √2 K_l^m P_l^m(z) cos(mφ)    m > 0
//     Y_l^−m = √2 K_l^m P_l^m(z) sin(mφ)    m > 0
//   with K_l^m = √((2l+1)/(4π) · (l−m)!/(l+m)!) and P_l^m the associated Legendre function
//   without the (−1)^m factor, so every P_l^m ≥ 0 near the pole. Band 1 is then
//   (Y_1^−1, Y_1^0, Y_1^1) = √(3/(4π)) · (y, z, x): a plain permutation of the direction.
// - z is the polar axis of whatever frame a direction is written in: in tangent space
//   (light-maps) the normal, in world space (PRT, probes) world +z. It is not the scene's up
//   axis (+y, docs/DESIGN.md): keeping the frame's own z as the pole keeps band 1 a
//   permutation of (x, y, z) in every frame, which the light-map folders, the PRT data and
//   the shaders already store. Rotate with ShRotation to put another axis at the pole.
// - Evaluation is by recurrences: the normalised associated Legendre recurrence in z for
//   N_l^m = K_l^m P_l^m / sin^m θ, and C_m + i·S_m = (x + i·y)^m for cos(mφ)·sin^m θ and
//   sin(mφ)·sin^m θ, so no trigonometric call and no pole singularity. Bands 0–2 also have
//   a closed-form fast path (checked against the recurrence in tests/core/sh_test.cpp).
// - Precision: evaluation is a template for float (per-sample work in the bakers, the same
//   arithmetic as the shaders) and double (projection, references). Quadrature rules,
//   zonal factors and rotation matrices are computed in double.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "illum/core/error.h"

namespace illum::sh {

// Highest band count every function accepts (l ≤ 31): it bounds the tables and the O(n³)
// rotation; up to it the recurrences meet the addition theorem to 1e-12
// (Sh.AdditionTheoremHoldsInEveryBand).
inline constexpr int kMaxBands = 32;

constexpr int coefficient_count(int bands) {
  return bands * bands;
}
constexpr int index(int l, int m) {
  return l * (l + 1) + m;
}
// Throws Error naming `what` unless 1 ≤ bands ≤ kMaxBands (inline, so that the compiler
// sees the range in the callers).
inline void check_bands(int bands, const char* what) {
  if (bands < 1 || bands > kMaxBands)
    throw Error(fmt::format("{}: SH band count {} is out of range 1..{}", what, bands, kMaxBands));
}

// Closed forms of bands 0–2 (the fast path; shaders/sh.glsl mirrors them):
inline constexpr double kY00 = 0.28209479177387814;  // 1/(2√π)
inline constexpr double kY1 = 0.48860251190291992;  // √(3/(4π)): Y_1^{−1,0,1} = kY1·(y, z, x)
inline constexpr double kY2xy =
    1.0925484305920792;  // √(15/(4π)): Y_2^−2 = ·xy, Y_2^−1 = ·yz, Y_2^1 = ·xz
inline constexpr double kY20 = 0.31539156525252005;  // √(5/(16π)): Y_2^0 = ·(3z² − 1)
inline constexpr double kY22 = 0.54627421529603959;  // √(15/(16π)): Y_2^2 = ·(x² − y²)

// Every Y_i(w), i < bands², of a unit direction w into out (size ≥ bands²). Bands ≤ 3 take
// the closed-form fast path, more the recurrences.
template <class T>
void evaluate(int bands, const glm::vec<3, T>& w, std::span<T> out);
// The same by the recurrences alone, whatever the band count (the fast path's reference).
template <class T>
void evaluate_recurrence(int bands, const glm::vec<3, T>& w, std::span<T> out);
std::vector<double> evaluate(int bands, const glm::dvec3& w);

// SH-L1 of a unit direction in T: (Y00, Y1−1, Y10, Y11) = (kY00, kY1·y, kY1·z, kY1·x).
template <class T>
inline glm::vec<4, T> evaluate_l1(const glm::vec<3, T>& w) {
  const T y0 = static_cast<T>(kY00), y1 = static_cast<T>(kY1);
  return {y0, y1 * w.y, y1 * w.z, y1 * w.x};
}

// Gauss–Legendre rule on [−1, 1] with n nodes (exact for polynomials of degree ≤ 2n − 1);
// nodes ascending, by Newton's method on the Legendre recurrence to double precision.
struct GaussLegendre {
  std::vector<double> nodes, weights;
};
GaussLegendre gauss_legendre(int n);

// A product rule on the unit sphere: Gauss–Legendre in z = cosθ × equally spaced φ.
// sphere_quadrature(d) integrates every polynomial in (x, y, z) of total degree ≤ d exactly
// (d/2 + 1 nodes in z, d + 1 in φ): the φ sum is exact for every e^{ikφ}, |k| ≤ d, and what
// is left is a polynomial of degree ≤ d in z. Projecting a function of bands n_f onto bands
// n exactly therefore needs d = (n_f − 1) + (n − 1).
struct SphereQuadrature {
  std::vector<glm::dvec3> directions;
  std::vector<double> weights;  // sum 4π
};
SphereQuadrature sphere_quadrature(int degree);

// c_i = ∫ f(ω) Y_i(ω) dω by the rule (exact when f·Y_i is a polynomial within its degree).
std::vector<double> project(int bands, const SphereQuadrature& rule,
                            const std::function<double(const glm::dvec3&)>& f);

// Monte-Carlo projection from `samples` independent uniform directions on the sphere (PCG32
// stream `seed`): c_i = (4π/N) Σ f(ω_k) Y_i(ω_k), with each coefficient's standard error
// estimated from the same samples (sample standard deviation of 4π f Y_i over √N).
struct MonteCarloProjection {
  std::vector<double> coefficients;
  std::vector<double> standard_errors;
};
MonteCarloProjection project_monte_carlo(int bands,
                                         const std::function<double(const glm::dvec3&)>& f,
                                         int samples, uint64_t seed);

// f(w) = Σ c_i Y_i(w) for c of bands² coefficients.
double reconstruct(int bands, std::span<const double> coefficients, const glm::dvec3& w);

// Zonal convolution. A kernel k(n·ω) around an axis n acts on SH by the Funk–Hecke theorem:
// ∫ k(n·ω) f(ω) dω = Σ_lm Λ_l f_lm Y_lm(n), with Λ_l = 2π ∫_{−1}^{1} k(t) P_l(t) dt
// = √(4π/(2l+1)) · k_l (k_l the kernel's Y_l^0 coefficient about +z). So convolving f with
// k multiplies band l by Λ_l, and the kernel turned towards n has coefficients Λ_l Y_lm(n).
//
// The clamped cosine max(t, 0) (Ramamoorthi & Hanrahan 2001, irradiance E = Λ ∗ L):
// Λ_0 = π, Λ_1 = 2π/3, Λ_l = 0 for odd l ≥ 3, and for even l ≥ 2
// Λ_l = 2π (−1)^{l/2−1} / ((l+2)(l−1)) · l! / (2^l ((l/2)!)²)   (Λ_2 = π/4, Λ_4 = −π/24).
std::vector<double> clamped_cosine_factors(int bands);
// Λ_l of any kernel by Gauss–Legendre with `nodes` nodes over each of [−1, 0] and [0, 1]
// (exact for a polynomial kernel of degree ≤ 2·nodes − 1 − l on each half, so kernels with
// a kink at t = 0, such as the clamped cosine, integrate exactly too).
std::vector<double> zonal_factors(int bands, const std::function<double(double)>& kernel,
                                  int nodes);
// Λ_l from a kernel's zonal coefficients k_l (its Y_l^0 coefficients about +z).
std::vector<double> zonal_factors_from_coefficients(std::span<const double> zonal);
// Multiplies band l of c (bands² values) by factors[l].
void convolve(int bands, std::span<const double> factors, std::span<double> coefficients);
// Coefficients of the kernel with factors Λ_l turned towards unit n: Λ_l Y_lm(n).
std::vector<double> zonal_along(int bands, std::span<const double> factors, const glm::dvec3& n);

// Windowing against ringing: a truncated SH series of a sharp function overshoots and goes
// negative (Gibbs); damping the high bands with σ_l trades sharpness for less ringing.
// With width w > 0 (usually the band count), for l < w and 0 beyond:
//   Hanning  σ_l = (1 + cos(π l / w)) / 2
//   Lanczos  σ_l = sin(π l / w) / (π l / w), σ_0 = 1
enum class Window { kNone, kHanning, kLanczos };
Window window_from_string(const std::string& name);  // none|hanning|lanczos; Error otherwise
const char* to_string(Window window);
std::vector<double> window_factors(int bands, Window window, double width);

}  // namespace illum::sh
