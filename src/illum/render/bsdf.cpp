#include "illum/render/bsdf.h"

#include <algorithm>
#include <cmath>

#include "illum/core/sampling.h"
#include "illum/render/material_eval.h"
#include "illum/render/microfacet.h"

namespace illum {

namespace {

vec3 reflect_local(const vec3& v) {
  return {-v.x, -v.y, v.z};
}

float safe_sqrt(float x) {
  return std::sqrt(std::max(x, 0.0f));
}

// Normalized lobe constants from the MaterialType contract (scene.h).
float phong_norm(float n) {
  return (n + 2.0f) * (0.5f * kInvPi);
}
// Errata: the contract's Blinn factor (n+8)/(8π) is an approximation that reflects up to
// 6.5% more than it receives at normal incidence for small n (measured by the furnace test
// in tests/render/bsdf_test.cpp). We use the exact normal-incidence normalization
// (n+2)(n+4) / (8π(2^(−n/2) + n)), which tends to (n+8)/(8π) ... (n+6)/(8π) for large n and
// is 1/π at n = 0.
float blinn_norm(float n) {
  return (n + 2.0f) * (n + 4.0f) / (8.0f * kPi * (std::exp2(-0.5f * n) + n));
}
// Pdf of cos^n around an axis: (n+1)/(2π)·cos^n.
float lobe_pdf(float n, float cos_a) {
  return cos_a > 0.0f ? (n + 1.0f) * (0.5f * kInvPi) * std::pow(cos_a, n) : 0.0f;
}
vec3 sample_lobe(float n, const vec2& u) {
  const float cos_a = std::pow(u.x, 1.0f / (n + 1.0f));
  const float sin_a = safe_sqrt(1.0f - cos_a * cos_a);
  const float phi = 2.0f * kPi * u.y;
  return {sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a};
}

}  // namespace

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0.0f) {  // arriving from inside: swap the media
    eta = 1.0f / eta;
    cos_i = -cos_i;
  }
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  const float cos_t = safe_sqrt(1.0f - sin2_t);
  const float r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_par * r_par + r_perp * r_perp);
}

Color fresnel_conductor(float cos_i, const Color& eta, const Color& k) {
  // Exact unpolarized Fresnel reflectance for an interface from vacuum to a medium of
  // complex index η + iκ (Born & Wolf), evaluated per channel.
  const float c = std::clamp(std::abs(cos_i), 0.0f, 1.0f);
  const float cos2 = c * c, sin2 = 1.0f - cos2;
  const Color eta2 = eta * eta, k2 = k * k;
  const Color t0 = eta2 - k2 - Color(sin2);
  const Color a2b2 = glm::sqrt(glm::max(t0 * t0 + 4.0f * eta2 * k2, Color(0.0f)));
  const Color t1 = a2b2 + Color(cos2);
  const Color a = glm::sqrt(glm::max(0.5f * (a2b2 + t0), Color(0.0f)));
  const Color t2 = 2.0f * c * a;
  const Color rs = (t1 - t2) / glm::max(t1 + t2, Color(1e-12f));
  const Color t3 = cos2 * a2b2 + Color(sin2 * sin2);
  const Color t4 = t2 * sin2;
  const Color rp = rs * (t3 - t4) / glm::max(t3 + t4, Color(1e-12f));
  return glm::clamp(0.5f * (rp + rs), Color(0.0f), Color(1.0f));
}

Bsdf::Bsdf(const Material& m, const Color& albedo, const Frame& shading, const vec3& ng)
    : type_(m.type),
      albedo_(albedo),
      specular_(m.specular),
      transmittance_(m.transmittance),
      eta_(m.eta),
      k_(m.k),
      exponent_(std::max(m.exponent, 0.0f)),
      ior_(m.ior),
      alpha_(std::max(m.alpha, kMinMicrofacetAlpha)),
      frame_(shading),
      ng_(ng),
      delta_(m.is_specular()) {
  if (type_ == MaterialType::kLambert) specular_ = Color(0.0f);
  if (type_ == MaterialType::kPhong || type_ == MaterialType::kBlinn) {
    const float d = luminance(albedo_), s = luminance(specular_);
    p_diffuse_ = d + s > 0.0f ? d / (d + s) : 1.0f;
  }
  if (!(ior_ > 0.0f)) ior_ = 1.0f;
}

