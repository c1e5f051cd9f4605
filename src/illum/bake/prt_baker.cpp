#include "illum/bake/prt_baker.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>

#include "illum/bake/lightmap_seams.h"
#include "illum/bake/prt_normal_map.h"
#include "illum/bake/prt_shooting.h"
#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/render/material_eval.h"

namespace illum::bake {

namespace {

constexpr int kMaxSpp = 1 << 20;
constexpr int kMaxDilate = 64;
constexpr int kMaxRounds = 10000;
constexpr int kMaxNormalMapSamples = 4096;
// A point whose normal-map samples all lie within this of its normal (cos, ~0.08°) is baked
// as without a map: the surface test is then empty and the closed form exact.
constexpr float kFlatNormalCos = 1.0f - 1e-6f;
// Seeds of the two point sets differ in their first word, so a vertex and a texel with the
// same numbers never share a sequence.
constexpr uint64_t kVertexStream = 0x7665727465780000ull;
// Folded into a point's second word for the scramble of its normal-map footprint points.
constexpr uint64_t kNormalMapStream = 0x6e6f726d616c0000ull;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A point the transfer is baked at.
struct BakePoint {
  vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f}, geometric_normal{0.0f, 0.0f, 1.0f};
  uint64_t stream_a = 0, stream_b = 0;  // its Sobol' scramble: hash(seed, a, b)
};

vec3 world_point(const Instance& inst, const vec3& p) {
  return vec3(inst.transform * vec4(p, 1.0f));
}

const Material& mesh_material(const Scene& scene, const Mesh& mesh) {
  static const Material kDefault{};
  return mesh.material >= 0 && size_t(mesh.material) < scene.materials.size()
             ? scene.materials[size_t(mesh.material)]
             : kDefault;
}

vec2 interpolate_uv0(const Mesh& mesh, size_t tri, const vec2& b) {
  if (mesh.uv0.size() != mesh.positions.size()) return vec2(0.0f);
  const uint32_t* idx = &mesh.indices[tri * 3];
  return (1.0f - b.x - b.y) * mesh.uv0[idx[0]] + b.x * mesh.uv0[idx[1]] + b.y * mesh.uv0[idx[2]];
}

// Where a vertex's rays start: 1e-3 of the way from the vertex to the mean centroid of its
// triangles. A vertex on a corner or an edge of a closed room lies on the planes of the
// adjacent walls, and rays from there slip out through the crack between them (light
// leaking in, energy leaking out); a point just inside its own triangles does not.
std::vector<vec3> vertex_ray_origins(const Instance& inst, const Mesh& mesh) {
  std::vector<vec3> centroid(mesh.vertex_count(), vec3(0.0f));
  std::vector<int> triangles(mesh.vertex_count(), 0);
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t* idx = &mesh.indices[t * 3];
    const vec3 c =
        (mesh.positions[idx[0]] + mesh.positions[idx[1]] + mesh.positions[idx[2]]) / 3.0f;
    for (int k = 0; k < 3; ++k) {
      centroid[idx[k]] += c;
      ++triangles[idx[k]];
    }
  }
  std::vector<vec3> origin(mesh.vertex_count());
  for (size_t v = 0; v < origin.size(); ++v) {
    const vec3 p = mesh.positions[v];
    const vec3 inside = triangles[v] ? p + 1e-3f * (centroid[v] / float(triangles[v]) - p) : p;
    origin[v] = world_point(inst, inside);
  }
  return origin;
}

