#include "illum/bake/lightmap_extras.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/core/work_split.h"
#include "illum/render/material_eval.h"
#include "illum/render/render_setup.h"

namespace illum::bake {

namespace {

constexpr int kMaxDilate = 64;
constexpr float kDefaultAoDistanceFraction = 0.1f;  // AoIntegrator::kDefaultDistanceFraction

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// S000 §2.10.2: √(d/d_max) for d < d_max and 1 otherwise.
float obscurance_transfer(float d, float d_max) {
  return d < d_max ? std::sqrt(d / d_max) : 1.0f;
}

void validate(const LightmapExtrasOptions& o) {
  if (!(o.ao_distance >= 0.0f && std::isfinite(o.ao_distance)))
    throw Error(
        fmt::format("light-map extras: ao distance {} must be a finite number ≥ 0 (0: "
                    "0.1 × the scene's diagonal)",
                    o.ao_distance));
  if (!(o.obscurance_dmax > 0.0f && std::isfinite(o.obscurance_dmax)))
    throw Error(fmt::format("light-map extras: obscurance d_max {} must be a finite number > 0",
                            o.obscurance_dmax));
  if (o.rays < 1 || o.rays > kMaxExtraRays)
    throw Error(
        fmt::format("light-map extras: rays = {} must lie in [1, {}]", o.rays, kMaxExtraRays));
  if (o.dilate < 0 || o.dilate > kMaxDilate)
    throw Error(
        fmt::format("light-map extras: dilate = {} must lie in [0, {}]", o.dilate, kMaxDilate));
  if (o.threads < 0)
    throw Error(fmt::format("light-map extras: threads = {} must be ≥ 0", o.threads));
}

void validate(const Scene& scene, const RayTracer& tracer, const atlas::TexelRaster& raster) {
  if (&tracer.scene() != &scene)
    throw Error("light-map extras: the ray tracer was built from another scene");
  atlas::check_texel_raster(scene, raster, "light-map extras");
}

}  // namespace

void LightmapExtrasOptions::select(const std::string& list) {
  ao = obscurance = bent_normal = false;
  // getline drops a trailing empty item: "ao," would pass as "ao".
  if (!list.empty() &&
      (list.front() == ',' || list.back() == ',' || list.find(",,") != std::string::npos))
    throw Error(
        fmt::format("--extras '{}': an empty name in the list (ao, obscurance, "
                    "bent_normal, separated by single commas)",
                    list));
  std::stringstream in(list);
  std::string name;
  bool any_name = false;
  while (std::getline(in, name, ',')) {
    bool* flag = name == "ao"            ? &ao
                 : name == "obscurance"  ? &obscurance
                 : name == "bent_normal" ? &bent_normal
                                         : nullptr;
    if (!flag)
      throw Error(
          fmt::format("--extras: unknown extra map '{}' (a comma-separated list of ao, obscurance, "
                      "bent_normal)",
                      name));
    if (*flag) throw Error(fmt::format("--extras: '{}' is listed twice", name));
    *flag = true;
    any_name = true;
  }
  if (!any_name) throw Error("--extras: empty list (ao, obscurance, bent_normal)");
}

Color average_albedo(const Scene& scene) {
  glm::dvec3 sum(0.0);
  double area = 0.0;
  for (const Instance& inst : scene.instances) {
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    const Color albedo =
        mesh.material >= 0 && static_cast<size_t>(mesh.material) < scene.materials.size()
            ? scene.materials[static_cast<size_t>(mesh.material)].albedo
            : Material{}.albedo;
    double mesh_area = 0.0;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const vec3 p0 = vec3(inst.transform * vec4(mesh.positions[mesh.indices[t]], 1.0f));
      const vec3 p1 = vec3(inst.transform * vec4(mesh.positions[mesh.indices[t + 1]], 1.0f));
      const vec3 p2 = vec3(inst.transform * vec4(mesh.positions[mesh.indices[t + 2]], 1.0f));
      mesh_area += 0.5 * double(glm::length(glm::cross(p1 - p0, p2 - p0)));
    }
    sum += glm::dvec3(albedo) * mesh_area;
    area += mesh_area;
  }
  return area > 0.0 ? Color(sum / area) : Color(0.0f);
}