namespace {
Frame interaction_frame(const SurfaceInteraction& si) {
  const float len = glm::length(si.shading.n);
  if (std::abs(len - 1.0f) < 1e-3f && glm::dot(si.shading.n, si.ns) > 0.999f) return si.shading;
  return Frame::from_normal(si.ns);
}
}  // namespace

Bsdf::Bsdf(const Scene& scene, const SurfaceInteraction& si)
    : Bsdf(interaction_material(scene, si),
           material_albedo(scene, interaction_material(scene, si), si.uv0), interaction_frame(si),
           si.ng) {}

bool Bsdf::to_local(const vec3& wo, const vec3& wi, vec3* lo, vec3* li) const {
  const float go = glm::dot(wo, ng_), gi = glm::dot(wi, ng_);
  if (go * gi <= 0.0f) return false;  // opaque: no transmission, no light leaks
  *lo = frame_.to_local(wo);
  *li = frame_.to_local(wi);
  if (go < 0.0f) {  // two-sided: mirror both across the tangent plane
    lo->z = -lo->z;
    li->z = -li->z;
  }
  return lo->z > 0.0f && li->z > 0.0f;
}

Color Bsdf::eval_local(const vec3& lo, const vec3& li) const {
  if (type_ == MaterialType::kConductor) {
    const Ggx ggx(alpha_);
    const vec3 m = glm::normalize(lo + li);
    return fresnel_conductor(glm::dot(lo, m), eta_, k_) *
           (ggx.d(m) * ggx.g2(lo, li) / (4.0f * lo.z * li.z));
  }
  Color f = albedo_ * kInvPi;
  if (type_ == MaterialType::kPhong) {
    const float cos_a = glm::dot(li, reflect_local(lo));
    if (cos_a > 0.0f) f += specular_ * phong_norm(exponent_) * std::pow(cos_a, exponent_);
  } else if (type_ == MaterialType::kBlinn) {
    const vec3 h = glm::normalize(lo + li);
    if (h.z > 0.0f) f += specular_ * blinn_norm(exponent_) * std::pow(h.z, exponent_);
  }
  return f;
}

float Bsdf::pdf_local(const vec3& lo, const vec3& li) const {
  if (type_ == MaterialType::kConductor) {
    const vec3 m = glm::normalize(lo + li);
    const float o_m = glm::dot(lo, m);
    return o_m > 0.0f ? Ggx(alpha_).d_visible(lo, m) / (4.0f * o_m) : 0.0f;
  }
  float pdf = p_diffuse_ * li.z * kInvPi;
  if (p_diffuse_ < 1.0f) {
    if (type_ == MaterialType::kPhong) {
      pdf += (1.0f - p_diffuse_) * lobe_pdf(exponent_, glm::dot(li, reflect_local(lo)));
    } else if (type_ == MaterialType::kBlinn) {
      const vec3 h = glm::normalize(lo + li);
      const float wo_h = glm::dot(lo, h);
      if (wo_h > 0.0f) pdf += (1.0f - p_diffuse_) * lobe_pdf(exponent_, h.z) / (4.0f * wo_h);
    }
  }
  return pdf;
}

namespace {
// The generalized half vector of a dielectric pair (Walter et al. 2007, eq. 16), oriented to
// z > 0, and the relative index η' = η_t/η_i across the side of li (1 for reflection).
// False when no microfacet connects them: grazing, or m facing away from either direction.
bool dielectric_half_vector(const vec3& lo, const vec3& li, float ior, vec3* m, float* etap) {
  if (lo.z == 0.0f || li.z == 0.0f) return false;
  *etap = lo.z * li.z > 0.0f ? 1.0f : (lo.z > 0.0f ? ior : 1.0f / ior);
  vec3 h = li * *etap + lo;
  const float len2 = glm::dot(h, h);
  if (!(len2 > 0.0f)) return false;
  h /= std::sqrt(len2);
  if (h.z < 0.0f) h = -h;
  if (glm::dot(h, li) * li.z <= 0.0f || glm::dot(h, lo) * lo.z <= 0.0f) return false;
  *m = h;
  return true;
}
}  // namespace

