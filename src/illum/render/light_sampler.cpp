#include "illum/render/light_sampler.h"

#include <algorithm>
#include <cmath>

#include "illum/render/material_eval.h"
#include "illum/scene/environment.h"

namespace illum {

namespace {

Color texture_mean(const Scene& scene, int texture) {
  if (texture < 0 || static_cast<size_t>(texture) >= scene.textures.size()) return Color(1.0f);
  const Image& image = scene.textures[texture].image;
  if (image.empty()) return Color(1.0f);
  Color sum(0.0f);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image.rgb(x, y);
  return sum / static_cast<float>(image.pixel_count());
}

// Unit direction from p to a point or spot light at `position`; false when p is at it.
bool direction_to(const vec3& position, const vec3& p, vec3* wi, float* r2) {
  const vec3 d = position - p;
  *r2 = glm::dot(d, d);
  if (!(*r2 > 0.0f)) return false;
  *wi = d / std::sqrt(*r2);
  return true;
}

// Hard cone edge (S004): full intensity inside, nothing outside.
bool inside_spot_cone(const Light& l, const vec3& wi) {
  return glm::dot(-wi, glm::normalize(l.direction)) > l.cos_cutoff();
}

}  // namespace

Ray shadow_ray(const vec3& p, const vec3& ng, const LightSample& sample) {
  const vec3 origin = offset_ray_origin(p, ng, sample.wi);
  if (!std::isfinite(sample.distance)) return Ray{origin, sample.wi, 0.0f, kInf};
  const vec3 d = sample.p - origin;
  const float distance = glm::length(d);
  if (!(distance > 0.0f)) return Ray{origin, sample.wi, 0.0f, 0.0f};
  // Relative margin: the ray meets the emitter's plane only at the target itself.
  return Ray{origin, d / distance, 0.0f, distance * (1.0f - 1e-4f)};
}

LightSampler::LightSampler(const Scene& scene) : scene_(scene) {
  const Bounds3 bounds = scene.bounds();
  if (!bounds.empty()) {
    center_ = bounds.center();
    radius_ = std::max(0.5f * bounds.diagonal(), 1e-6f);
  }
  const float disk_area = kPi * radius_ * radius_;

  lights_.resize(scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    Entry& e = lights_[i];
    e.type = light.type;
    e.scene_light = static_cast<int>(i);
    switch (light.type) {
      case LightType::kPoint:
        e.power = 4.0f * kPi * light.intensity;
        break;
      case LightType::kSpot:
        e.power = light.cone_solid_angle() * light.intensity;
        has_spots_ = true;
        break;
      case LightType::kDirectional:
        e.power = light.irradiance * disk_area;
        break;
      case LightType::kEnvironment:
        if (environment_light_ < 0) environment_light_ = static_cast<int>(i);
        break;
      case LightType::kArea: {
        if (light.instance < 0 || static_cast<size_t>(light.instance) >= scene.instances.size())
          break;
        const Instance& inst = scene.instances[light.instance];
        if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size()) break;
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.material < 0 || static_cast<size_t>(mesh.material) >= scene.materials.size())
          break;
        const Material& material = scene.materials[mesh.material];
        if (!material.is_emissive()) break;
        e.material = mesh.material;
        std::vector<float> areas;
        for (size_t t = 0; t < mesh.triangle_count(); ++t) {
          Triangle tri;
          const uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                         i2 = mesh.indices[3 * t + 2];
          tri.p0 = vec3(inst.transform * vec4(mesh.positions[i0], 1.0f));
          tri.p1 = vec3(inst.transform * vec4(mesh.positions[i1], 1.0f));
          tri.p2 = vec3(inst.transform * vec4(mesh.positions[i2], 1.0f));
          if (!mesh.uv0.empty()) {
            tri.uv0 = mesh.uv0[i0];
            tri.uv1 = mesh.uv0[i1];
            tri.uv2 = mesh.uv0[i2];
          } else {
            tri.uv0 = tri.uv1 = tri.uv2 = vec2(0.0f);
          }
          const vec3 c = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
          const float len = glm::length(c);
          tri.area = 0.5f * len;
          if (!(tri.area > 0.0f) || !std::isfinite(tri.area)) continue;
          tri.n = c / len;
          e.triangles.push_back(tri);
          areas.push_back(tri.area);
          e.total_area += tri.area;
        }
        if (e.triangles.empty()) break;
        e.triangle_distribution = Distribution1D(areas.data(), static_cast<int>(areas.size()));
        e.power =
            kPi * e.total_area * material.emission * texture_mean(scene, material.emission_texture);
        break;
      }
    }
  }
  if (scene.environment && environment_light_ < 0) {
    Entry e;
    e.type = LightType::kEnvironment;
    environment_light_ = static_cast<int>(lights_.size());
    lights_.push_back(e);
  }
  if (environment_light_ >= 0 && scene.environment) {
    const Environment& env = *scene.environment;
    Color mean(0.0f);
    if (env.radiance.empty()) {
      mean = env.scale * env.constant;
    } else {
      // Importance map: luminance × sin θ per texel (equal-area correction of the lat-long
      // grid), with a small floor so no texel that bilinear lookups can reach has pdf 0.
      const Image& img = env.radiance;
      const int w = img.width(), h = img.height();
      std::vector<float> weights(static_cast<size_t>(w) * h);
      double weight_sum = 0.0, sin_sum = 0.0;
      Color rgb_sum(0.0f);
      for (int y = 0; y < h; ++y) {
        const float sin_theta =
            std::sin(kPi * (static_cast<float>(y) + 0.5f) / static_cast<float>(h));
        for (int x = 0; x < w; ++x) {
          const Color c = img.rgb(x, y);
          const float l = std::max(luminance(c), 0.0f);
          weights[static_cast<size_t>(y) * w + x] = l * sin_theta;
          weight_sum += l * sin_theta;
          sin_sum += sin_theta;
          rgb_sum += c * sin_theta;
        }
      }
      const float floor =
          static_cast<float>(weight_sum / std::max(sin_sum, 1e-12)) * 1e-3f + 1e-12f;
      for (int y = 0; y < h; ++y) {
        const float sin_theta =
            std::sin(kPi * (static_cast<float>(y) + 0.5f) / static_cast<float>(h));
        for (int x = 0; x < w; ++x) weights[static_cast<size_t>(y) * w + x] += floor * sin_theta;
      }
      env_distribution_ = Distribution2D(weights.data(), w, h);
      mean = env.scale * rgb_sum / static_cast<float>(std::max(sin_sum, 1e-12));
    }
    // Parallel light through a disk of area πR² from every direction: Φ = πR²·∫L dω.
    lights_[environment_light_].power = 4.0f * kPi * mean * disk_area;
  }

  std::vector<float> weights(lights_.size());
  float total = 0.0f;
  for (size_t i = 0; i < lights_.size(); ++i) {
    weights[i] = std::max(luminance(lights_[i].power), 0.0f);
    if (!std::isfinite(weights[i])) weights[i] = 0.0f;
    total += weights[i];
  }
  if (!(total > 0.0f)) {
    std::fill(weights.begin(), weights.end(), 1.0f);
    total = static_cast<float>(weights.size());
  }
  if (!weights.empty()) {
    power_selection_ = Distribution1D(weights.data(), static_cast<int>(weights.size()));
    std::vector<float> mixed(weights.size());
    const float uniform = 1.0f / static_cast<float>(weights.size());
    for (size_t i = 0; i < weights.size(); ++i)
      mixed[i] = 0.5f * weights[i] / total + 0.5f * uniform;
    selection_ = Distribution1D(mixed.data(), static_cast<int>(mixed.size()));
  }
}

