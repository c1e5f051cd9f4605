#include "illum/bake/radiosity_baker.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "illum/bake/lightmap_seams.h"
#include "illum/bake/progressive_shooting.h"
#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/render/material_eval.h"
#include "illum/scene/environment.h"

namespace illum::bake {

using glm::dvec2;

namespace {

constexpr int kMaxLayers = 4;
constexpr int kMaxGroupSize = 15;
constexpr int kMaxSamplesPerSurface = 1000;
constexpr int kMaxRays = 65536;
constexpr int kMaxDilate = 64;
// A cluster of half-diagonal r at distance d subtends a cone of half-angle asin(r/d); past
// 0.5 (30°) the shared visibility would stand for a sixth of the hemisphere's width.
constexpr float kMaxClusterRatio = 0.5f;

void validate(const RadiosityBakeOptions& o) {
  if (!(o.threshold > 0.0 && o.threshold < 1.0))  // NaN fails too
    throw Error(
        fmt::format("radiosity bake: threshold = {} must lie in (0, 1) (a share of the "
                    "initial unshot power)",
                    o.threshold));
  if (!(o.relative_threshold > 0.0 && o.relative_threshold <= 1.0))
    throw Error(
        fmt::format("radiosity bake: relative_threshold = {} must lie in (0, 1] (the "
                    "texels' mean unshot share; 1 turns it off)",
                    o.relative_threshold));
  if (o.samples_per_surface < 1 || o.samples_per_surface > kMaxSamplesPerSurface)
    throw Error(fmt::format("radiosity bake: samples_per_surface = {} must lie in [1, {}]",
                            o.samples_per_surface, kMaxSamplesPerSurface));
  if (o.group_size < 1 || o.group_size > kMaxGroupSize)
    throw Error(fmt::format("radiosity bake: group_size = {} must lie in [1, {}]", o.group_size,
                            kMaxGroupSize));
  if (o.sky_rays < 1 || o.sky_rays > kMaxRays)
    throw Error(
        fmt::format("radiosity bake: sky_rays = {} must lie in [1, {}]", o.sky_rays, kMaxRays));
  if (o.reach_rays < 0 || o.reach_rays > kMaxRays)
    throw Error(
        fmt::format("radiosity bake: reach_rays = {} must lie in [0, {}]", o.reach_rays, kMaxRays));
  if (!(o.cluster_ratio >= 0.0f && o.cluster_ratio <= kMaxClusterRatio))
    throw Error(fmt::format("radiosity bake: cluster_ratio = {} must lie in [0, {}]",
                            o.cluster_ratio, kMaxClusterRatio));
  if (o.dilate < 0 || o.dilate > kMaxDilate)
    throw Error(
        fmt::format("radiosity bake: dilate = {} must lie in [0, {}]", o.dilate, kMaxDilate));
  if (!(o.time_budget_s >= 0.0) || !std::isfinite(o.time_budget_s))
    throw Error(fmt::format("radiosity bake: time budget {} s must be a finite number ≥ 0",
                            o.time_budget_s));
  if (o.threads < 0)
    throw Error(fmt::format("radiosity bake: threads = {} must be ≥ 0", o.threads));
}

// Surfaces of the shooter choice: the connected pieces (4-neighbours) of covered texels of
// one instance. The atlas keeps charts `padding` ≥ 1 texels apart, so these are its charts.
int label_surfaces(const atlas::TexelRaster& raster, std::vector<int>& surface) {
  const size_t n = raster.samples.size();
  surface.assign(n, -1);
  int count = 0;
  std::vector<int32_t> stack;
  for (size_t seed = 0; seed < n; ++seed) {
    if (surface[seed] >= 0) continue;
    surface[seed] = count;
    stack.assign(1, int32_t(seed));
    while (!stack.empty()) {
      const atlas::TexelSample& s = raster.samples[size_t(stack.back())];
      stack.pop_back();
      const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int x = s.x + dx[k], y = s.y + dy[k];
        if (x < 0 || y < 0 || x >= raster.width || y >= raster.height) continue;
        const int32_t j = raster.at(x, y);
        if (j < 0 || surface[size_t(j)] >= 0 || raster.samples[size_t(j)].instance != s.instance)
          continue;
        surface[size_t(j)] = count;
        stack.push_back(j);
      }
    }
    ++count;
  }
  return count;
}

const Material& texel_material(const Scene& scene, const atlas::TexelSample& s, vec2* uv0) {
  const Mesh& mesh = scene.meshes[size_t(scene.instances[size_t(s.instance)].mesh)];
  *uv0 = vec2(0.0f);
  if (mesh.uv0.size() == mesh.positions.size()) {
    const size_t t = size_t(s.triangle) * 3;
    const vec2 b = s.barycentric;
    *uv0 = (1.0f - b.x - b.y) * mesh.uv0[mesh.indices[t]] + b.x * mesh.uv0[mesh.indices[t + 1]] +
           b.y * mesh.uv0[mesh.indices[t + 2]];
  }
  static const Material kDefault;
  return mesh.material >= 0 && size_t(mesh.material) < scene.materials.size()
             ? scene.materials[size_t(mesh.material)]
             : kDefault;
}

struct TexelFrame {
  vec3 p, ng, n, t, b;
  explicit TexelFrame(const atlas::TexelSample& s)
      : p(s.position),
        ng(s.geometric_normal),
        n(s.normal),
        t(s.tangent),
        b(glm::cross(s.normal, s.tangent) * s.tangent_sign) {}
  // Above the texel's hemisphere and not below its geometric surface (as the path baker).
  bool valid(const vec3& w) const { return glm::dot(w, n) > 0.0f && glm::dot(w, ng) > 0.0f; }
};

// Everything the shooting loop asks of the scene (progressive_shooting.h, Transport).
struct RadiosityTransport {
  const Scene& scene;
  const RayTracer& tracer;
  const atlas::TexelRaster& raster;
  const std::vector<Color>& albedo;
  LightmapBasis basis;
  int layers;
  int reach_rays;
  uint64_t seed;
  std::vector<Color>* accumulated;  // layers per texel
  mutable std::atomic<int64_t> rays{0};

