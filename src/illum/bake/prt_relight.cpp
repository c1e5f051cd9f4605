#include "illum/bake/prt_relight.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/sh.h"
#include "illum/render/material_eval.h"
#include "illum/scene/environment.h"

namespace illum::bake {

namespace {

void check_light(const ShLight& light, int bands) {
  if (light.bands != bands || light.coefficients.size() != size_t(sh::coefficient_count(bands)))
    throw Error(
        fmt::format("relight: the light has {} bands, the transfer {}", light.bands, bands));
}

// Σ_i T_i L_i for one point's transfer t ([i][rgb]).
Color apply_transfer(const float* t, const ShLight& light) {
  Color sum(0.0f);
  for (size_t i = 0; i < light.coefficients.size(); ++i)
    sum += Color(t[i * 3], t[i * 3 + 1], t[i * 3 + 2]) * light.coefficients[i];
  return sum;
}

}  // namespace

Color ShLight::radiance(const vec3& from) const {
  std::vector<float> y(coefficients.size());
  sh::evaluate<float>(bands, glm::normalize(from), y);
  Color sum(0.0f);
  for (size_t i = 0; i < y.size(); ++i) sum += coefficients[i] * y[i];
  return sum;
}

ShLight sun_light(int bands, const vec3& direction, const Color& irradiance) {
  sh::check_bands(bands, "sun light");
  const float len = glm::length(direction);
  if (!std::isfinite(len) || !(len > 0.0f))
    throw Error(fmt::format("--sun {},{},{}: the direction must be finite and not zero",
                            direction.x, direction.y, direction.z));
  if (!(std::isfinite(irradiance.x) && std::isfinite(irradiance.y) &&
        std::isfinite(irradiance.z)) ||
      irradiance.x < 0.0f || irradiance.y < 0.0f || irradiance.z < 0.0f)
    throw Error("--irradiance must be finite and ≥ 0");
  ShLight light;
  light.bands = bands;
  std::vector<float> y(size_t(sh::coefficient_count(bands)));
  sh::evaluate<float>(bands, -direction / len, y);
  for (float v : y) light.coefficients.push_back(irradiance * v);
  return light;
}

ShLight environment_light(int bands, const Environment& env) {
  sh::check_bands(bands, "environment light");
  const size_t count = size_t(sh::coefficient_count(bands));
  std::vector<glm::dvec3> sum(count, glm::dvec3(0.0));
  if (env.radiance.empty()) {
    // A constant sky has only c_0 = L·√(4π).
    sum[0] = glm::dvec3(env.constant) * double(env.scale) * std::sqrt(4.0 * kPi);
  } else {
    const int w = env.radiance.width(), h = env.radiance.height();
    std::vector<double> y(count);
    for (int row = 0; row < h; ++row) {
      // Exact solid angle of a pixel of this row: (2π/w)(cos θ0 − cos θ1).
      const double d_omega =
          (2.0 * kPi / w) * (std::cos(kPi * row / h) - std::cos(kPi * (row + 1) / h));
      for (int x = 0; x < w; ++x) {
        const vec3 dir = equirect_direction_from_uv(
            {(x + 0.5f) / float(w), (row + 0.5f) / float(h)}, env.rotation_y);
        const glm::dvec3 l = glm::dvec3(env.radiance.rgb(x, row)) * double(env.scale);
        sh::evaluate<double>(bands, glm::normalize(glm::dvec3(dir)), y);
        for (size_t i = 0; i < count; ++i) sum[i] += l * (y[i] * d_omega);
      }
    }
  }
  ShLight light;
  light.bands = bands;
  bool lit = false;
  for (const glm::dvec3& c : sum) {
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw Error(fmt::format("{}: the environment's SH projection is not finite", env.path));
    light.coefficients.push_back(Color(c));
  }
  lit = sum[0].x > 0.0 || sum[0].y > 0.0 || sum[0].z > 0.0;
  if (!lit)
    throw Error(fmt::format("{}: the environment is unlit (no positive radiance)",
                            env.path.empty() ? "environment" : env.path));
  return light;
}

Image sh_environment_map(const ShLight& light, int width) {
  const int w = std::max(2, width), h = std::max(1, w / 2);
  Image map(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      map.set_rgb(x, y,
                  light.radiance(
                      equirect_direction_from_uv({(x + 0.5f) / float(w), (y + 0.5f) / float(h)})));
  return map;
}

vec2 relight_sample_offset(int s, int samples) {
  const int n = int(std::ceil(std::sqrt(double(samples))));
  return {(float(s % n) + 0.5f) / float(n), (float(s / n) + 0.5f) / float(n)};
}

TexelTaps bilinear_texel_taps(vec2 uv1, int width, int height) {
  const float u = uv1.x * float(width) - 0.5f, v = uv1.y * float(height) - 0.5f;
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  const float ax = u - float(x0), ay = v - float(y0);
  TexelTaps taps;
  for (int k = 0; k < 4; ++k) {
    taps.x[k] = std::clamp(x0 + (k & 1), 0, width - 1);
    taps.y[k] = std::clamp(y0 + (k >> 1), 0, height - 1);
    taps.weight[k] = ((k & 1) ? ax : 1.0f - ax) * ((k >> 1) ? ay : 1.0f - ay);
  }
  return taps;
}

Image relight(const Scene& scene, const RayTracer& tracer, const baked::PrtSet& set,
              const ShLight& light, const Camera& camera, const RelightOptions& options) {
  check_light(light, set.bands);
  if (options.lookup == PrtLookup::kTexels && set.texel_transfer.empty())
    throw Error(fmt::format("{}: holds no texel transfer", set.folder));
  if (options.lookup == PrtLookup::kVertices && set.vertex_transfer.empty())
    throw Error(fmt::format("{}: holds no vertex transfer", set.folder));
  if (options.lookup == PrtLookup::kVq && set.vq.count() == 0)
    throw Error(fmt::format("{}: holds no VQ-compressed transfer (bake with --vq)", set.folder));
  if (options.width < 1 || options.height < 1 || options.samples < 1)
    throw Error("relight: image size and samples must be ≥ 1");
  ThreadLimit limit(options.threads);
  const size_t channels = size_t(3 * sh::coefficient_count(set.bands));
  const TransferMap& map = set.texel_transfer;
  Image image(options.width, options.height, 3);

  parallel_for_tiles(options.width, options.height, 16, [&](const Tile& tile) {
    std::vector<float> t(channels);
    for (int py = tile.y0; py < tile.y1; ++py)
      for (int px = tile.x0; px < tile.x1; ++px) {
        if (interrupt_requested()) return;
        Color sum(0.0f);
        for (int s = 0; s < options.samples; ++s) {
          const vec2 f = relight_sample_offset(s, options.samples);
          const Ray ray =
              camera.generate_ray(float(px) + f.x, float(py) + f.y, options.width, options.height);
          Hit hit;
          if (!tracer.intersect(ray, &hit)) {
            if (options.background) sum += light.radiance(ray.direction);
            continue;
          }
          const SurfaceInteraction si = tracer.interaction(ray, hit);
          const Instance& inst = scene.instances[hit.instance];
          const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
          if (options.lookup == PrtLookup::kVq) {
            const int w = set.atlas.width, h = set.atlas.height;
            std::fill(t.begin(), t.end(), 0.0f);
            for (int k = 0; k < 4; ++k) {
              const float ox = (k & 1) ? 0.25f : -0.25f, oy = (k >> 1) ? 0.25f : -0.25f;
              const int x = std::clamp(int(std::floor(si.uv1.x * float(w) + ox)), 0, w - 1);
              const int y = std::clamp(int(std::floor(si.uv1.y * float(h) + oy)), 0, h - 1);
              const float* r =
                  &set.vq
                       .representatives[size_t(set.vq.indices[size_t(y) * size_t(w) + size_t(x)]) *
                                        channels];
              for (size_t c = 0; c < channels; ++c) t[c] += 0.25f * r[c];
            }
          } else if (options.lookup == PrtLookup::kTexels) {
            const TexelTaps taps = bilinear_texel_taps(si.uv1, map.width, map.height);
            std::fill(t.begin(), t.end(), 0.0f);
            for (int k = 0; k < 4; ++k) {
              const float* src = map.pixel(taps.x[k], taps.y[k]);
              for (size_t c = 0; c < channels; ++c) t[c] += taps.weight[k] * src[c];
            }
          } else {
            const std::vector<float>& vt = set.vertex_transfer[hit.instance];
            const uint32_t* idx = &mesh.indices[size_t(hit.primitive) * 3];
            const float b[3] = {1.0f - hit.barycentric.x - hit.barycentric.y, hit.barycentric.x,
                                hit.barycentric.y};
            std::fill(t.begin(), t.end(), 0.0f);
            for (int k = 0; k < 3; ++k)
              for (size_t c = 0; c < channels; ++c)
                t[c] += b[k] * vt[size_t(idx[k]) * channels + c];
          }
          const Color albedo = material_albedo(scene, interaction_material(scene, si), si.uv0);
          sum += albedo * apply_transfer(t.data(), light);
        }
        image.set_rgb(px, py, sum / float(options.samples));
      }
  });
  if (interrupt_requested()) throw Interrupted{};
  return image;
}

std::vector<PixelFootprint> pixel_footprints(const RayTracer& tracer, const Camera& camera,
                                             int width, int height) {
  std::vector<PixelFootprint> out(size_t(width) * size_t(height), PixelFootprint::kFlat);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      PixelFootprint& f = out[size_t(y) * size_t(width) + size_t(x)];
      uint32_t instance = kInvalidId;
      vec3 normal(0.0f);
      for (int k = 0; k < 81; ++k) {
        Hit hit;
        const Ray ray = camera.generate_ray(float(x) + float(k % 9) / 8.0f,
                                            float(y) + float(k / 9) / 8.0f, width, height);
        if (!tracer.intersect(ray, &hit)) {
          f = PixelFootprint::kMiss;
          break;
        }
        const vec3 ng = tracer.interaction(ray, hit).ng;
        if (k == 0) instance = hit.instance, normal = ng;
        if (hit.instance != instance || glm::dot(ng, normal) < 0.999f) f = PixelFootprint::kSurface;
      }
    }
  return out;
}

}  // namespace illum::bake