bool LightSampler::is_delta(int light) const {
  const LightType t = lights_[light].type;
  return t == LightType::kPoint || t == LightType::kSpot || t == LightType::kDirectional;
}

Color LightSampler::total_power() const {
  Color sum(0.0f);
  for (const Entry& e : lights_) sum += e.power;
  return sum;
}

int LightSampler::choose(float u, float* pmf) const {
  if (lights_.empty()) {
    if (pmf) *pmf = 0.0f;
    return -1;
  }
  return selection_.sample_discrete(u, pmf);
}

float LightSampler::pmf(int light) const {
  if (light < 0 || light >= light_count()) return 0.0f;
  return selection_.pmf(light);
}

bool LightSampler::can_reach(int light, const vec3& p) const {
  const Entry& e = lights_[static_cast<size_t>(light)];
  if (e.type != LightType::kSpot) return true;
  const Light& l = scene_.lights[static_cast<size_t>(e.scene_light)];
  vec3 wi;
  float r2 = 0.0f;
  return direction_to(l.position, p, &wi, &r2) && inside_spot_cone(l, wi);
}

float LightSampler::reachable_share(const vec3& p) const {
  float share = 0.0f;
  for (int i = 0; i < light_count(); ++i)
    if (can_reach(i, p)) share += selection_.pmf(i);
  return share;
}

int LightSampler::choose(float u, const vec3& p, float* pmf) const {
  if (!has_spots_) return choose(u, pmf);
  const float share = reachable_share(p);
  if (!(share > 0.0f)) {
    *pmf = 0.0f;
    return -1;
  }
  // Inverse CDF over the reachable lights (in index order, so u's stratification carries
  // over); the last reachable light with pmf > 0 takes any rounding remainder.
  const float target = u * share;
  float below = 0.0f;
  int last = -1;
  for (int i = 0; i < light_count(); ++i) {
    const float w = selection_.pmf(i);
    if (!(w > 0.0f) || !can_reach(i, p)) continue;
    last = i;
    if (target < below + w) break;
    below += w;
  }
  *pmf = last >= 0 ? selection_.pmf(last) / share : 0.0f;
  return last;
}