// World area of each texel: Σ over the triangles of the uv1 area they cover in it × the
// triangle's world/uv area ratio (exact for the piecewise-linear chart map).
std::vector<float> texel_areas(const Scene& scene, const atlas::TexelRaster& raster) {
  std::vector<double> area(size_t(raster.width) * size_t(raster.height), 0.0);
  const glm::dvec2 size(raster.width, raster.height);
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (mesh.uv1.size() != mesh.positions.size()) continue;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const uint32_t* idx = &mesh.indices[t * 3];
      const vec3 p0 = world_point(inst, mesh.positions[idx[0]]);
      const vec3 p1 = world_point(inst, mesh.positions[idx[1]]);
      const vec3 p2 = world_point(inst, mesh.positions[idx[2]]);
      const double world = 0.5 * double(glm::length(glm::cross(p1 - p0, p2 - p0)));
      glm::dvec2 q[3];
      for (int c = 0; c < 3; ++c) q[c] = glm::dvec2(mesh.uv1[idx[c]]) * size;
      const double uv = 0.5 * std::abs((q[1].x - q[0].x) * (q[2].y - q[0].y) -
                                       (q[2].x - q[0].x) * (q[1].y - q[0].y));
      if (!(uv > 1e-12) || !(world > 0.0)) continue;
      const glm::dvec2 lo = glm::min(q[0], glm::min(q[1], q[2]));
      const glm::dvec2 hi = glm::max(q[0], glm::max(q[1], q[2]));
      const int x0 = std::max(0, int(std::floor(lo.x))), y0 = std::max(0, int(std::floor(lo.y)));
      const int x1 = std::min(raster.width - 1, int(std::floor(hi.x)));
      const int y1 = std::min(raster.height - 1, int(std::floor(hi.y)));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
          area[size_t(y) * size_t(raster.width) + size_t(x)] +=
              atlas::texel_overlap_area(q, x, y) * world / uv;
    }
  }
  return {area.begin(), area.end()};
}

// The direct transfer of a normal-mapped point into sum: the mean over its K perturbed
// normals n′_k of (1/π)∫ V max(n′_k·ω, 0) [n·ω > 0] [n_g·ω > 0] Y_i(ω) dω. The spp rays go in
// K consecutive blocks (block k: cosine-distributed about n′_k), so each block is a run of
// the Sobol' sequence (a net when spp/K is a power of 2) rather than every K-th point, which
// would put each normal's rays in one stratum; a block's rays weigh 1/(K·its size), so the
// normals count alike whether or not K divides spp. Returns the rays traced.
int64_t perturbed_transfer(const RayTracer& tracer, const BakePoint& pt,
                           std::span<const vec3> normals, const PrtBakeOptions& options,
                           std::vector<float>& y, std::vector<double>& sum) {
  const int count = int(y.size());
  const int64_t spp = options.spp;
  const int64_t blocks = std::min<int64_t>(int64_t(normals.size()), spp);
  const bool trace = options.mode != PrtMode::kUnshadowed;
  SobolSampler sampler(hash_mix(options.seed, pt.stream_a, pt.stream_b));
  std::fill(sum.begin(), sum.end(), 0.0);
  int64_t traced = 0;
  for (int64_t block = 0; block < blocks; ++block) {
    const int64_t first = (block * spp + blocks - 1) / blocks;
    const int64_t last = ((block + 1) * spp + blocks - 1) / blocks;
    const double weight = 1.0 / double(blocks * (last - first));
    const Frame frame = Frame::from_normal(normals[size_t(block)]);
    for (int64_t r = first; r < last; ++r) {
      if ((r & 1023) == 1023 && interrupt_requested()) break;
      sampler.start_sample(uint32_t(r));
      const vec3 dir = frame.to_world(sample_cosine_hemisphere(sampler.next_2d()));
      // Below the surface: the large-scale normal and the geometric one (S002 §5.7).
      if (glm::dot(dir, pt.normal) <= 0.0f || glm::dot(dir, pt.geometric_normal) <= 0.0f) continue;
      if (trace) {
        ++traced;
        const Ray ray{offset_ray_origin(pt.position, pt.geometric_normal, dir), dir, 0.0f, kInf};
        if (tracer.occluded(ray)) continue;
      }
      sh::evaluate<float>(options.bands, dir, y);
      for (int i = 0; i < count; ++i) sum[size_t(i)] += weight * double(y[size_t(i)]);
    }
  }
  return traced;
}

// The perturbed normals of point k (prt_normal_map.h) into `normals`; left empty for a
// point without a normal map.
using NormalSamples = std::function<void(size_t point, std::vector<vec3>& normals)>;