  double magnitude(const Color& c) const { return double(c.x) + double(c.y) + double(c.z); }
  Color reflect(int receiver, const Color& arriving) const {
    return albedo[size_t(receiver)] * arriving;
  }
  // The seed's ray test between the group's centre and the receiver's point, both pushed
  // off their surfaces.
  bool visible(const ShotSource& source, int receiver) const {
    const atlas::TexelSample& r = raster.samples[size_t(receiver)];
    const vec3 towards = source.position - r.position;
    const vec3 origin = offset_ray_origin(r.position, r.geometric_normal, towards);
    const vec3 target = offset_ray_origin(source.position, source.normal, -towards);
    rays.fetch_add(1, std::memory_order_relaxed);
    return !tracer.occluded(Ray{origin, target - origin, 0.0f, 0.999f});
  }
  double reach(const ShotSource& source) const {
    if (reach_rays == 0) return -1.0;
    const Frame frame = Frame::from_normal(source.normal);
    SobolSampler sampler(hash_mix(seed, uint64_t(source.centre), 0x7265616368ull));
    int landed = 0;
    for (int k = 0; k < reach_rays; ++k) {
      sampler.start_sample(uint32_t(k));
      const vec3 w = glm::normalize(frame.to_world(sample_cosine_hemisphere(sampler.next_2d())));
      const Ray ray{offset_ray_origin(source.position, source.normal, w), w};
      Hit hit;
      if (!tracer.intersect(ray, &hit)) continue;
      const Mesh& mesh = scene.meshes[size_t(scene.instances[hit.instance].mesh)];
      if (mesh.uv1.empty()) continue;  // no patches there: what lands is lost
      if (glm::dot(tracer.interaction(ray, hit).ng, w) < 0.0f) ++landed;  // front sides only
    }
    rays.fetch_add(reach_rays, std::memory_order_relaxed);
    return double(landed) / double(reach_rays);
  }
  // A shot arrives from the source's centre: spread it over the layers by that direction.
  void received(int receiver, const ShotSource& source, const Color& arriving) const {
    const TexelFrame f(raster.samples[size_t(receiver)]);
    const vec3 d = source.position - f.p;
    const float len = glm::length(d);
    if (!(len > 0.0f)) return;
    const vec3 w = d / len;
    const float cos_r = glm::dot(w, f.n);
    if (!(cos_r > 0.0f)) return;
    float weight[kMaxLayers];
    basis_weights(basis, w, f.n, f.t, f.b, weight);
    Color* acc = &(*accumulated)[size_t(receiver) * size_t(layers)];
    const Color radiance_solid_angle = arriving / cos_r;  // ∫ L dω over the source
    for (int j = 0; j < layers; ++j) acc[j] += radiance_solid_angle * weight[j];
  }
};

}  // namespace

