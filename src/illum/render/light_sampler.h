// Sampling the scene's lights: toward a shading point (next-event estimation, with the
// pdfs MIS needs) and out of the lights (photon emission). Shared by every offline renderer.
//
// Light indices are Scene::lights indices. A scene with an Environment but no kEnvironment
// light gets one implicit environment light appended at index Scene::lights.size().
//
// Radiometry (scene.h): point/spot lights store intensity I (W/sr), so a spot light given
// by flux Φ has I = Φ/Ω with Ω = 2π(1 − cos θc) and a hard cone edge (S004); directional
// lights store irradiance E (W/m²); area lights are an instance's triangles emitting the
// material's L_e (× emission texture) from the front face only (counter-clockwise winding,
// the side the geometric normal points to); the environment emits environment_radiance().
//
// Power Φ (for selection and photon flux): point 4πI; spot I·Ω; area π·Σ L_e·A; directional
// E·πR²; environment 4π·L̄·πR² (L̄ the solid-angle mean radiance), with R the radius of the
// scene's bounding sphere: both distant lights are emitted through a disk of radius R.
#pragma once

#include <optional>
#include <vector>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/core/sampling.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

// A light point seen from a shading point, for next-event estimation.
struct LightSample {
  vec3 wi{0.0f};          // unit direction from the shading point toward the light
  float distance = kInf;  // to the sampled light point (kInf: directional, environment)
  vec3 p{0.0f};           // sampled point on the light (area, point, spot)
  // Radiance arriving along wi (area, environment), or for delta lights the irradiance on
  // a surface facing the light: point/spot I/r², directional E. Visibility not included.
  Color li{0.0f};
  float pdf = 0.0f;  // solid-angle pdf of wi for this light (not times the selection pmf); 1 for
                     // delta lights
  bool delta = false;
  // The contribution to reflected radiance is f·li·|cos θ| / (pdf · selection pmf).
};

// The shadow ray for a light sample seen from surface point p with geometric normal ng:
// its origin is pushed off the surface (offset_ray_origin) and, for lights at a finite
// distance, it is aimed at the sampled light point itself and stops just short of it.
// (Keeping the direction wi and the distance from p instead lets the offset origin reach
// the emitter before tmax when the light is closer than about one offset per unit cosine,
// e.g. the Cornell box in metres: the light then shadows itself.)
Ray shadow_ray(const vec3& p, const vec3& ng, const LightSample& sample);

// A photon leaving a light.
struct LightEmission {
  Ray ray;            // origin on the light (or its disk, for distant lights), unit direction
  vec3 normal{0.0f};  // emitter normal at the origin (area), else the ray direction
  Color flux{0.0f};   // power carried, W: averaging N of these per light gives that light's Φ;
                      // the selecting overload divides by the pmf, so its average is ΣΦ
  int light = -1;
};

class LightSampler {
 public:
  // `scene` must outlive the sampler. Precomputes emitter triangles, powers and the
  // environment's importance map.
  explicit LightSampler(const Scene& scene);

  int light_count() const { return static_cast<int>(lights_.size()); }
  LightType type(int light) const { return lights_[light].type; }
  bool is_delta(int light) const;
  Color power(int light) const { return lights_[light].power; }
  Color total_power() const;

  // Picks a light for next-event estimation: half by power (luminance), half uniformly.
  // Pure power selection starves small lights next to a distant one whose "power" over a
  // disk covering the scene is huge but mostly occluded indoors (Sibenik's sun got 99.5% of
  // the samples, its spot lights 0.15%, rendering them as fireflies).
  int choose(float u, float* pmf) const;
  float pmf(int light) const;
  // The same selection at shading point p, restricted to the lights that can reach p: a
  // spot light whose cone does not contain p (its estimate there is exactly 0) gets
  // probability 0 and the other lights share its probability in proportion. Unbiased, since
  // only lights with zero contribution lose their samples; pmf(light, p) is the probability
  // that choose(·, p, ·) returns `light` (for MIS weights of emitters hit from p). Sibenik's
  // three spots light a third of the nave: elsewhere their samples were all wasted. Without
  // spot lights this is choose(u, pmf); with them it costs a pass over the lights.
  int choose(float u, const vec3& p, float* pmf) const;
  float pmf(int light, const vec3& p) const;
  // Picks a light with probability proportional to its power (photon emission).
  int choose_by_power(float u, float* pmf) const;

  // Next-event estimation: samples a direction from `p` toward `light`. Nothing when the
  // light cannot reach p (outside a spot cone, behind an area light, zero emission).
  // Uses u.x for the triangle choice of area lights (re-used for the point).
  std::optional<LightSample> sample_li(int light, const vec3& p, const vec2& u) const;

  // Solid-angle pdf (from p) that sample_li(light, p, ·) produced the area-light point `si`
  // (a hit of that light's surface); not times pmf.
  float pdf_li_area(int light, const vec3& p, const SurfaceInteraction& si) const;

  // Environment: the implicit or explicit environment light (−1 if none), its radiance
  // arriving from `dir` (pointing away from the scene), and the solid-angle pdf of sample_li
  // for it choosing `dir` (not times pmf).
  int environment_light() const { return environment_light_; }
  Color environment_radiance(const vec3& dir) const;
  float pdf_environment(const vec3& dir) const;

  // Emission of one photon from `light`; u_pos picks the point (area: triangle and point,
  // distant: disk point), u_dir the direction. Spot: uniform in the cone; point: uniform
  // sphere; area: cosine-weighted around the front normal; directional and environment:
  // parallel rays from a disk of radius R facing the light, outside the scene's bounds.
  std::optional<LightEmission> sample_emission(int light, const vec2& u_pos,
                                               const vec2& u_dir) const;
  // Chooses the light by power first (flux divided by its pmf).
  std::optional<LightEmission> sample_emission(float u_light, const vec2& u_pos,
                                               const vec2& u_dir) const;

  // Bounding sphere used for distant lights.
  vec3 scene_center() const { return center_; }
  float scene_radius() const { return radius_; }

 private:
  struct Triangle {
    vec3 p0, p1, p2;
    vec2 uv0, uv1, uv2;
    vec3 n;  // unit front normal (winding)
    float area;
  };
  struct Entry {
    LightType type = LightType::kPoint;
    int scene_light = -1;  // −1: implicit environment
    Color power{0.0f};
    // area lights
    std::vector<Triangle> triangles;
    Distribution1D triangle_distribution;
    float total_area = 0.0f;
    int material = -1;
  };

  // Picks a triangle and a uniform point on it; returns the point, normal and uv0.
  const Triangle& sample_triangle(const Entry& e, const vec2& u, vec3* p, vec2* uv) const;
  Color area_emission(const Entry& e, const vec2& uv) const;
  vec3 sample_environment_direction(const vec2& u, float* pdf) const;
  // False when `light` is a spot light whose cone does not contain p (the one test
  // sample_li uses), or p is at its position; true for every other light.
  bool can_reach(int light, const vec3& p) const;
  // Sum of the selection pmf of the lights that can reach p.
  float reachable_share(const vec3& p) const;

  const Scene& scene_;
  bool has_spots_ = false;
  std::vector<Entry> lights_;
  Distribution1D selection_;        // next-event estimation: power/uniform mixture
  Distribution1D power_selection_;  // emission: by power
  int environment_light_ = -1;
  Distribution2D env_distribution_;
  vec3 center_{0.0f};
  float radius_ = 1.0f;
};

}  // namespace illum