// Direct transfer of every point into out ([point][i][rgb], grey): unshadowed in closed
// form, shadowed by cosine-distributed visibility rays; a normal-mapped point by rays
// about each of its perturbed normals in turn (traced unless unshadowed).
void bake_direct(const RayTracer& tracer, std::span<const BakePoint> points,
                 const NormalSamples& normal_samples, const PrtBakeOptions& options,
                 const char* label, std::vector<float>& out, std::atomic<int64_t>& rays) {
  const int count = sh::coefficient_count(options.bands);
  const size_t p = size_t(count) * 3;
  out.assign(points.size() * p, 0.0f);
  const std::vector<double> cosine = sh::clamped_cosine_factors(options.bands);
  Progress progress(label, int64_t(points.size()), options.progress);
  parallel_for(
      int64_t(points.size()),
      [&](int64_t begin, int64_t end) {
        std::vector<float> y(static_cast<size_t>(count));
        std::vector<double> sum(static_cast<size_t>(count));
        std::vector<vec3> normals;
        int64_t traced = 0;
        for (int64_t k = begin; k < end; ++k) {
          if (interrupt_requested()) break;
          const BakePoint& pt = points[size_t(k)];
          float* t = &out[size_t(k) * p];
          normals.clear();
          if (normal_samples) normal_samples(size_t(k), normals);
          if (std::all_of(normals.begin(), normals.end(),
                          [&](const vec3& m) { return glm::dot(m, pt.normal) >= kFlatNormalCos; }))
            normals.clear();
          if (!normals.empty()) {
            traced += perturbed_transfer(tracer, pt, normals, options, y, sum);
            for (int i = 0; i < count; ++i)
              for (int ch = 0; ch < 3; ++ch) t[i * 3 + ch] = float(sum[size_t(i)]);
            continue;
          }
          if (options.mode == PrtMode::kUnshadowed) {
            // (1/π) Λ_l Y_lm(n): the clamped cosine turned towards n (Funk–Hecke).
            const std::vector<double> c =
                sh::zonal_along(options.bands, cosine, glm::dvec3(pt.normal));
            for (int i = 0; i < count; ++i)
              for (int ch = 0; ch < 3; ++ch) t[i * 3 + ch] = float(c[size_t(i)] / kPi);
            continue;
          }
          // pdf cos/π cancels the (1/π) cos of the transfer: each escaping ray weighs Y_i(ω).
          const Frame frame = Frame::from_normal(pt.normal);
          SobolSampler sampler(hash_mix(options.seed, pt.stream_a, pt.stream_b));
          std::fill(sum.begin(), sum.end(), 0.0);
          for (int r = 0; r < options.spp; ++r) {
            if ((r & 1023) == 1023 && interrupt_requested()) break;
            sampler.start_sample(uint32_t(r));
            const vec3 dir = frame.to_world(sample_cosine_hemisphere(sampler.next_2d()));
            if (glm::dot(dir, pt.geometric_normal) <= 0.0f) continue;  // below the surface
            const Ray ray{offset_ray_origin(pt.position, pt.geometric_normal, dir), dir, 0.0f,
                          kInf};
            ++traced;
            if (tracer.occluded(ray)) continue;
            sh::evaluate<float>(options.bands, dir, y);
            for (int i = 0; i < count; ++i) sum[size_t(i)] += double(y[size_t(i)]);
          }
          for (int i = 0; i < count; ++i)
            for (int ch = 0; ch < 3; ++ch)
              t[i * 3 + ch] = float(sum[size_t(i)] / double(options.spp));
        }
        rays += traced;
        progress.advance(end - begin);
      },
      16);
  progress.finish();
  if (interrupt_requested()) throw Interrupted{};
}

}  // namespace