RadiosityBakeOptions RadiosityBakeOptions::from_params(const Params& params) {
  RadiosityBakeOptions o;
  o.basis = lightmap_basis_from_string(params.get<std::string>("basis", "plain"));
  o.content = lightmap_content_from_string(params.get<std::string>("content", "all"));
  o.threshold = params.get<float>("threshold", float(kDefaultRadiosityThreshold));
  o.relative_threshold = params.get<float>("relative_threshold", float(o.relative_threshold));
  o.samples_per_surface = params.get<int>("samples_per_surface", o.samples_per_surface);
  o.group_size = params.get<int>("group_size", o.group_size);
  o.sky_rays = params.get<int>("sky_rays", o.sky_rays);
  o.reach_rays = params.get<int>("reach_rays", o.reach_rays);
  o.cluster_ratio = params.get<float>("cluster_ratio", o.cluster_ratio);
  o.dilate = params.get<int>("dilate", o.dilate);
  o.stitch = params.get<bool>("stitch", true);
  o.stitch_coplanar = params.get<bool>("stitch_coplanar", o.stitch_coplanar);
  o.seed = params.get_seed("seed", o.seed);
  validate(o);
  return o;
}

Image texel_areas(const Scene& scene, const atlas::TexelRaster& raster) {
  Image area(raster.width, raster.height, 1);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (mesh.uv1.empty()) continue;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      vec3 p[3];
      dvec2 uv[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.indices[t + size_t(k)];
        p[k] = vec3(inst.transform * vec4(mesh.positions[v], 1.0f));
        uv[k] = dvec2(double(mesh.uv1[v].x) * raster.width, double(mesh.uv1[v].y) * raster.height);
      }
      const double world = 0.5 * double(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])));
      const dvec2 e1 = uv[1] - uv[0], e2 = uv[2] - uv[0];
      const double texels = 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x);
      if (!(world > 0.0) || !(texels > 0.0)) continue;
      const double ratio = world / texels;
      const int x0 = std::max(0, int(std::floor(std::min({uv[0].x, uv[1].x, uv[2].x}))));
      const int y0 = std::max(0, int(std::floor(std::min({uv[0].y, uv[1].y, uv[2].y}))));
      const int x1 =
          std::min(raster.width - 1, int(std::floor(std::max({uv[0].x, uv[1].x, uv[2].x}))));
      const int y1 =
          std::min(raster.height - 1, int(std::floor(std::max({uv[0].y, uv[1].y, uv[2].y}))));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          if (raster.at(x, y) < 0) continue;
          const double a = atlas::texel_overlap_area(uv, x, y);
          if (a > 0.0) area.pixel(x, y)[0] += float(a * ratio);
        }
    }
  }
  return area;
}