float LightSampler::pmf(int light, const vec3& p) const {
  if (!has_spots_) return pmf(light);
  if (light < 0 || light >= light_count() || !can_reach(light, p)) return 0.0f;
  const float share = reachable_share(p);
  return share > 0.0f ? selection_.pmf(light) / share : 0.0f;
}

int LightSampler::choose_by_power(float u, float* pmf) const {
  if (lights_.empty()) {
    if (pmf) *pmf = 0.0f;
    return -1;
  }
  return power_selection_.sample_discrete(u, pmf);
}

const LightSampler::Triangle& LightSampler::sample_triangle(const Entry& e, const vec2& u, vec3* p,
                                                            vec2* uv) const {
  float pdf = 0.0f;
  int index = 0;
  const float x = e.triangle_distribution.sample_continuous(u.x, &pdf, &index);
  index = std::clamp(index, 0, static_cast<int>(e.triangles.size()) - 1);
  // Re-use the fraction of u.x within the chosen cell as a fresh uniform number.
  const float n = static_cast<float>(e.triangles.size());
  const float u_reuse = std::clamp(x * n - static_cast<float>(index), 0.0f, 0.99999994f);
  const Triangle& tri = e.triangles[index];
  const vec2 b = sample_uniform_triangle(vec2(u_reuse, u.y));
  const float b0 = 1.0f - b.x - b.y;
  *p = b0 * tri.p0 + b.x * tri.p1 + b.y * tri.p2;
  *uv = b0 * tri.uv0 + b.x * tri.uv1 + b.y * tri.uv2;
  return tri;
}

Color LightSampler::area_emission(const Entry& e, const vec2& uv) const {
  return material_emission(scene_, scene_.materials[e.material], uv);
}

Color LightSampler::environment_radiance(const vec3& dir) const {
  if (!scene_.environment) return Color(0.0f);
  return illum::environment_radiance(*scene_.environment, dir);
}

float LightSampler::pdf_environment(const vec3& dir) const {
  if (!scene_.environment) return 0.0f;
  const Environment& env = *scene_.environment;
  if (env.radiance.empty() || env_distribution_.empty()) return pdf_uniform_sphere();
  const vec2 uv = equirect_uv_from_direction(dir, env.rotation_y);
  const float sin_theta = std::sin(kPi * uv.y);
  if (!(sin_theta > 0.0f)) return 0.0f;
  return env_distribution_.pdf(uv) / (2.0f * kPi * kPi * sin_theta);
}

vec3 LightSampler::sample_environment_direction(const vec2& u, float* pdf) const {
  const Environment& env = *scene_.environment;
  if (env.radiance.empty() || env_distribution_.empty()) {
    *pdf = pdf_uniform_sphere();
    return sample_uniform_sphere(u);
  }
  float pdf_uv = 0.0f;
  const vec2 uv = env_distribution_.sample_continuous(u, &pdf_uv);
  const float sin_theta = std::sin(kPi * uv.y);
  *pdf = sin_theta > 0.0f ? pdf_uv / (2.0f * kPi * kPi * sin_theta) : 0.0f;
  return equirect_direction_from_uv(uv, env.rotation_y);
}

std::optional<LightSample> LightSampler::sample_li(int light, const vec3& p, const vec2& u) const {
  if (light < 0 || light >= light_count()) return std::nullopt;
  const Entry& e = lights_[light];
  LightSample s;
  switch (e.type) {
    case LightType::kPoint:
    case LightType::kSpot: {
      const Light& l = scene_.lights[e.scene_light];
      float r2 = 0.0f;
      if (!direction_to(l.position, p, &s.wi, &r2)) return std::nullopt;
      s.distance = std::sqrt(r2);
      s.p = l.position;
      if (e.type == LightType::kSpot && !inside_spot_cone(l, s.wi)) return std::nullopt;
      s.li = l.intensity / r2;
      s.pdf = 1.0f;
      s.delta = true;
      break;
    }
    case LightType::kDirectional: {
      const Light& l = scene_.lights[e.scene_light];
      s.wi = -glm::normalize(l.direction);
      s.li = l.irradiance;
      s.pdf = 1.0f;
      s.delta = true;
      break;
    }
    case LightType::kArea: {
      if (e.triangles.empty()) return std::nullopt;
      vec2 uv;
      const Triangle& tri = sample_triangle(e, u, &s.p, &uv);
      const vec3 d = s.p - p;
      const float r2 = glm::dot(d, d);
      if (!(r2 > 0.0f)) return std::nullopt;
      s.distance = std::sqrt(r2);
      s.wi = d / s.distance;
      const float cos_l = -glm::dot(s.wi, tri.n);
      if (cos_l <= 0.0f) return std::nullopt;  // back face emits nothing
      s.li = area_emission(e, uv);
      s.pdf = r2 / (cos_l * e.total_area);
      break;
    }
    case LightType::kEnvironment: {
      if (!scene_.environment) return std::nullopt;
      s.wi = sample_environment_direction(u, &s.pdf);
      if (!(s.pdf > 0.0f)) return std::nullopt;
      s.li = environment_radiance(s.wi);
      break;
    }
  }
  if (is_black(s.li)) return std::nullopt;
  return s;
}