void PrtBakeOptions::validate() const {
  if (bands < kMinPrtBands || bands > kMaxPrtBands)
    throw Error(fmt::format("PRT bake: bands = {} must lie in [{}, {}]", bands, kMinPrtBands,
                            kMaxPrtBands));
  if (spp < 1 || spp > kMaxSpp)
    throw Error(fmt::format("PRT bake: spp = {} must lie in [1, {}]", spp, kMaxSpp));
  if (!(shoot_tolerance >= 1e-6 && shoot_tolerance <= 1.0))
    throw Error(
        fmt::format("PRT bake: shoot_tolerance = {} must lie in [1e-6, 1]", shoot_tolerance));
  if (!(shoot_relative_tolerance >= 1e-6 && shoot_relative_tolerance <= 1.0))
    throw Error(fmt::format("PRT bake: shoot_relative_tolerance = {} must lie in [1e-6, 1]",
                            shoot_relative_tolerance));
  if (max_rounds < 0 || max_rounds > kMaxRounds)
    throw Error(
        fmt::format("PRT bake: max_rounds = {} must lie in [0, {}]", max_rounds, kMaxRounds));
  if (dilate < 0 || dilate > kMaxDilate)
    throw Error(fmt::format("PRT bake: dilate = {} must lie in [0, {}]", dilate, kMaxDilate));
  if (normal_map_samples < 1 || normal_map_samples > kMaxNormalMapSamples)
    throw Error(fmt::format("PRT bake: normal_map_samples = {} must lie in [1, {}]",
                            normal_map_samples, kMaxNormalMapSamples));
  if (threads < 0) throw Error(fmt::format("PRT bake: threads = {} must be ≥ 0", threads));
}

PrtBakeOptions PrtBakeOptions::from_params(const Params& params) {
  PrtBakeOptions o;
  const std::string mode = params.get<std::string>("mode", to_string(o.mode));
  try {
    o.mode = prt_mode_from_string(mode);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", params.where("mode"), e.what()));
  }
  o.bands = params.get_int_in("bands", o.bands, kMinPrtBands, kMaxPrtBands);
  o.spp = params.get_int_in("spp", o.spp, 1, kMaxSpp);
  o.shoot_tolerance =
      double(params.get_float_in("shoot_tolerance", float(o.shoot_tolerance), 1e-6f, 1.0f));
  o.shoot_relative_tolerance = double(params.get_float_in(
      "shoot_relative_tolerance", float(o.shoot_relative_tolerance), 1e-6f, 1.0f));
  o.max_rounds = params.get_int_in("max_rounds", o.max_rounds, 0, kMaxRounds);
  o.dilate = params.get_int_in("dilate", o.dilate, 0, kMaxDilate);
  // As the light-map bakers: off in the struct (the raw transfer), on through files and CLI.
  o.stitch = params.get<bool>("stitch", true);
  o.stitch_coplanar = params.get<bool>("stitch_coplanar", o.stitch_coplanar);
  o.seed = params.get_seed("seed", o.seed);
  o.normal_maps = params.get<bool>("normal_maps", o.normal_maps);
  o.normal_map_samples =
      params.get_int_in("normal_map_samples", o.normal_map_samples, 1, kMaxNormalMapSamples);
  return o;
}

PrtPatches texel_patches(const Scene& scene, const atlas::TexelRaster& raster) {
  PrtPatches out;
  const std::vector<float> area = texel_areas(scene, raster);
  out.patches.resize(raster.samples.size());
  for (size_t k = 0; k < raster.samples.size(); ++k) {
    const atlas::TexelSample& s = raster.samples[k];
    const Mesh& mesh = scene.meshes[size_t(scene.instances[size_t(s.instance)].mesh)];
    out.patches[k] = {s.position, s.normal, s.geometric_normal,
                      area[size_t(s.y) * size_t(raster.width) + size_t(s.x)],
                      material_albedo(scene, mesh_material(scene, mesh),
                                      interpolate_uv0(mesh, size_t(s.triangle), s.barycentric))};
  }
  out.receiver = [&scene, &raster](const Ray& ray, const Hit& hit) {
    TransferReceipt r;
    const Instance& inst = scene.instances[hit.instance];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (mesh.uv1.size() != mesh.positions.size()) return r;
    const uint32_t* idx = &mesh.indices[size_t(hit.primitive) * 3];
    const vec3 p0 = world_point(inst, mesh.positions[idx[0]]);
    const vec3 ng = glm::cross(world_point(inst, mesh.positions[idx[1]]) - p0,
                               world_point(inst, mesh.positions[idx[2]]) - p0);
    const vec2 b = hit.barycentric;
    const vec2 uv =
        (1.0f - b.x - b.y) * mesh.uv1[idx[0]] + b.x * mesh.uv1[idx[1]] + b.y * mesh.uv1[idx[2]];
    const int x = std::clamp(int(uv.x * float(raster.width)), 0, raster.width - 1);
    const int y = std::clamp(int(uv.y * float(raster.height)), 0, raster.height - 1);
    const int32_t k = raster.at(x, y);
    if (k < 0) return r;
    r.back = glm::dot(ng, ray.direction) >= 0.0f;  // against the winding: the back side
    r.count = 1;
    r.patch[0] = k;
    r.weight[0] = 1.0f;
    return r;
  };
  return out;
}