Color Bsdf::eval_dielectric(const vec3& lo, const vec3& li, TransportMode mode) const {
  vec3 m;
  float etap;
  if (!dielectric_half_vector(lo, li, ior_, &m, &etap)) return Color(0.0f);
  const Ggx ggx(alpha_);
  const float fr = fresnel_dielectric(glm::dot(lo, m), ior_);
  const float dg = ggx.d(m) * ggx.g2(lo, li);
  if (etap == 1.0f && lo.z * li.z > 0.0f) return Color(fr * dg / std::abs(4.0f * lo.z * li.z));
  const float i_m = glm::dot(li, m), o_m = glm::dot(lo, m);
  const float denom = (i_m + o_m / etap) * (i_m + o_m / etap);
  float ft = (1.0f - fr) * dg * std::abs(i_m * o_m / (lo.z * li.z * denom));
  if (mode == TransportMode::kRadiance) ft /= etap * etap;
  return transmittance_ * ft;
}

float Bsdf::pdf_dielectric(const vec3& lo, const vec3& li) const {
  vec3 m;
  float etap;
  if (!dielectric_half_vector(lo, li, ior_, &m, &etap)) return 0.0f;
  const Ggx ggx(alpha_);
  const float o_m = glm::dot(lo, m);
  const float fr = fresnel_dielectric(o_m, ior_);
  if (lo.z * li.z > 0.0f) return ggx.d_visible(lo, m) / (4.0f * std::abs(o_m)) * fr;
  const float i_m = glm::dot(li, m);
  const float denom = (i_m + o_m / etap) * (i_m + o_m / etap);
  return ggx.d_visible(lo, m) * std::abs(i_m) / denom * (1.0f - fr);
}

Color Bsdf::eval(const vec3& wo, const vec3& wi, TransportMode mode) const {
  if (delta_) return Color(0.0f);
  if (type_ == MaterialType::kDielectric)
    return eval_dielectric(frame_.to_local(wo), frame_.to_local(wi), mode);
  vec3 lo, li;
  if (!to_local(wo, wi, &lo, &li)) return Color(0.0f);
  return eval_local(lo, li);
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  if (delta_) return 0.0f;
  if (type_ == MaterialType::kDielectric)
    return pdf_dielectric(frame_.to_local(wo), frame_.to_local(wi));
  vec3 lo, li;
  if (!to_local(wo, wi, &lo, &li)) return 0.0f;
  return pdf_local(lo, li);
}