LightmapExtras bake_lightmap_extras(const Scene& scene, const RayTracer& tracer,
                                    const atlas::TexelRaster& raster,
                                    const LightmapExtrasOptions& options) {
  validate(options);
  validate(scene, tracer, raster);
  ThreadLimit thread_limit(options.threads);
  const auto start = std::chrono::steady_clock::now();

  LightmapExtras out;
  out.ao_distance = options.ao_distance > 0.0f ? options.ao_distance
                                               : kDefaultAoDistanceFraction * scene_scale(scene);
  out.average_albedo = average_albedo(scene);
  const int w = raster.width, h = raster.height;
  if (options.ao) out.ao = Image(w, h, 3);
  if (options.obscurance) {
    out.obscurance = Image(w, h, 3);
    out.obscurance_color = Image(w, h, 3);
  }
  if (options.bent_normal) out.bent_normal = Image(w, h, 3);
  if (!options.any()) return out;

  // One ray per direction serves every map: it looks as far as the farther of the two
  // distances, and each map reads the hit distance against its own.
  const float ao_distance = out.ao_distance;
  const float d_max = options.obscurance_dmax;
  const float reach = std::max(options.ao || options.bent_normal ? ao_distance : 0.0f,
                               options.obscurance ? d_max : 0.0f);
  const Color r_ave = out.average_albedo;
  const int64_t count = static_cast<int64_t>(raster.samples.size());
  Progress progress("extras", count, options.progress);
  std::atomic<int64_t> total_rays{0};
  const double inv_rays = 1.0 / static_cast<double>(options.rays);

  // One texel's maps and its ray count. Texels are independent (one sampler each), so they
  // are split across MPI ranks when the run has several (core/work_split.h).
  struct TexelRecord {
    Color ao, obscurance, obscurance_color, bent_normal;
    int64_t rays;
  };
  split_items<TexelRecord>(
      count, 16,
      [&](int64_t i) {
        TexelRecord record{};
        if (interrupt_requested()) return record;
        const atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
        const Frame frame = Frame::from_normal(s.normal);
        SobolSampler sampler(
            hash_mix(options.seed, static_cast<uint64_t>(s.x), static_cast<uint64_t>(s.y)));
        int64_t open = 0;
        double obscurance = 0.0;
        glm::dvec3 bleeding(0.0), bent(0.0);
        for (int k = 0; k < options.rays; ++k) {
          if ((k & 1023) == 1023 && interrupt_requested()) break;
          sampler.start_sample(static_cast<uint32_t>(k));
          const vec3 dir = frame.to_world(sample_cosine_hemisphere(sampler.next_2d()));
          // Below the geometric surface: blocked by the texel's own surface at distance 0
          // (ρ(0) = 0), as the `ao` integrator counts it.
          if (glm::dot(dir, s.geometric_normal) <= 0.0f) continue;
          const Ray ray{offset_ray_origin(s.position, s.geometric_normal, dir), dir, 0.0f, reach};
          Hit hit;
          const bool blocked = tracer.intersect(ray, &hit);
          ++record.rays;
          const float d = blocked ? hit.t : kInf;
          if (d >= ao_distance) {
            ++open;
            bent += glm::dvec3(dir);
          }
          if (options.obscurance) {
            const float rho = obscurance_transfer(d, d_max);
            obscurance += rho;
            Color albedo = r_ave;
            if (d < d_max) {
              const SurfaceInteraction si = tracer.interaction(ray, hit);
              albedo = material_albedo(scene, interaction_material(scene, si), si.uv0);
            }
            bleeding += glm::dvec3(albedo) * double(rho);
          }
        }
        record.ao = Color(float(double(open) * inv_rays));
        record.obscurance = Color(float(obscurance * inv_rays));
        record.obscurance_color = Color(bleeding * inv_rays);
        const double len = glm::length(bent);
        record.bent_normal = len > 0.0 ? Color(bent / len) : Color(s.normal);
        return record;
      },
      [&](int64_t i, const TexelRecord& record) {
        const atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
        if (options.ao) out.ao.set_rgb(s.x, s.y, record.ao);
        if (options.obscurance) {
          out.obscurance.set_rgb(s.x, s.y, record.obscurance);
          out.obscurance_color.set_rgb(s.x, s.y, record.obscurance_color);
        }
        if (options.bent_normal) out.bent_normal.set_rgb(s.x, s.y, record.bent_normal);
        total_rays += record.rays;
        progress.advance(1);
      });
  progress.finish();
  if (interrupt_requested()) throw Interrupted{};
  // Across ranks only the root received the texels; the others' maps are empty.
  if (const WorkSplit* split = work_split(); split && !split->is_root()) return out;

  for (Image* map : {&out.ao, &out.obscurance, &out.obscurance_color, &out.bent_normal})
    if (map->width() > 0) atlas::dilate(*map, raster, options.dilate);
  // Dilated texels are means of unit vectors: put them back on the sphere.
  if (options.bent_normal)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const vec3 v = out.bent_normal.rgb(x, y);
        const float len = glm::length(v);
        if (len > 0.0f) out.bent_normal.set_rgb(x, y, Color(v / len));
      }
  out.seconds = seconds_since(start);
  out.rays = total_rays.load();
  return out;
}