PrtPatches vertex_patches(const Scene& scene) {
  PrtPatches out;
  std::vector<size_t> base(scene.instances.size() + 1, 0);
  for (size_t i = 0; i < scene.instances.size(); ++i)
    base[i + 1] = base[i] + scene.meshes[size_t(scene.instances[i].mesh)].vertex_count();
  out.patches.resize(base.back());
  // A vertex stands for its hat function: a third of each adjacent triangle's area.
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    const Material& material = mesh_material(scene, mesh);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    const std::vector<vec3> origin = vertex_ray_origins(inst, mesh);
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      const vec3 n = glm::normalize(normal_matrix * mesh.normals[v]);
      const vec2 uv0 = mesh.uv0.size() == mesh.positions.size() ? mesh.uv0[v] : vec2(0.0f);
      out.patches[base[i] + v] = {origin[v], n, n, 0.0f, material_albedo(scene, material, uv0)};
    }
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const uint32_t* idx = &mesh.indices[t * 3];
      const vec3 p0 = world_point(inst, mesh.positions[idx[0]]);
      const float third = glm::length(glm::cross(world_point(inst, mesh.positions[idx[1]]) - p0,
                                                 world_point(inst, mesh.positions[idx[2]]) - p0)) /
                          6.0f;
      for (int c = 0; c < 3; ++c) out.patches[base[i] + idx[c]].area += third;
    }
  }
  out.receiver = [&scene, base](const Ray& ray, const Hit& hit) {
    TransferReceipt r;
    const Instance& inst = scene.instances[hit.instance];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    const uint32_t* idx = &mesh.indices[size_t(hit.primitive) * 3];
    const vec3 p0 = world_point(inst, mesh.positions[idx[0]]);
    const vec3 ng = glm::cross(world_point(inst, mesh.positions[idx[1]]) - p0,
                               world_point(inst, mesh.positions[idx[2]]) - p0);
    const vec2 b = hit.barycentric;
    r.back = glm::dot(ng, ray.direction) >= 0.0f;  // against the winding: the back side
    r.count = 3;
    for (int c = 0; c < 3; ++c) r.patch[c] = int32_t(base[hit.instance] + idx[c]);
    r.weight[0] = 1.0f - b.x - b.y;
    r.weight[1] = b.x;
    r.weight[2] = b.y;
    return r;
  };
  return out;
}

namespace {

// The interreflected transfer: the direct `transfer` of the patches that `make_patches`
// builds, shot between them until converged (prt_shooting.h); the shooting's figures go to
// `bake` (its shares and back sides when `keep_shares`).
template <class MakePatches>
void shoot_bounces(const RayTracer& tracer, MakePatches make_patches, int payload,
                   const TransferShootingOptions& shooting, bool keep_shares,
                   std::vector<float>& transfer, std::atomic<int64_t>& rays, PrtBake* bake) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrtPatches set = make_patches();
  const TransferShootingResult shot =
      shoot_transfer(tracer, set.patches, set.receiver, payload, transfer, shooting);
  bake->shoot_rounds += shot.rounds;
  bake->unshot_fraction = std::max(bake->unshot_fraction, shot.unshot_fraction);
  bake->relative_unshot = std::max(bake->relative_unshot, shot.relative_unshot);
  if (keep_shares) {
    bake->shot_shares = shot.shares;
    bake->back_sides = shot.back_sides;
  }
  rays += shot.rays;
  bake->shoot_seconds += seconds_since(t0);
}

