// Isotropic GGX (Trowbridge-Reitz) microfacet distribution in the local shading frame
// (z = the macro normal): the normal distribution D, Smith's height-correlated masking-
// shadowing G2 = 1/(1 + Λ(o) + Λ(i)), and sampling of the visible normals (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)).
//
// Visible-normal sampling draws m with density D_o(m) = G1(o)·max(0, o·m)·D(m)/cos θo, which
// cancels D and most of G in the estimator weight: a conductor's reflection sample weighs
// F·G2/G1(o) ≤ F, so no sample carries more than the Fresnel factor.
#pragma once

#include <algorithm>
#include <cmath>

#include "illum/core/math.h"

namespace illum {

class Ggx {
 public:
  explicit Ggx(float alpha) : alpha_(alpha), alpha2_(alpha * alpha) {}

  float alpha() const { return alpha_; }

  // D(m) = α² / (π (cos²θm (α² − 1) + 1)²); m in the upper hemisphere.
  float d(const vec3& m) const {
    if (m.z <= 0.0f) return 0.0f;
    const float t = m.z * m.z * (alpha2_ - 1.0f) + 1.0f;
    return alpha2_ / (kPi * t * t);
  }
  // Smith Λ(w) = (√(1 + α² tan²θ) − 1)/2, symmetric in ±w.
  float lambda(const vec3& w) const {
    const float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return 1e30f;  // grazing: fully masked
    const float tan2 = std::max(1.0f - cos2, 0.0f) / cos2;
    return 0.5f * (std::sqrt(1.0f + alpha2_ * tan2) - 1.0f);
  }
  float g1(const vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
  float g2(const vec3& wo, const vec3& wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

  // Density of visible normals seen from wo (solid angle of m); wo.z ≠ 0, m.z > 0.
  float d_visible(const vec3& wo, const vec3& m) const {
    return g1(wo) * std::abs(glm::dot(wo, m)) * d(m) / std::abs(wo.z);
  }

  // A visible normal for wo (either hemisphere: mirrored to z > 0 first); the result has
  // m.z ≥ 0.
  vec3 sample_visible(vec3 wo, const vec2& u) const {
    if (wo.z < 0.0f) wo = -wo;
    // Stretch to the hemisphere configuration (α = 1), sample the projected disk, unstretch.
    const vec3 vh = glm::normalize(vec3(alpha_ * wo.x, alpha_ * wo.y, wo.z));
    const float lensq = vh.x * vh.x + vh.y * vh.y;
    const vec3 t1 = lensq > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : vec3(1, 0, 0);
    const vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(1.0f - p1 * p1, 0.0f)) + s * p2;
    const vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(1.0f - p1 * p1 - p2 * p2, 0.0f)) * vh;
    return glm::normalize(vec3(alpha_ * nh.x, alpha_ * nh.y, std::max(nh.z, 1e-6f)));
  }

 private:
  float alpha_, alpha2_;
};

}  // namespace illum
