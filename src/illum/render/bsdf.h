// Scattering functions for every MaterialType, evaluated and sampled in world space.
//
// Conventions: wo and wi are unit vectors pointing away from the surface. eval() returns f
// (no cosine); the estimator weight of a sample is f·|cos θi| / pdf, returned ready-made.
// Opaque materials are two-sided: they reflect on whichever side wo lies (geometric normal),
// and never let light through (wi on the other geometric side gives zero).
//
// Delta lobes (mirror; conductor and dielectric with α < kMinMicrofacetAlpha) have eval() =
// pdf() = 0; sample() returns `delta = true`, pdf = the probability of the lobe it picked,
// and the weight.
//
// Rough conductor and dielectric (GGX α = Material::alpha, microfacet.h): conductor
// f = F(o·m)·D(m)·G2(o,i) / (4 cos θo cos θi) with m = normalize(o + i); dielectric after
// Walter et al. 2007 — reflection F·D·G2 / (4 |cos θo cos θi|), transmission
// (1 − F)·D·G2·|i·m|·|o·m| / (|cos θo cos θi|·(i·m + o·m/η')²) with m = normalize(η'·i + o)
// and η' = η_i/η_o (the indices on i's and o's sides), divided by η'² in radiance mode (so
// f(o,i)/η_o² = f(i,o)/η_i²). Both sample visible normals; the dielectric then picks
// reflection with probability F(o·m).
//
// Phong follows scene.h exactly; Blinn uses the exact energy normalization instead of the
// approximate (n+8)/(8π) (see blinn_norm in bsdf.cpp: the approximation creates energy).
//
// Dielectric radiance scaling: refracting radiance into a medium with relative index
// η = η_t/η_i compresses solid angle, so radiance is multiplied by 1/η² (kRadiance, camera
// paths). Photons carry flux, which does not scale (kImportance). A closed glass object in
// air scales by 1/η² entering and η² leaving, so only paths ending inside glass differ.
#pragma once

#include <optional>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

enum class TransportMode { kRadiance, kImportance };

struct BsdfSample {
  vec3 wi{0.0f};       // world, unit
  Color f{0.0f};       // BSDF value (0 for delta lobes)
  Color weight{0.0f};  // f·|cos θi| / pdf: multiply the path throughput by this
  float pdf = 0.0f;    // solid-angle pdf; for delta lobes the lobe's selection probability
  bool delta = false;
  bool transmission = false;
};

// Fresnel reflectance of a smooth dielectric boundary for light arriving with cosine
// `cos_i` (> 0: from the outside) and relative index eta = η_inside/η_outside. Returns 1 on
// total internal reflection.
float fresnel_dielectric(float cos_i, float eta);
// Fresnel reflectance of a conductor with complex index eta + i·k (per channel) at cos_i.
Color fresnel_conductor(float cos_i, const Color& eta, const Color& k);

class Bsdf {
 public:
  // `albedo` is the texture-resolved diffuse reflectance; `shading` the frame around the
  // shading normal; `ng` the geometric normal (decides sides).
  Bsdf(const Material& material, const Color& albedo, const Frame& shading, const vec3& ng);
  // Resolves textures from the scene at the interaction.
  Bsdf(const Scene& scene, const SurfaceInteraction& si);

  bool is_delta() const { return delta_; }
  MaterialType type() const { return type_; }

  Color eval(const vec3& wo, const vec3& wi, TransportMode mode = TransportMode::kRadiance) const;
  float pdf(const vec3& wo, const vec3& wi) const;
  // u_lobe picks a lobe (diffuse/glossy, reflect/refract); u warps the direction.
  std::optional<BsdfSample> sample(const vec3& wo, float u_lobe, const vec2& u,
                                   TransportMode mode = TransportMode::kRadiance) const;

  // Probability that sample() picks the diffuse lobe (Phong/Blinn; 1 for Lambert).
  float diffuse_probability() const { return p_diffuse_; }
  // Whether sample() reads u_lobe: Phong/Blinn with both lobes, and glass. For the others
  // any u_lobe gives the same sample, so a caller may pass 0 and save drawing it.
  bool uses_lobe_choice() const { return type_ == MaterialType::kDielectric || p_diffuse_ < 1.0f; }

 private:
  // Local directions with the flip for two-sided opaque materials applied (z ≥ 0 for wo).
  bool to_local(const vec3& wo, const vec3& wi, vec3* lo, vec3* li) const;
  Color eval_local(const vec3& lo, const vec3& li) const;
  float pdf_local(const vec3& lo, const vec3& li) const;
  // Rough dielectric, both sides, in the shading frame.
  Color eval_dielectric(const vec3& lo, const vec3& li, TransportMode mode) const;
  float pdf_dielectric(const vec3& lo, const vec3& li) const;

  MaterialType type_;
  Color albedo_, specular_, transmittance_, eta_, k_;
  float exponent_, ior_, alpha_;
  Frame frame_;
  vec3 ng_;
  bool delta_;
  float p_diffuse_ = 1.0f;
};

// The reflectance a material shows at normal incidence (textures applied): albedo for
// diffuse and glossy materials (plus specular), mirror specular, dielectric transmittance
// tint, conductor Fresnel at normal incidence. Used by the `albedo` debug view.
Color material_reflectance(const Scene& scene, const Material& material,
                           const SurfaceInteraction& si);

}  // namespace illum