// The light-map's seam stitching, per coefficient: E/π = Σ T_i L_i is linear in T, so T's
// lookups agreeing on both sides of a seam makes the relit light-map's agree for every
// lighting. The same matrix for every coefficient; solved a few coefficients at a time,
// which gives the same result (each channel has its own CG) in less memory.
void stitch_transfer(const Scene& scene, const atlas::TexelRaster& raster, bool coplanar,
                     std::vector<Image>& layers, PrtBake* bake) {
  const auto t0 = std::chrono::steady_clock::now();
  const Seams seams = find_seams(scene, raster.width, raster.height, {.coplanar = coplanar});
  constexpr int kCoefficientsPerSolve = 8;
  const int count = int(layers.size());
  for (int first = 0; first < count; first += kCoefficientsPerSolve) {
    const int last = std::min(count, first + kCoefficientsPerSolve);
    std::vector<Image> some(std::make_move_iterator(layers.begin() + first),
                            std::make_move_iterator(layers.begin() + last));
    stitch_seams(seams, raster, some);
    std::move(some.begin(), some.end(), layers.begin() + first);
  }
  bake->seam_edges = seams.edges;
  bake->coplanar_edges = seams.coplanar_pairs;
  bake->stitch_seconds = seconds_since(t0);
}

// Per texel (the SHL-map): the transfer at every raster sample, dilated and stitched.
void bake_texel_transfer(const Scene& scene, const RayTracer& tracer,
                         const atlas::TexelRaster& raster, const PrtBakeOptions& options,
                         const TransferShootingOptions& shooting, std::atomic<int64_t>& rays,
                         PrtBake* bake) {
  const int count = sh::coefficient_count(options.bands);
  const int payload = 3 * count;
  std::vector<BakePoint> points(raster.samples.size());
  for (size_t k = 0; k < points.size(); ++k) {
    const atlas::TexelSample& s = raster.samples[k];
    points[k] = {s.position, s.normal, s.geometric_normal, uint64_t(s.x), uint64_t(s.y)};
  }
  NormalSamples texel_normals;
  if (options.normal_maps)
    texel_normals = [&](size_t k, std::vector<vec3>& normals) {
      texel_normal_samples(
          scene, raster, raster.samples[k], options.normal_map_samples,
          hash_mix(options.seed, points[k].stream_a, points[k].stream_b ^ kNormalMapStream),
          normals);
    };
  std::vector<float> transfer;
  bake_direct(tracer, points, texel_normals, options, "prt texels", transfer, rays);
  if (options.mode == PrtMode::kInterreflected)
    shoot_bounces(
        tracer, [&] { return texel_patches(scene, raster); }, payload, shooting, true, transfer,
        rays, bake);
  bake->texel_transfer = TransferMap(raster.width, raster.height, payload);
  // Dilated one coefficient (an RGB image) at a time: core Images hold up to 4 channels.
  std::vector<Image> layers;
  for (int i = 0; i < count; ++i) {
    Image layer(raster.width, raster.height, 3);
    for (size_t k = 0; k < points.size(); ++k)
      std::copy_n(&transfer[k * size_t(payload) + size_t(i) * 3], 3,
                  layer.pixel(raster.samples[k].x, raster.samples[k].y));
    atlas::dilate(layer, raster, options.dilate);
    layers.push_back(std::move(layer));
  }
  if (options.stitch) stitch_transfer(scene, raster, options.stitch_coplanar, layers, bake);
  for (int i = 0; i < count; ++i)
    for (int y = 0; y < raster.height; ++y)
      for (int x = 0; x < raster.width; ++x)
        std::copy_n(layers[size_t(i)].pixel(x, y), 3,
                    bake->texel_transfer.pixel(x, y) + size_t(i) * 3);
  bake->texels = points.size();
}

