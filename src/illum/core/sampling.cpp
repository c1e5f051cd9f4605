#include "illum/core/sampling.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"

namespace illum {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;  // largest float below 1

vec3 direction_from(float cos_theta, float phi) {
  // sin from (1 − cos)(1 + cos) keeps precision for narrow cones, where 1 − cos² cancels.
  const float sin_theta = std::sqrt(std::max(0.0f, (1.0f - cos_theta) * (1.0f + cos_theta)));
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
}  // namespace

vec3 sample_uniform_hemisphere(const vec2& u) {
  return direction_from(u.x, 2.0f * kPi * u.y);
}
float pdf_uniform_hemisphere() {
  return 0.5f * kInvPi;
}

vec3 sample_cosine_hemisphere(const vec2& u) {
  // Malley: uniform points on the disk lifted to the hemisphere are cosine distributed.
  const vec2 d = sample_concentric_disk(u);
  return {d.x, d.y, std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y))};
}
float pdf_cosine_hemisphere(float cos_theta) {
  return std::max(cos_theta, 0.0f) * kInvPi;
}

vec3 sample_uniform_sphere(const vec2& u) {
  return direction_from(1.0f - 2.0f * u.x, 2.0f * kPi * u.y);
}
float pdf_uniform_sphere() {
  return 0.25f * kInvPi;
}

vec3 sample_uniform_cone(const vec2& u, float cos_theta_max) {
  // cos θ is uniform on [cos θmax, 1] because dω = d(cos θ) dφ.
  const float cos_theta = 1.0f - u.x * (1.0f - cos_theta_max);
  return direction_from(cos_theta, 2.0f * kPi * u.y);
}
float pdf_uniform_cone(float cos_theta_max) {
  ILLUM_DCHECK(cos_theta_max < 1.0f, "degenerate cone");
  return 1.0f / (2.0f * kPi * (1.0f - cos_theta_max));
}

vec2 sample_concentric_disk(const vec2& u) {
  // Shirley–Chiu: concentric squares of [-1,1]^2 map to concentric circles, preserving
  // relative area, so stratification survives the warp.
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0f) * (b / a);
  } else {
    r = b;
    phi = kPi / 2.0f - (kPi / 4.0f) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}
float pdf_concentric_disk() {
  return kInvPi;
}

vec2 sample_uniform_triangle(const vec2& u) {
  // Heitz 2019: fold the square along its diagonal onto the half-scale triangle pair.
  float b0, b1;
  if (u.y > u.x) {
    b0 = 0.5f * u.x;
    b1 = u.y - b0;
  } else {
    b1 = 0.5f * u.y;
    b0 = u.x - b1;
  }
  return {b1, 1.0f - b0 - b1};
}

// ---------------------------------------------------------------------------------------

Distribution1D::Distribution1D(const float* weights, int count) {
  ILLUM_CHECK(count > 0, "Distribution1D needs at least one weight");
  func_.assign(weights, weights + count);
  cdf_.resize(static_cast<size_t>(count) + 1);
  // Accumulate in double: with a million env-map texels a float running sum would stall.
  double sum = 0.0;
  cdf_[0] = 0.0f;
  std::vector<double> running(static_cast<size_t>(count) + 1, 0.0);
  for (size_t i = 0; i < func_.size(); ++i) {
    ILLUM_CHECK(std::isfinite(func_[i]) && func_[i] >= 0.0f,
                "Distribution1D weight {} is {} (must be finite and non-negative)", i, func_[i]);
    sum += func_[i];
    running[i + 1] = sum;
  }
  integral_ = static_cast<float>(sum / count);
  for (size_t i = 1; i < cdf_.size(); ++i)
    cdf_[i] = sum > 0.0 ? static_cast<float>(running[i] / sum)
                        : static_cast<float>(static_cast<double>(i) / count);
  cdf_.back() = 1.0f;
}

float Distribution1D::pdf(int index) const {
  ILLUM_DCHECK(index >= 0 && index < count(), "cell {} out of range", index);
  return integral_ > 0.0f ? func_[static_cast<size_t>(index)] / integral_ : 1.0f;
}

float Distribution1D::pmf(int index) const {
  return pdf(index) / static_cast<float>(count());
}

namespace {
// The cell i with cdf[i] <= u < cdf[i+1]: it always has positive probability, since u < 1
// and cdf[i+1] > u >= cdf[i].
int find_cell(const std::vector<float>& cdf, float u) {
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  const auto i = static_cast<int>(it - cdf.begin()) - 1;
  return std::clamp(i, 0, static_cast<int>(cdf.size()) - 2);
}
}  // namespace

float Distribution1D::sample_continuous(float u, float* pdf_out, int* offset) const {
  ILLUM_DCHECK(!func_.empty(), "sampling an empty distribution");
  const int i = find_cell(cdf_, u);
  const auto si = static_cast<size_t>(i);
  float du = u - cdf_[si];
  const float width = cdf_[si + 1] - cdf_[si];
  if (width > 0.0f) du /= width;
  if (pdf_out) *pdf_out = pdf(i);
  if (offset) *offset = i;
  const auto n = static_cast<float>(count());
  float x = std::min((static_cast<float>(i) + std::clamp(du, 0.0f, 1.0f)) / n, kOneMinusEpsilon);
  // Rounding can carry x across the edge of cell i; pull it back so that the cell a caller
  // derives from x (as Distribution2D::pdf does) is the one whose pdf we report.
  while (static_cast<int>(x * n) > i) x = std::nextafter(x, 0.0f);
  while (static_cast<int>(x * n) < i) x = std::nextafter(x, 1.0f);
  return x;
}

int Distribution1D::sample_discrete(float u, float* pmf_out) const {
  ILLUM_DCHECK(!func_.empty(), "sampling an empty distribution");
  const int i = find_cell(cdf_, u);
  if (pmf_out) *pmf_out = pmf(i);
  return i;
}

Distribution2D::Distribution2D(const float* weights, int width, int height) {
  ILLUM_CHECK(width > 0 && height > 0, "Distribution2D needs a positive size, got {}x{}", width,
              height);
  conditional_.reserve(static_cast<size_t>(height));
  std::vector<float> row_integrals(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    conditional_.emplace_back(weights + static_cast<size_t>(y) * width, width);
    row_integrals[static_cast<size_t>(y)] = conditional_.back().integral();
  }
  marginal_ = Distribution1D(row_integrals.data(), height);
}

vec2 Distribution2D::sample_continuous(const vec2& u, float* pdf_out) const {
  float pdf_row, pdf_column;
  int row;
  const float y = marginal_.sample_continuous(u.y, &pdf_row, &row);
  const float x =
      conditional_[static_cast<size_t>(row)].sample_continuous(u.x, &pdf_column, nullptr);
  if (pdf_out) *pdf_out = pdf_row * pdf_column;
  return {x, y};
}

float Distribution2D::pdf(const vec2& p) const {
  ILLUM_DCHECK(!empty(), "pdf of an empty distribution");
  const int height = marginal_.count();
  const int width = conditional_.front().count();
  const int x = std::clamp(static_cast<int>(p.x * static_cast<float>(width)), 0, width - 1);
  const int y = std::clamp(static_cast<int>(p.y * static_cast<float>(height)), 0, height - 1);
  return marginal_.pdf(y) * conditional_[static_cast<size_t>(y)].pdf(x);
}

}  // namespace illum
