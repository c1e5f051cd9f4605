// `illum-bench prt-point-check`: where a per-texel PRT bake and the path tracer part. For random
// camera hits on flat pixels (bake::pixel_footprints) of a scene lit by one distant light, the
// direct (shadowed) transfer is compared three ways, all in the same units (albedo ×
// (1/π)∫V max(0, n·ω) L_band(ω) dω, channel-summed), L_band being the band-limited light as
// the path tracer is given it (bake::sh_environment_map, looked up as the path tracer does):
//  - relit: what `bake::relight` shows at the hit (the bilinear SHL-map lookup at uv1 · L);
//  - at the hit: the integral at the hit point itself, by `--reference-rays` stratified
//    cosine rays from the point and normals the path tracer uses (what it converges to);
//  - at the taps: the same integral at each of the four bilinear taps' own sample points
//    (the points the bake started its rays from), weighted as the lookup weighs them.
// So relit − at-hit = (relit − taps) + (taps − at-hit): the first is the bake's own error at
// its points (Monte-Carlo noise if the bake is right), the second the representation's
// (where the texel's one point stands for the whole texel, and the lookup's interpolation).
// Hits are classified by what their four taps are: all covered texels of the hit's own plane
// (interior), any tap an uncovered (dilated) texel, or any tap a texel of another plane or
// instance (a chart border packed against another chart, or a texel straddling a crease).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/baked/prt_file.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/core/rng.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/render/material_eval.h"
#include "illum/scene/environment.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

// The band-limited light as the path tracer sees it: the positive part of the written-back
// map minus the negative part (bench_prt_vs_path.cpp renders them apart and subtracts).
struct BandLimitedLight {
  Environment positive, negative;
  Color operator()(const vec3& dir) const {
    return environment_radiance(positive, dir) - environment_radiance(negative, dir);
  }
};

BandLimitedLight band_limited(const bake::ShLight& sh) {
  BandLimitedLight out;
  out.positive.radiance = bake::sh_environment_map(sh, 512);
  out.negative.radiance = out.positive.radiance;
  for (size_t i = 0; i < out.positive.radiance.data().size(); ++i) {
    float& p = out.positive.radiance.data()[i];
    out.negative.radiance.data()[i] = std::max(-p, 0.0f);
    p = std::max(p, 0.0f);
  }
  return out;
}

struct Estimate {
  double mean = 0.0, variance_of_mean = 0.0;
};

// (1/π)∫ V max(0, n·ω) L(ω) dω over directions above the geometric plane too, from `p`, by
// n_side² jittered-stratified cosine samples about n (pdf cos/π: each unoccluded ray weighs
// L(ω)); rays leave as the bake's and the path tracer's do (offset_ray_origin).
Estimate direct_integral(const RayTracer& tracer, const BandLimitedLight& light, const vec3& p,
                         const vec3& n, const vec3& ng, int n_side, Rng& rng) {
  const Frame frame = Frame::from_normal(n);
  double sum = 0.0, sum2 = 0.0;
  const int count = n_side * n_side;
  for (int k = 0; k < count; ++k) {
    const vec2 u((float(k % n_side) + rng.next_float()) / float(n_side),
                 (float(k / n_side) + rng.next_float()) / float(n_side));
    const vec3 dir = frame.to_world(sample_cosine_hemisphere(u));
    double v = 0.0;
    if (glm::dot(dir, ng) > 0.0f) {
      const Ray ray{offset_ray_origin(p, ng, dir), dir, 0.0f, kInf};
      if (!tracer.occluded(ray)) {
        const Color l = light(dir);
        v = double(l.x) + double(l.y) + double(l.z);
      }
    }
    sum += v;
    sum2 += v * v;
  }
  Estimate e;
  e.mean = sum / count;
  // Stratification makes this an upper bound of the variance of the mean.
  e.variance_of_mean = std::max(0.0, sum2 / count - e.mean * e.mean) / count;
  return e;
}

int ref_side_of(int rays) {
  return std::max(1, int(std::lround(std::sqrt(double(rays)))));
}

double transfer_dot(const float* t, const bake::ShLight& light) {
  double sum = 0.0;
  for (size_t i = 0; i < light.coefficients.size(); ++i)
    for (int c = 0; c < 3; ++c)
      sum += double(t[i * 3 + size_t(c)]) * double(light.coefficients[i][c]);
  return sum;
}

enum HitClass { kInterior, kUncoveredTap, kForeignTap, kClassCount };
const char* const kClassNames[kClassCount] = {"interior", "uncovered tap", "other-plane tap"};