// Per vertex: the transfer at every vertex of every instance, from just inside its triangles.
void bake_vertex_transfer(const Scene& scene, const RayTracer& tracer,
                          const PrtBakeOptions& options, const TransferShootingOptions& shooting,
                          std::atomic<int64_t>& rays, PrtBake* bake) {
  const int payload = 3 * sh::coefficient_count(options.bands);
  std::vector<size_t> base(scene.instances.size() + 1, 0);
  for (size_t i = 0; i < scene.instances.size(); ++i)
    base[i + 1] = base[i] + scene.meshes[size_t(scene.instances[i].mesh)].vertex_count();
  std::vector<BakePoint> points(base.back());
  std::vector<int> point_instance(base.back());
  std::vector<VertexRing> rings(options.normal_maps ? scene.instances.size() : 0);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    std::fill(point_instance.begin() + std::ptrdiff_t(base[i]),
              point_instance.begin() + std::ptrdiff_t(base[i + 1]), int(i));
    if (options.normal_maps) rings[i] = vertex_ring(scene.meshes[size_t(scene.instances[i].mesh)]);
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    const std::vector<vec3> origin = vertex_ray_origins(inst, mesh);
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      const vec3 n = glm::normalize(normal_matrix * mesh.normals[v]);
      points[base[i] + v] = {origin[v], n, n, kVertexStream ^ i, v};
    }
  }
  NormalSamples vertex_normals;
  if (options.normal_maps)
    vertex_normals = [&](size_t k, std::vector<vec3>& normals) {
      const int i = point_instance[k];
      vertex_normal_samples(
          scene, i, uint32_t(k - base[size_t(i)]), points[k].normal, rings[size_t(i)],
          options.normal_map_samples,
          hash_mix(options.seed, points[k].stream_a, points[k].stream_b ^ kNormalMapStream),
          normals);
    };
  std::vector<float> transfer;
  bake_direct(tracer, points, vertex_normals, options, "prt vertices", transfer, rays);
  if (options.mode == PrtMode::kInterreflected)
    shoot_bounces(
        tracer, [&] { return vertex_patches(scene); }, payload, shooting, !options.texels, transfer,
        rays, bake);
  bake->vertex_transfer.resize(scene.instances.size());
  for (size_t i = 0; i < scene.instances.size(); ++i)
    bake->vertex_transfer[i].assign(
        transfer.begin() + std::ptrdiff_t(base[i] * size_t(payload)),
        transfer.begin() + std::ptrdiff_t(base[i + 1] * size_t(payload)));
  bake->vertices = points.size();
}

}  // namespace

PrtBake bake_prt(const Scene& scene, const RayTracer& tracer, const atlas::TexelRaster& raster,
                 const PrtBakeOptions& options) {
  options.validate();
  if (&tracer.scene() != &scene)
    throw Error("PRT bake: the ray tracer was built from another scene");
  atlas::check_texel_raster(scene, raster, "PRT bake");
  for (const Mesh& mesh : scene.meshes)
    if (mesh.normals.size() != mesh.positions.size())
      throw Error(fmt::format("PRT bake: mesh '{}' has {} normals for {} vertices", mesh.name,
                              mesh.normals.size(), mesh.positions.size()));
  ThreadLimit thread_limit(options.threads);
  const auto start = std::chrono::steady_clock::now();

  PrtBake bake;
  bake.bands = options.bands;
  bake.mode = options.mode;
  std::atomic<int64_t> rays{0};
  TransferShootingOptions shooting;
  shooting.rays = options.spp;
  shooting.tolerance = options.shoot_tolerance;
  shooting.relative_tolerance = options.shoot_relative_tolerance;
  shooting.max_rounds = options.max_rounds;
  shooting.seed = hash_mix(options.seed, 0x73686f6f74ull);
  if (options.texels) bake_texel_transfer(scene, tracer, raster, options, shooting, rays, &bake);
  if (options.vertices) bake_vertex_transfer(scene, tracer, options, shooting, rays, &bake);
  bake.rays = rays.load();
  bake.seconds = seconds_since(start);
  return bake;
}

nlohmann::json shooting_record(const PrtBake& baked) {
  const TransferShotShares& s = baked.shot_shares;
  return {{"shoot_rounds", baked.shoot_rounds},
          {"unshot_fraction", baked.unshot_fraction},
          {"relative_unshot", baked.relative_unshot},
          {"shot_shares",
           {{"front", s.front},
            {"back", s.back},
            {"escaped", s.escaped},
            {"lost", s.lost},
            {"below", s.below}}},
          {"back_sides", baked.back_sides}};
}

}  // namespace illum::bake