float LightSampler::pdf_li_area(int light, const vec3& p, const SurfaceInteraction& si) const {
  if (light < 0 || light >= light_count()) return 0.0f;
  const Entry& e = lights_[light];
  if (e.type != LightType::kArea || !(e.total_area > 0.0f)) return 0.0f;
  const vec3 d = si.p - p;
  const float r2 = glm::dot(d, d);
  const float cos_l = std::abs(glm::dot(d, si.ng)) / std::sqrt(r2);
  if (!(cos_l > 0.0f)) return 0.0f;
  return r2 / (cos_l * e.total_area);
}

std::optional<LightEmission> LightSampler::sample_emission(int light, const vec2& u_pos,
                                                           const vec2& u_dir) const {
  if (light < 0 || light >= light_count()) return std::nullopt;
  const Entry& e = lights_[light];
  LightEmission em;
  em.light = light;
  auto from_disk = [&](const vec3& travel) {
    // A disk of radius R perpendicular to the travel direction, behind the scene's sphere.
    const Frame f = Frame::from_normal(travel);
    const vec2 d = sample_concentric_disk(u_pos) * radius_;
    return center_ - radius_ * travel + d.x * f.t + d.y * f.b;
  };
  switch (e.type) {
    case LightType::kPoint: {
      const Light& l = scene_.lights[e.scene_light];
      em.ray.origin = l.position;
      em.ray.direction = sample_uniform_sphere(u_dir);
      em.normal = em.ray.direction;
      em.flux = l.intensity / pdf_uniform_sphere();
      break;
    }
    case LightType::kSpot: {
      const Light& l = scene_.lights[e.scene_light];
      const float cos_c = l.cos_cutoff();
      em.ray.origin = l.position;
      em.ray.direction =
          Frame::from_normal(glm::normalize(l.direction)).to_world(sample_spot_cone(u_dir, cos_c));
      em.normal = em.ray.direction;
      em.flux = l.intensity / pdf_spot_cone(cos_c);  // I·Ω: the whole flux, spread uniformly
      break;
    }
    case LightType::kDirectional: {
      const Light& l = scene_.lights[e.scene_light];
      const vec3 travel = glm::normalize(l.direction);
      em.ray.origin = from_disk(travel);
      em.ray.direction = travel;
      em.normal = travel;
      em.flux = l.irradiance * (kPi * radius_ * radius_);
      break;
    }
    case LightType::kArea: {
      if (e.triangles.empty()) return std::nullopt;
      vec2 uv;
      vec3 p;
      const Triangle& tri = sample_triangle(e, u_pos, &p, &uv);
      const vec3 local = sample_cosine_hemisphere(u_dir);
      em.ray.direction = Frame::from_normal(tri.n).to_world(local);
      em.ray.origin = p;
      em.normal = tri.n;
      // L_e·cos θ / (pdf_A · cos θ/π) = π·A·L_e.
      em.flux = area_emission(e, uv) * (kPi * e.total_area);
      break;
    }
    case LightType::kEnvironment: {
      if (!scene_.environment) return std::nullopt;
      float pdf = 0.0f;
      const vec3 wi = sample_environment_direction(u_dir, &pdf);
      if (!(pdf > 0.0f)) return std::nullopt;
      const vec3 travel = -wi;
      em.ray.origin = from_disk(travel);
      em.ray.direction = travel;
      em.normal = travel;
      em.flux = environment_radiance(wi) * (kPi * radius_ * radius_ / pdf);
      break;
    }
  }
  em.ray.direction = glm::normalize(em.ray.direction);
  if (is_black(em.flux)) return std::nullopt;
  return em;
}

std::optional<LightEmission> LightSampler::sample_emission(float u_light, const vec2& u_pos,
                                                           const vec2& u_dir) const {
  float pmf = 0.0f;
  const int light = choose_by_power(u_light, &pmf);
  if (light < 0 || !(pmf > 0.0f)) return std::nullopt;
  std::optional<LightEmission> em = sample_emission(light, u_pos, u_dir);
  if (em) em->flux /= pmf;
  return em;
}

}  // namespace illum