RadiosityBake bake_radiosity(const Scene& scene, const RayTracer& tracer,
                             const atlas::TexelRaster& raster,
                             const RadiosityBakeOptions& options) {
  validate(options);
  if (&tracer.scene() != &scene)
    throw Error("radiosity bake: the ray tracer was built from another scene");
  atlas::check_texel_raster(scene, raster, "radiosity bake");
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = raster.samples.size();
  // Dominant-direction maps are made from SH-L1 sums at the end (lightmap_basis.h).
  const LightmapBasis accumulated_basis = accumulation_basis(options.basis);
  const int layers = layer_count(accumulated_basis);

  RadiosityBake bake;
  bake.basis = options.basis;
  bake.content = options.content;
  bake.texels = n;
  bake.area = texel_areas(scene, raster);

  // Patches, their albedo and emitted exitance.
  ShootingPatches set;
  std::vector<int> surface;
  set.surface_count = label_surfaces(raster, surface);
  set.grid_width = raster.width;
  set.grid_height = raster.height;
  set.patch_at = raster.sample_of;
  set.patches.resize(n);
  std::vector<Color> albedo(n), unshot(n), total(n, Color(0.0f));
  bool emitters = false;
  for (size_t i = 0; i < n; ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    set.patches[i] =
        ShootingPatch{s.position, s.normal, bake.area.pixel(s.x, s.y)[0], s.x, s.y, surface[i]};
    vec2 uv0;
    const Material& m = texel_material(scene, s, &uv0);
    albedo[i] = glm::clamp(material_albedo(scene, m, uv0), Color(0.0f), Color(1.0f));
    unshot[i] = m.is_emissive() ? kPi * material_emission(scene, m, uv0) : Color(0.0f);
    emitters = emitters || !is_black(unshot[i]);
  }

  // Direct light of point, spot and sun lights and the sky: arrives, and is re-emitted.
  const Environment* sky = scene.environment ? &*scene.environment : nullptr;
  bool delta = false;
  for (const Light& l : scene.lights) delta = delta || l.is_delta();
  if (!delta && !sky && !emitters)
    throw Error(
        fmt::format("radiosity bake: scene '{}' has no light (no point, spot, "
                    "directional or environment light and no emissive light-mapped "
                    "surface): nothing to bake",
                    scene.name));
  std::vector<Color> accumulated(n * size_t(layers), Color(0.0f));
  std::atomic<int64_t> direct_rays{0};
  const bool skip_delta = options.content == LightmapContent::kIndirect;
  {
    ThreadLimit limit(options.threads);
    parallel_for(
        int64_t(n),
        [&](int64_t i0, int64_t i1) {
          int64_t rays = 0;
          float weight[kMaxLayers];
          for (int64_t i = i0; i < i1; ++i) {
            if (interrupt_requested()) break;
            const atlas::TexelSample& s = raster.samples[size_t(i)];
            const TexelFrame f(s);
            Color* acc = &accumulated[size_t(i) * size_t(layers)];
            Color arrived(0.0f), shown(0.0f);
            for (const Light& l : scene.lights) {
              if (!l.is_delta()) continue;
              vec3 w;
              float tmax = kInf;
              Color li;  // ∫ L dω over the light: intensity / r², or the sun's irradiance
              if (l.type == LightType::kDirectional) {
                w = -glm::normalize(l.direction);
                li = l.irradiance;
              } else {
                const vec3 d = l.position - f.p;
                const float r2 = glm::dot(d, d);
                if (!(r2 > 0.0f)) continue;
                const float r = std::sqrt(r2);
                w = d / r;
                tmax = r * (1.0f - 1e-4f);
                // Hard cone edge, as the path tracer's light sampler.
                if (l.type == LightType::kSpot &&
                    glm::dot(-w, glm::normalize(l.direction)) <= l.cos_cutoff())
                  continue;
                li = l.intensity / r2;
              }
              if (!f.valid(w)) continue;
              ++rays;
              if (tracer.occluded(Ray{offset_ray_origin(f.p, f.ng, w), w, 0.0f, tmax})) continue;
              const Color e = li * glm::dot(w, f.n);
              arrived += e;
              if (skip_delta) continue;
              shown += e;
              basis_weights(accumulated_basis, w, f.n, f.t, f.b, weight);
              for (int j = 0; j < layers; ++j) acc[j] += li * weight[j];
            }
            if (sky) {
              // Directions as the path baker draws them: cosine for plain; for directional
              // bases an equal cosine/uniform mixture (their basis functions do not vanish
              // at the horizon, where a cosine pdf alone gives infinite variance).
              const bool mixture = options.basis != LightmapBasis::kPlain;
              const Frame frame = Frame::from_normal(f.n);
              SobolSampler sampler(hash_mix(options.seed, uint64_t(s.x), uint64_t(s.y)));
              const float inv = 1.0f / float(options.sky_rays);
              for (int k = 0; k < options.sky_rays; ++k) {
                sampler.start_sample(uint32_t(k));
                const float u_lobe = sampler.next_1d();
                const vec2 u = sampler.next_2d();
                const vec3 local = !mixture || u_lobe < 0.5f ? sample_cosine_hemisphere(u)
                                                             : sample_uniform_hemisphere(u);
                const vec3 w = glm::normalize(frame.to_world(local));
                if (!f.valid(w)) continue;
                ++rays;
                if (tracer.occluded(Ray{offset_ray_origin(f.p, f.ng, w), w})) continue;
                const float c = glm::dot(w, f.n);
                const float pdf =
                    mixture ? 0.5f * c * kInvPi + 0.5f * pdf_uniform_hemisphere() : c * kInvPi;
                const Color l = environment_radiance(*sky, w) * (inv / pdf);
                arrived += l * c;
                shown += l * c;
                basis_weights(accumulated_basis, w, f.n, f.t, f.b, weight);
                for (int j = 0; j < layers; ++j) acc[j] += l * weight[j];
              }
            }
            total[size_t(i)] = shown;
            unshot[size_t(i)] += albedo[size_t(i)] * arrived;
          }
          direct_rays.fetch_add(rays, std::memory_order_relaxed);
        },
        64);
    if (interrupt_requested()) throw Interrupted{};

    RadiosityTransport transport{
        scene,        tracer,      raster, albedo, accumulated_basis, layers, options.reach_rays,
        options.seed, &accumulated};
    ShootingOptions shooting;
    shooting.threshold = options.threshold;
    shooting.relative_threshold = options.relative_threshold;
    shooting.samples_per_surface = options.samples_per_surface;
    shooting.group_size = options.group_size;
    shooting.seed = options.seed;
    shooting.time_budget_s = options.time_budget_s;
    shooting.cluster_ratio = options.cluster_ratio;
    shooting.progress = options.progress;
    shooting.label = "radiosity";
    const ShootingStats stats = shoot_progressively(set, total, unshot, transport, shooting);
    bake.shots = stats.shots;
    bake.visibility_rays = stats.visibility_tests;
    bake.shared_clusters = stats.shared_clusters;
    bake.initial_power = stats.initial_power;
    bake.remaining_power = stats.remaining_power;
    bake.relative_unshot = stats.relative_unshot;
    bake.relative_shots = stats.relative_shots;
    bake.converged = stats.converged;
    bake.scale_min = stats.scale_min;
    bake.scale_max = stats.scale_max;
    bake.scale_mean = stats.scale_mean;
    bake.rays = direct_rays.load() + transport.rays.load();
  }

  for (int j = 0; j < layers; ++j) {
    Image image(raster.width, raster.height, 3);
    for (size_t i = 0; i < n; ++i) {
      const atlas::TexelSample& s = raster.samples[i];
      const Color& c = accumulated[i * size_t(layers) + size_t(j)];
      for (int ch = 0; ch < 3; ++ch) image.pixel(s.x, s.y)[ch] = c[ch];
    }
    atlas::dilate(image, raster, options.dilate);
    bake.layers.push_back(std::move(image));
  }
  if (options.stitch) {
    const StitchReport stitched =
        stitch_baked_layers(scene, raster, bake.layers, options.stitch_coplanar);
    bake.stitch_seconds = stitched.seconds;
    bake.seam_edges = stitched.seam_edges;
    bake.coplanar_edges = stitched.coplanar_edges;
  }
  if (options.basis == LightmapBasis::kDominant) bake.layers = dominant_from_sh(bake.layers);
  bake.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return bake;
}

}  // namespace illum::bake