GlobalLineObscurance obscurance_global_lines(const Scene& scene, const RayTracer& tracer,
                                             const atlas::TexelRaster& raster,
                                             const GlobalLineObscuranceOptions& options) {
  if (options.directions < 1 || options.directions > kMaxExtraRays)
    throw Error(fmt::format("global-line obscurance: directions = {} must lie in [1, {}]",
                            options.directions, kMaxExtraRays));
  if (options.lines_per_direction < 1 || options.lines_per_direction > (int64_t{1} << 32))
    throw Error(
        fmt::format("global-line obscurance: lines_per_direction = {} must lie in [1, "
                    "2^32]",
                    options.lines_per_direction));
  if (!(options.obscurance_dmax > 0.0f && std::isfinite(options.obscurance_dmax)))
    throw Error(fmt::format("global-line obscurance: d_max {} must be a finite number > 0",
                            options.obscurance_dmax));
  if (&tracer.scene() != &scene)
    throw Error("global-line obscurance: the ray tracer was built from another scene");
  atlas::check_texel_raster(scene, raster, "global-line obscurance");
  ThreadLimit thread_limit(options.threads);
  const auto start = std::chrono::steady_clock::now();
  const int w = raster.width, h = raster.height;
  GlobalLineObscurance out;
  out.obscurance = Image(w, h, 3);
  out.count = Image(w, h, 1);
  const Bounds3 bounds = tracer.bounds();
  if (bounds.empty()) return out;
  const vec3 centre = bounds.center();
  const float radius = 0.5f * bounds.diagonal() * 1.001f + 1e-6f;
  const float d_max = options.obscurance_dmax;

  // Each direction's contributions (texel, ρ) are kept apart and summed in direction order
  // afterwards, so the result does not depend on scheduling.
  struct Crossing {
    float t;  // position along the line
    vec3 ng;
    int32_t sample;  // raster sample of the crossed texel, −1 for none
  };
  struct Contribution {
    int32_t sample;
    float rho;
  };
  const int64_t directions = options.directions;
  std::vector<std::vector<Contribution>> contributions(static_cast<size_t>(directions));
  std::atomic<int64_t> total_rays{0};
  parallel_for(
      directions,
      [&](int64_t begin, int64_t end) {
        std::vector<Crossing> crossings;
        int64_t rays = 0;
        for (int64_t di = begin; di < end; ++di) {
          if (interrupt_requested()) break;
          std::vector<Contribution>& list = contributions[static_cast<size_t>(di)];
          Rng rng(hash_mix(options.seed, static_cast<uint64_t>(di), 0x6c696e6573ull));
          const vec3 omega = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
          const Frame frame = Frame::from_normal(omega);
          for (int64_t line = 0; line < options.lines_per_direction; ++line) {
            const vec2 disc = sample_concentric_disk(vec2(rng.next_float(), rng.next_float()));
            const vec3 origin =
                centre + radius * (disc.x * frame.t + disc.y * frame.b) - radius * omega;
            crossings.clear();
            // Walk the line: every crossing in order, placed by its projection on the line.
            Ray ray{origin, omega, 0.0f, 2.0f * radius};
            for (int guard = 0; guard < 4096; ++guard) {
              Hit hit;
              ++rays;
              if (!tracer.intersect(ray, &hit)) break;
              const SurfaceInteraction si = tracer.interaction(ray, hit);
              const Mesh& mesh = scene.meshes[size_t(scene.instances[hit.instance].mesh)];
              int32_t sample = -1;  // only meshes with light-map coordinates own texels
              if (!mesh.uv1.empty()) {
                const int tx = std::clamp(int(si.uv1.x * float(w)), 0, w - 1);
                const int ty = std::clamp(int(si.uv1.y * float(h)), 0, h - 1);
                sample = raster.at(tx, ty);
              }
              crossings.push_back({glm::dot(si.p - origin, omega), si.ng, sample});
              ray.origin = offset_ray_origin(si.p, si.ng, omega);
              ray.tmax = 2.0f * radius - glm::dot(ray.origin - origin, omega);
              if (!(ray.tmax > 0.0f)) break;
            }
            for (size_t k = 0; k < crossings.size(); ++k) {
              const Crossing& a = crossings[k];
              if (a.sample < 0) continue;
              // The side the surface's front faces along the line: forward → the next
              // crossing, backward → the previous one; none there → open (ρ = 1).
              const bool forward = glm::dot(a.ng, omega) > 0.0f;
              float d = kInf;
              if (forward && k + 1 < crossings.size()) d = crossings[k + 1].t - a.t;
              if (!forward && k > 0) d = a.t - crossings[k - 1].t;
              list.push_back({a.sample, obscurance_transfer(d, d_max)});
            }
          }
        }
        total_rays += rays;
      },
      1);
  if (interrupt_requested()) throw Interrupted{};
  std::vector<double> sum(raster.samples.size(), 0.0), count(raster.samples.size(), 0.0);
  for (const std::vector<Contribution>& list : contributions)
    for (const Contribution& c : list) {
      sum[size_t(c.sample)] += c.rho;
      count[size_t(c.sample)] += 1.0;
    }
  for (size_t i = 0; i < raster.samples.size(); ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    out.count.pixel(s.x, s.y)[0] = float(count[i]);
    if (count[i] > 0.0) out.obscurance.set_rgb(s.x, s.y, Color(float(sum[i] / count[i])));
  }
  out.seconds = seconds_since(start);
  out.rays = total_rays.load();
  return out;
}

}  // namespace illum::bake