struct HitRecord {
  int cls = kInterior;
  double albedo = 0.0;  // channel mean, for reporting only
  double relit = 0.0, at_hit = 0.0, at_hit_var = 0.0, taps = 0.0, taps_var = 0.0;
  bool any_tap_centre_outside = false;
};

}  // namespace

int run_prt_point_check(SuiteArgs args) {
  CLI::App app("Direct PRT transfer at its texels vs the integral at camera hits",
               "illum-bench prt-point-check");
  std::string scene_path = "data/scenes/cornell-opening/cornell-opening.illum.json", env_path,
              json_path;
  std::string sun;
  int resolution = 512, bands = 6, bake_spp = 64, width = 96, height = 64, points = 2000,
      reference_rays = 4096, tap_rays = 1024, threads = 0;
  bool stitch = true;
  uint64_t seed = 1, bake_seed = 0;
  int texel_count = 0;
  std::vector<std::string> pixels;
  app.add_option("--scene", scene_path, "scene (its own lights and emission are removed)");
  app.add_option("--env", env_path, "an equirectangular HDR: the light");
  app.add_option("--sun", sun, "X,Y,Z,E: a sun instead of --env");
  app.add_option("--resolution", resolution, "atlas side")->check(CLI::Range(16, 4096));
  app.add_option("--bands", bands, "SH bands")
      ->check(CLI::Range(bake::kMinPrtBands, bake::kMaxPrtBands));
  app.add_option("--bake-spp", bake_spp, "transfer rays a texel")->check(CLI::Range(1, 1 << 16));
  app.add_option("--width", width, "image width (hits are drawn from its flat pixels)")
      ->check(CLI::Range(8, 4096));
  app.add_option("--height", height, "image height")->check(CLI::Range(8, 4096));
  app.add_option("--points", points, "camera hits compared")->check(CLI::Range(1, 1 << 22));
  app.add_option("--reference-rays", reference_rays, "rays for the integral at a hit")
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--tap-rays", tap_rays, "rays for the integral at a tap's point")
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--stitch", stitch, "stitch the SHL-map's seams as the CLI's bake does");
  app.add_option("--threads", threads, "worker threads (0: all)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", seed, "seed of the hits and the references");
  app.add_option("--bake-seed", bake_seed, "seed of the bake (0: --seed)");
  app.add_option("--texels", texel_count,
                 "also compare this many random covered texels at their own points");
  app.add_option("--pixel", pixels, "X,Y: print this pixel's hit and taps (repeatable)");
  app.add_option("--json", json_path, "write the figures here");
  if (!parse_args(app, args)) return 0;
  if (env_path.empty() == sun.empty()) throw Error("prt-point-check: give one of --env and --sun");
  check_output_folder(json_path);
  ThreadLimit limit(threads);

  Scene scene = load_scene(scene_path);
  for (Material& m : scene.materials) m.emission = Color(0.0f);
  scene.lights.clear();
  scene.environment.reset();
  bake::ShLight sh;
  if (!env_path.empty()) {
    Environment env;
    env.path = env_path;
    env.radiance = read_image(env_path, false);
    sh = bake::environment_light(bands, env);
  } else {
    float v[4];
    if (std::sscanf(sun.c_str(), "%f,%f,%f,%f", &v[0], &v[1], &v[2], &v[3]) != 4)
      throw Error(fmt::format("--sun '{}': expected X,Y,Z,E", sun));
    sh = bake::sun_light(bands, vec3(v[0], v[1], v[2]), Color(v[3]));
  }
  const BandLimitedLight light = band_limited(sh);

  atlas::make_meshes_unique(scene);
  atlas::AtlasOptions atlas_options;
  atlas_options.resolution = resolution;
  const atlas::Atlas atlas = atlas::build_atlas(scene, atlas_options);
  atlas::apply_atlas(scene, atlas);
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);
  bake::PrtBakeOptions bake_options =
      bake::PrtBakeOptions::from_params(Params({{"bands", bands},
                                                {"mode", "shadowed"},
                                                {"spp", bake_spp},
                                                {"seed", bake_seed ? bake_seed : seed},
                                                {"stitch", stitch}},
                                               "prt-point-check"));
  bake_options.progress = false;
  bake_options.vertices = false;
  const bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, bake_options);
  const bake::TransferMap& map = baked.texel_transfer;
  std::printf("bake: %zu texels, atlas %dx%d, %d rays a texel, %.2f s, stitch %s\n", baked.texels,
              map.width, map.height, bake_spp, baked.seconds, stitch ? "on" : "off");

  if (texel_count > 0) {
    // Texels drawn uniformly: the bake's value against the integral at its own point.
    const size_t texels_compared = static_cast<size_t>(texel_count);
    std::vector<double> bake_value(texels_compared), reference(texels_compared),
        reference_var(texels_compared);
    const int side = std::max(1, int(std::lround(std::sqrt(double(tap_rays)))));
    parallel_for(
        int64_t(texel_count),
        [&](int64_t begin, int64_t end) {
          for (int64_t k = begin; k < end; ++k) {
            Rng rng(hash_mix(seed, 0x746578656cull, uint64_t(k)));
            const size_t s = std::min(raster.samples.size() - 1,
                                      size_t(rng.next_float() * float(raster.samples.size())));
            const atlas::TexelSample& ts = raster.samples[s];
            bake_value[size_t(k)] = transfer_dot(map.pixel(ts.x, ts.y), sh);
            const Estimate e = direct_integral(tracer, light, ts.position, ts.normal,
                                               ts.geometric_normal, side, rng);
            reference[size_t(k)] = e.mean;
            reference_var[size_t(k)] = e.variance_of_mean;
          }
        },
        16);
    double sb = 0, sr = 0, sd = 0, sd2 = 0, below = 0, above = 0;
    for (int k = 0; k < texel_count; ++k) {
      const double d = bake_value[size_t(k)] - reference[size_t(k)];
      sb += bake_value[size_t(k)];
      sr += reference[size_t(k)];
      sd += d;
      sd2 += d * d;
      below += d < 0 ? 1 : 0;
      above += d > 0 ? 1 : 0;
    }
    const double n = texel_count, mean = sr / n;
    std::printf(
        "texels %d: mean reference %.4g, bake %.4g: bake-reference %+.4f ± %.4f (relative); "
        "below %.1f %%, above %.1f %%\n",
        texel_count, mean, sb / n, sd / n / mean,
        std::sqrt(std::max(0.0, sd2 / n - (sd / n) * (sd / n)) / n) / mean, 100.0 * below / n,
        100.0 * above / n);
  }

  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  const bake::Seams seams =
      pixels.empty() ? bake::Seams{} : bake::find_seams(scene, map.width, map.height);
  if (!pixels.empty())
    std::printf("seams: %lld edges (%lld within an instance), %lld coplanar pairs\n",
                (long long)seams.edges, (long long)seams.within_instance,
                (long long)seams.coplanar_pairs);
  for (const std::string& spec : pixels) {
    // A pixel's centre: its hit, the four taps and what each stands for.
    int px = 0, py = 0;
    if (std::sscanf(spec.c_str(), "%d,%d", &px, &py) != 2)
      throw Error(fmt::format("--pixel '{}': expected X,Y", spec));
    const Ray ray = camera.generate_ray(float(px) + 0.5f, float(py) + 0.5f, width, height);
    Hit hit;
    if (!tracer.intersect(ray, &hit)) {
      std::printf("pixel %d,%d: no hit\n", px, py);
      continue;
    }
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    Rng rng(hash_mix(seed, uint64_t(px), uint64_t(py)));
    const Estimate e =
        direct_integral(tracer, light, si.p, si.ns, si.ng, ref_side_of(reference_rays), rng);
    std::printf(
        "pixel %d,%d: instance %u '%s' p (%.3f %.3f %.3f) ng (%.3f %.3f %.3f) uv1 texel (%.2f "
        "%.2f): at hit %.4g ± %.2g\n",
        px, py, hit.instance, scene.instances[hit.instance].name.c_str(), si.p.x, si.p.y, si.p.z,
        si.ng.x, si.ng.y, si.ng.z, si.uv1.x * map.width, si.uv1.y * map.height, e.mean,
        std::sqrt(e.variance_of_mean));
    // Seam samples within 1.5 texels of the hit's lookup, and what lies on their other side.
    const vec2 at(si.uv1.x * float(map.width), si.uv1.y * float(map.height));
    int listed = 0;
    for (const bake::SeamSample& seam : seams.samples)
      for (int side = 0; side < 2 && listed < 6; ++side) {
        if (glm::length(seam.side[side] - at) > 1.5f) continue;
        const vec2 other = seam.side[1 - side];
        const int ox = std::clamp(int(other.x), 0, map.width - 1);
        const int oy = std::clamp(int(other.y), 0, map.height - 1);
        const int32_t k = raster.at(ox, oy);
        if (k < 0) {
          std::printf("  seam (%.2f %.2f) ~ (%.2f %.2f): uncovered there, baked %.4g\n",
                      seam.side[side].x, seam.side[side].y, other.x, other.y,
                      transfer_dot(map.pixel(ox, oy), sh));
        } else {
          const atlas::TexelSample& ts = raster.samples[size_t(k)];
          std::printf(
              "  seam (%.2f %.2f) ~ (%.2f %.2f): instance %d '%s' p (%.3f %.3f %.3f) "
              "n (%.3f %.3f %.3f), baked %.4g\n",
              seam.side[side].x, seam.side[side].y, other.x, other.y, ts.instance,
              scene.instances[size_t(ts.instance)].name.c_str(), ts.position.x, ts.position.y,
              ts.position.z, ts.normal.x, ts.normal.y, ts.normal.z,
              transfer_dot(map.pixel(ox, oy), sh));
        }
        ++listed;
      }
    const float u = si.uv1.x * float(map.width) - 0.5f, v = si.uv1.y * float(map.height) - 0.5f;
    const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
    for (int t = 0; t < 4; ++t) {
      const int x = std::clamp(x0 + (t & 1), 0, map.width - 1);
      const int y = std::clamp(y0 + (t >> 1), 0, map.height - 1);
      const double w = double((t & 1) ? u - float(x0) : 1.0f - (u - float(x0))) *
                       double((t >> 1) ? v - float(y0) : 1.0f - (v - float(y0)));
      const int32_t k = raster.at(x, y);
      const double tap_value = transfer_dot(map.pixel(x, y), sh);
      if (k < 0) {
        std::printf("  tap (%d %d) w %.2f: uncovered (dilated), baked %.4g\n", x, y, w, tap_value);
        continue;
      }
      const atlas::TexelSample& ts = raster.samples[size_t(k)];
      const Estimate te = direct_integral(tracer, light, ts.position, ts.normal,
                                          ts.geometric_normal, ref_side_of(tap_rays), rng);
      std::printf(
          "  tap (%d %d) w %.2f: instance %d '%s' tri %d, centre %s, p (%.3f %.3f %.3f) "
          "ng (%.3f %.3f %.3f), %.3f m from the hit: baked %.4g, at its point %.4g\n",
          x, y, w, ts.instance, scene.instances[size_t(ts.instance)].name.c_str(), ts.triangle,
          ts.centre_inside ? "inside" : "OUTSIDE", ts.position.x, ts.position.y, ts.position.z,
          ts.geometric_normal.x, ts.geometric_normal.y, ts.geometric_normal.z,
          glm::length(ts.position - si.p), tap_value, te.mean);
    }
  }
  const std::vector<bake::PixelFootprint> footprints =
      bake::pixel_footprints(tracer, camera, width, height);
  std::vector<int> flat;
  for (size_t i = 0; i < footprints.size(); ++i)
    if (footprints[i] == bake::PixelFootprint::kFlat) flat.push_back(int(i));
  if (flat.empty()) throw Error("prt-point-check: no flat pixel");

  const int ref_side = std::max(1, int(std::lround(std::sqrt(double(reference_rays)))));
  const int tap_side = std::max(1, int(std::lround(std::sqrt(double(tap_rays)))));
  std::vector<HitRecord> hits(static_cast<size_t>(points));
  parallel_for(
      int64_t(points),
      [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k) {
          Rng rng(hash_mix(seed, 0x706f696e74ull, uint64_t(k)));
          HitRecord& r = hits[size_t(k)];
          const int pixel = flat[std::min(flat.size() - 1, size_t(rng.next_float() * flat.size()))];
          const float fx = rng.next_float(), fy = rng.next_float();
          const Ray ray = camera.generate_ray(float(pixel % width) + fx, float(pixel / width) + fy,
                                              width, height);
          Hit hit;
          if (!tracer.intersect(ray, &hit)) continue;  // cannot happen on a flat pixel
          const SurfaceInteraction si = tracer.interaction(ray, hit);
          const Color albedo = material_albedo(scene, interaction_material(scene, si), si.uv0);
          r.albedo = (double(albedo.x) + albedo.y + albedo.z) / 3.0;
          // Everything below is per unit albedo (grey transfer): the albedo multiplies all
          // three sides alike, so weighting it in would only reweigh hits.
          const Estimate e = direct_integral(tracer, light, si.p, si.ns, si.ng, ref_side, rng);
          r.at_hit = e.mean;
          r.at_hit_var = e.variance_of_mean;
          const float u = si.uv1.x * float(map.width) - 0.5f;
          const float v = si.uv1.y * float(map.height) - 0.5f;
          const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
          const float ax = u - float(x0), ay = v - float(y0);
          for (int t = 0; t < 4; ++t) {
            const int x = std::clamp(x0 + (t & 1), 0, map.width - 1);
            const int y = std::clamp(y0 + (t >> 1), 0, map.height - 1);
            const double w = double((t & 1) ? ax : 1.0f - ax) * double((t >> 1) ? ay : 1.0f - ay);
            if (w == 0.0) continue;
            r.relit += w * transfer_dot(map.pixel(x, y), sh);
            const int32_t s = raster.at(x, y);
            if (s < 0) {
              r.cls = std::max(r.cls, int(kUncoveredTap));
              // An uncovered texel holds a mean of its neighbours: its "point" is not
              // defined; the hit's own integral stands in.
              r.taps += w * e.mean;
              continue;
            }
            const atlas::TexelSample& ts = raster.samples[size_t(s)];
            if (ts.instance != int(hit.instance) || glm::dot(ts.geometric_normal, si.ng) < 0.999f)
              r.cls = int(kForeignTap);
            r.any_tap_centre_outside = r.any_tap_centre_outside || !ts.centre_inside;
            const Estimate te = direct_integral(tracer, light, ts.position, ts.normal,
                                                ts.geometric_normal, tap_side, rng);
            r.taps += w * te.mean;
            r.taps_var += w * w * te.variance_of_mean;
          }
        }
      },
      8);

  nlohmann::json out = {{"suite", "prt-point-check"},
                        {"scene", scene_path},
                        {"light", env_path.empty() ? "sun " + sun : "env " + env_path},
                        {"resolution", resolution},
                        {"bands", bands},
                        {"bake_spp", bake_spp},
                        {"stitch", stitch},
                        {"image", {width, height}},
                        {"points", points},
                        {"classes", nlohmann::json::array()}};
  // Per class and over all: relative biases (to the mean at-hit value) of relit − at-hit,
  // relit − taps (the bake at its points) and taps − at-hit (the representation), with the
  // standard error of each mean from the spread over hits.
  const auto report = [&](const char* name, auto&& keep) {
    double n = 0, sum_hit = 0;
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    size_t outside3 = 0, centre_outside = 0;
    for (const HitRecord& r : hits) {
      if (!keep(r)) continue;
      const double d[3] = {r.relit - r.at_hit, r.relit - r.taps, r.taps - r.at_hit};
      for (int i = 0; i < 3; ++i) s[i] += d[i], s2[i] += d[i] * d[i];
      // The bake's noise is not in this σ (its rays are few): the taps' and the hit's are.
      const double sigma = std::sqrt(r.at_hit_var + r.taps_var);
      if (std::abs(d[2]) > 3.0 * sigma) ++outside3;
      centre_outside += r.any_tap_centre_outside ? 1 : 0;
      sum_hit += r.at_hit;
      ++n;
    }
    if (n == 0) return;
    const double mean = sum_hit / n;
    double bias[3], se[3];
    for (int i = 0; i < 3; ++i) {
      bias[i] = s[i] / n / mean;
      se[i] = std::sqrt(std::max(0.0, s2[i] / n - (s[i] / n) * (s[i] / n)) / n) / mean;
    }
    std::printf(
        "%-16s %6.0f hits (%5.1f %%), mean at-hit %.4g: relit-hit %+.4f ± %.4f, "
        "relit-taps (bake) %+.4f ± %.4f, taps-hit (representation) %+.4f ± %.4f; "
        "taps-hit beyond 3σ %.1f %%; a tap's centre outside its triangle %.1f %%\n",
        name, n, 100.0 * n / double(hits.size()), mean, bias[0], se[0], bias[1], se[1], bias[2],
        se[2], 100.0 * double(outside3) / n, 100.0 * double(centre_outside) / n);
    out["classes"].push_back({{"class", name},
                              {"hits", n},
                              {"mean_at_hit", mean},
                              {"relit_minus_hit", bias[0]},
                              {"relit_minus_hit_se", se[0]},
                              {"relit_minus_taps", bias[1]},
                              {"relit_minus_taps_se", se[1]},
                              {"taps_minus_hit", bias[2]},
                              {"taps_minus_hit_se", se[2]},
                              {"taps_minus_hit_beyond_3_sigma", double(outside3) / n},
                              {"tap_centre_outside", double(centre_outside) / n}});
  };
  report("all", [](const HitRecord&) { return true; });
  for (int c = 0; c < kClassCount; ++c)
    report(kClassNames[c], [c](const HitRecord& r) { return r.cls == c; });
  report("centre outside", [](const HitRecord& r) { return r.any_tap_centre_outside; });
  report("interior, inside",
         [](const HitRecord& r) { return r.cls == kInterior && !r.any_tap_centre_outside; });
  std::fflush(stdout);
  if (!json_path.empty()) write_json(json_path, out);
  return 0;
}

}  // namespace illum::bench
