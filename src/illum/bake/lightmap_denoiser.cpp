#include "illum/bake/lightmap_denoiser.h"

#include <cmath>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"

namespace illum::bake {

namespace {

constexpr int kMaxIterations = 10;
// B3-spline taps at offsets −2..2 (Dammertz et al.'s h).
constexpr float kKernel[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
// SVGF's 3×3 Gaussian that steadies the variance before it scales the luminance weight.
constexpr float kPrefilter[3] = {0.25f, 0.5f, 0.25f};

struct TexelGeometry {
  vec3 position{0.0f};
  vec3 normal{0.0f};
  float size = 0.0f;  // world metres per texel along the most stretched direction
};

// Largest singular value of the map from texel coordinates to world space on the texel's
// triangle: the world length of the longest one-texel step. Zero for a triangle degenerate
// in uv1 (its texels then mix with nothing).
float texel_world_size(const Scene& scene, const atlas::TexelRaster& raster,
                       const atlas::TexelSample& s) {
  const Instance& inst = scene.instances[static_cast<size_t>(s.instance)];
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  glm::dvec3 p[3];
  glm::dvec2 u[3];
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.indices[3 * static_cast<size_t>(s.triangle) + static_cast<size_t>(k)];
    p[k] = glm::dvec3(vec3(inst.transform * vec4(mesh.positions[v], 1.0f)));
    u[k] = glm::dvec2(mesh.uv1[v]) * glm::dvec2(raster.width, raster.height);
  }
  const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const glm::dvec2 u1 = u[1] - u[0], u2 = u[2] - u[0];
  const double det = u1.x * u2.y - u2.x * u1.y;
  if (!(std::abs(det) > 1e-12)) return 0.0f;
  // J = [e1 e2]·[u1 u2]⁻¹, and its largest singular value from the 2×2 JᵀJ.
  const glm::dvec3 c0 = (e1 * u2.y - e2 * u1.y) / det;
  const glm::dvec3 c1 = (e2 * u1.x - e1 * u2.x) / det;
  const double a = glm::dot(c0, c0), b = glm::dot(c0, c1), c = glm::dot(c1, c1);
  const double half_diff = 0.5 * (a - c);
  const double largest = 0.5 * (a + c) + std::sqrt(half_diff * half_diff + b * b);
  const float size = static_cast<float>(std::sqrt(largest));
  return std::isfinite(size) ? size : 0.0f;
}

void validate(const Scene& scene, const atlas::TexelRaster& raster,
              const std::vector<Image>& layers, const Image& variance,
              const std::vector<float>& guide_weights) {
  atlas::check_texel_raster(scene, raster, "light-map denoise");
  if (layers.empty()) throw Error("light-map denoise: no layers");
  for (const Image& layer : layers)
    if (layer.width() != raster.width || layer.height() != raster.height || layer.channels() < 3)
      throw Error(fmt::format(
          "light-map denoise: a layer is {}x{} with {} channels, the raster {}x{} (RGB needed)",
          layer.width(), layer.height(), layer.channels(), raster.width, raster.height));
  if (variance.width() != raster.width || variance.height() != raster.height ||
      variance.channels() != 1)
    throw Error(fmt::format(
        "light-map denoise: the variance image is {}x{} with {} channels, the raster {}x{} (1)",
        variance.width(), variance.height(), variance.channels(), raster.width, raster.height));
  if (guide_weights.size() != layers.size())
    throw Error(fmt::format("light-map denoise: {} guide weights for {} layers",
                            guide_weights.size(), layers.size()));
  for (const float w : guide_weights)
    if (!std::isfinite(w)) throw Error("light-map denoise: a guide weight is not finite");
  for (const atlas::TexelSample& s : raster.samples) {
    const Mesh& mesh =
        scene.meshes[static_cast<size_t>(scene.instances[static_cast<size_t>(s.instance)].mesh)];
    if (mesh.uv1.size() != mesh.positions.size())
      throw Error(fmt::format(
          "light-map denoise: texel ({}, {}) lies on instance {}, whose mesh has no uv1 "
          "(raster made from another scene?)",
          s.x, s.y, s.instance));
    const float v = variance.pixel(s.x, s.y)[0];
    if (!(std::isfinite(v) && v >= 0.0f))
      throw Error(fmt::format("light-map denoise: texel ({}, {}) has variance {}", s.x, s.y, v));
    for (const Image& layer : layers)
      if (!is_finite(layer.rgb(s.x, s.y)))
        throw Error(fmt::format("light-map denoise: texel ({}, {}) is not finite", s.x, s.y));
  }
}

}  // namespace

void LightmapDenoiseOptions::validate() const {
  if (iterations < 0 || iterations > kMaxIterations)
    throw Error(fmt::format("light-map denoise: iterations = {} must lie in [0, {}]", iterations,
                            kMaxIterations));
  const auto positive = [](const char* name, float v) {
    if (!(std::isfinite(v) && v > 0.0f))
      throw Error(fmt::format("light-map denoise: {} = {} must be positive and finite", name, v));
  };
  positive("luminance_sigma", luminance_sigma);
  positive("plane_sigma", plane_sigma);
  positive("reach", reach);
  if (!(std::isfinite(normal_power) && normal_power >= 0.0f))
    throw Error(
        fmt::format("light-map denoise: normal_power = {} must be ≥ 0 and finite", normal_power));
}

void denoise_lightmap(const Scene& scene, const atlas::TexelRaster& raster,
                      std::vector<Image>& layers, const Image& variance,
                      const std::vector<float>& guide_weights,
                      const LightmapDenoiseOptions& options) {
  options.validate();
  validate(scene, raster, layers, variance, guide_weights);
  const size_t count = raster.samples.size();
  if (options.iterations == 0 || count == 0) return;

  std::vector<TexelGeometry> geometry(count);
  parallel_for(static_cast<int64_t>(count), [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
      geometry[static_cast<size_t>(i)] = {s.position, s.normal, texel_world_size(scene, raster, s)};
    }
  });