std::optional<BsdfSample> Bsdf::sample(const vec3& wo, float u_lobe, const vec2& u,
                                       TransportMode mode) const {
  BsdfSample s;
  if (type_ == MaterialType::kDielectric && !delta_) {
    const vec3 lo = frame_.to_local(wo);
    if (lo.z == 0.0f) return std::nullopt;
    const vec3 m = Ggx(alpha_).sample_visible(lo, u);
    const float o_m = glm::dot(lo, m);
    if (o_m * lo.z <= 0.0f) return std::nullopt;
    vec3 li;
    if (u_lobe < fresnel_dielectric(o_m, ior_)) {
      li = 2.0f * o_m * m - lo;
      if (li.z * lo.z <= 0.0f) return std::nullopt;
    } else {
      // Refraction through the microfacet m (Snell about m instead of the macro normal).
      const float eta = o_m > 0.0f ? ior_ : 1.0f / ior_;
      const vec3 n = o_m > 0.0f ? m : -m;
      const float cos_i = std::abs(o_m);
      const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
      if (sin2_t >= 1.0f) return std::nullopt;
      li = -lo / eta + (cos_i / eta - safe_sqrt(1.0f - sin2_t)) * n;
      if (li.z * lo.z >= 0.0f) return std::nullopt;
      s.transmission = true;
    }
    li = glm::normalize(li);
    s.pdf = pdf_dielectric(lo, li);
    if (!(s.pdf > 0.0f)) return std::nullopt;
    s.f = eval_dielectric(lo, li, mode);
    s.wi = glm::normalize(frame_.to_world(li));
    s.weight = s.f * (std::abs(li.z) / s.pdf);
    return s;
  }
  if (type_ == MaterialType::kDielectric) {
    const vec3 lo = frame_.to_local(wo);
    if (lo.z == 0.0f) return std::nullopt;
    const bool entering = lo.z > 0.0f;
    const float eta = entering ? ior_ : 1.0f / ior_;  // η_t / η_i
    const float fr = fresnel_dielectric(lo.z, ior_);
    s.delta = true;
    if (u_lobe < fr) {
      s.wi = frame_.to_world(reflect_local(lo));
      s.pdf = fr;
      s.weight = Color(1.0f);  // F / F
      return s;
    }
    const float cos_i = std::abs(lo.z);
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    const vec3 n(0.0f, 0.0f, entering ? 1.0f : -1.0f);
    const vec3 li = -lo / eta + (cos_i / eta - cos_t) * n;
    s.wi = glm::normalize(frame_.to_world(li));
    s.pdf = 1.0f - fr;
    s.transmission = true;
    s.weight = transmittance_ * (mode == TransportMode::kRadiance ? 1.0f / (eta * eta) : 1.0f);
    return s;
  }

  // Opaque materials: work on the side wo lies on.
  const float go = glm::dot(wo, ng_);
  if (go == 0.0f) return std::nullopt;
  vec3 lo = frame_.to_local(wo);
  const bool flip = go < 0.0f;
  if (flip) lo.z = -lo.z;
  if (lo.z <= 0.0f) return std::nullopt;  // shading normal disagrees with the geometry
  auto to_world = [&](vec3 li) {
    if (flip) li.z = -li.z;
    return glm::normalize(frame_.to_world(li));
  };

  if (delta_) {  // mirror or smooth conductor
    s.delta = true;
    s.pdf = 1.0f;
    s.wi = to_world(reflect_local(lo));
    s.weight = type_ == MaterialType::kMirror ? specular_ : fresnel_conductor(lo.z, eta_, k_);
    if (glm::dot(s.wi, ng_) * go <= 0.0f) return std::nullopt;
    return s;
  }

  vec3 li;
  if (type_ == MaterialType::kConductor) {
    const vec3 m = Ggx(alpha_).sample_visible(lo, u);
    li = 2.0f * glm::dot(lo, m) * m - lo;
  } else if (u_lobe < p_diffuse_) {
    li = sample_cosine_hemisphere(u);
  } else if (type_ == MaterialType::kPhong) {
    li = Frame::from_normal(reflect_local(lo)).to_world(sample_lobe(exponent_, u));
  } else {  // Blinn: sample the half vector
    const vec3 h = sample_lobe(exponent_, u);
    li = 2.0f * glm::dot(lo, h) * h - lo;
  }
  if (li.z <= 0.0f) return std::nullopt;
  s.wi = to_world(li);
  if (glm::dot(s.wi, ng_) * go <= 0.0f) return std::nullopt;
  s.pdf = pdf_local(lo, li);
  if (!(s.pdf > 0.0f)) return std::nullopt;
  s.f = eval_local(lo, li);
  s.weight = s.f * (li.z / s.pdf);
  return s;
}

Color material_reflectance(const Scene& scene, const Material& m, const SurfaceInteraction& si) {
  switch (m.type) {
    case MaterialType::kLambert:
      return material_albedo(scene, m, si.uv0);
    case MaterialType::kPhong:
    case MaterialType::kBlinn:
      return material_albedo(scene, m, si.uv0) + m.specular;
    case MaterialType::kMirror:
      return m.specular;
    case MaterialType::kDielectric:
      return m.transmittance;
    case MaterialType::kConductor:
      return fresnel_conductor(1.0f, m.eta, m.k);
  }
  return Color(0.0f);
}

}  // namespace illum