  // Working copies over the covered texels only (raster.samples order): every layer's RGB
  // side by side, the guide and its variance.
  const size_t channels = 3 * layers.size();
  std::vector<float> value(count * channels), next_value(count * channels);
  std::vector<float> var(count), next_var(count), prefiltered(count), guide(count);
  for (size_t i = 0; i < count; ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    for (size_t k = 0; k < layers.size(); ++k) {
      const float* px = layers[k].pixel(s.x, s.y);
      for (size_t c = 0; c < 3; ++c) value[i * channels + 3 * k + c] = px[c];
    }
    var[i] = variance.pixel(s.x, s.y)[0];
  }

  const float inv_plane = 1.0f / options.plane_sigma;
  // Logarithm of the geometric weight of texel j seen from i, with taps `distance` texels
  // apart; false when j must not contribute at all.
  const auto geometric = [&](size_t i, size_t j, float distance, float* log_weight) {
    const TexelGeometry& a = geometry[i];
    const TexelGeometry& b = geometry[j];
    const float cos_normals = glm::dot(a.normal, b.normal);
    if (!(cos_normals > 0.0f)) return false;
    const vec3 d = b.position - a.position;
    const float size = std::max(a.size, b.size);
    const float bound = options.reach * (distance + 1.0f) * size;
    if (glm::dot(d, d) > bound * bound) return false;
    const float off_plane =
        std::max(std::abs(glm::dot(a.normal, d)), std::abs(glm::dot(b.normal, d)));
    const float plane = off_plane * inv_plane / size;  // size > 0 here unless d = 0
    *log_weight = (off_plane > 0.0f ? -0.5f * plane * plane : 0.0f) +
                  (cos_normals < 1.0f ? options.normal_power * std::log(cos_normals) : 0.0f);
    return true;
  };

  const auto neighbour = [&](const atlas::TexelSample& s, int dx, int dy) -> int32_t {
    const int x = s.x + dx, y = s.y + dy;
    if (x < 0 || y < 0 || x >= raster.width || y >= raster.height) return -1;
    return raster.at(x, y);
  };

  for (int pass = 0; pass < options.iterations; ++pass) {
    if (interrupt_requested()) throw Interrupted{};
    const int step = 1 << pass;
    parallel_for(static_cast<int64_t>(count), [&](int64_t begin, int64_t end) {
      for (int64_t t = begin; t < end; ++t) {
        const size_t i = static_cast<size_t>(t);
        float g = 0.0f;
        for (size_t k = 0; k < layers.size(); ++k)
          g += guide_weights[k] *
               luminance(Color(value[i * channels + 3 * k], value[i * channels + 3 * k + 1],
                               value[i * channels + 3 * k + 2]));
        guide[i] = g;
        // The variance seen by the luminance weight: a 3×3 mean over the texel's own surface.
        const atlas::TexelSample& s = raster.samples[i];
        float sum = 0.0f, weight = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int32_t j = neighbour(s, dx, dy);
            float log_weight = 0.0f;
            if (j < 0 || !geometric(i, static_cast<size_t>(j), std::hypot(float(dx), float(dy)),
                                    &log_weight))
              continue;
            const float w = kPrefilter[dx + 1] * kPrefilter[dy + 1] * std::exp(log_weight);
            sum += w * var[static_cast<size_t>(j)];
            weight += w;
          }
        prefiltered[i] = sum / weight;  // the centre always counts
      }
    });

    parallel_for(static_cast<int64_t>(count), [&](int64_t begin, int64_t end) {
      std::vector<double> sum(channels);
      for (int64_t t = begin; t < end; ++t) {
        const size_t i = static_cast<size_t>(t);
        const atlas::TexelSample& s = raster.samples[i];
        std::fill(sum.begin(), sum.end(), 0.0);
        double weight = 0.0, var_sum = 0.0;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int32_t tap = neighbour(s, dx * step, dy * step);
            if (tap < 0) continue;
            const size_t j = static_cast<size_t>(tap);
            float log_weight = 0.0f;
            if (j != i) {
              if (!geometric(i, j, float(step) * std::hypot(float(dx), float(dy)), &log_weight))
                continue;
              const float difference = std::abs(guide[i] - guide[j]);
              if (difference > 0.0f) {
                const float sigma =
                    options.luminance_sigma * std::sqrt(prefiltered[i] + prefiltered[j]);
                if (!(sigma > 0.0f)) continue;  // exact values that differ: an edge
                log_weight -= difference / sigma;
              }
            }
            const double w = double(kKernel[dx + 2] * kKernel[dy + 2]) * std::exp(log_weight);
            if (w == 0.0) continue;
            const float* v = &value[j * channels];
            for (size_t c = 0; c < channels; ++c) sum[c] += w * v[c];
            weight += w;
            var_sum += w * w * var[j];
          }
        // The centre's weight is the kernel's alone, so `weight` > 0.
        for (size_t c = 0; c < channels; ++c)
          next_value[i * channels + c] = static_cast<float>(sum[c] / weight);
        next_var[i] = static_cast<float>(var_sum / (weight * weight));
      }
    });
    value.swap(next_value);
    var.swap(next_var);
  }

  for (size_t i = 0; i < count; ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    for (size_t k = 0; k < layers.size(); ++k) {
      float* px = layers[k].pixel(s.x, s.y);
      for (size_t c = 0; c < 3; ++c) px[c] = value[i * channels + 3 * k + c];
    }
  }
}

}  // namespace illum::bake
