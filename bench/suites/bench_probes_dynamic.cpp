// `illum-bench probes-dynamic`: a dynamic object lit by the probe volume in the real-time
// renderer (realtime/probe_volume.h), per pixel and with the per-instance ambient-cube
// fallback, against the path tracer rendering the same scene with the object as an ordinary
// mesh (docs/probes.md "Dynamic objects in the real-time renderer").
//
// One probe bake of the scene's static part; the real-time frames are drawn without the
// scene's lights, so the object shows only what the probes give it (their irradiance holds
// direct and bounced light, as the path tracer's). Compared over the object's pixels a camera
// ray hits (silhouette pixels, whose 8 neighbours do not all see it, left out): the luminance
// error |R − P| per pixel relative to the mean path-traced luminance P̄ over those pixels
// (mean, median, 90th percentile; relative to P̄, not to each pixel's P, because the side
// facing the box's open front is nearly black and per-pixel ratios there say nothing) and the
// signed mean (R − P)/P̄ (the bias), for both lookups. The path tracer's own noise is in these
// numbers; its standard error per pixel is printed too (from two half-spp runs: |a − b|/2
// estimates σ of their mean).
//
// With --images DIR: probes_dynamic_compare.png (crops around the object: path tracer,
// per-pixel lookup, per-instance cube; outside the object every panel shows the path-traced
// image darkened, for context) and probes_dynamic_error.png (|R − P| / P̄ as a heat map,
// black → red → yellow → white at 100 %, per pixel and per instance).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "illum/bake/probe_baker.h"
#include "illum/bake/probe_lookup.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/core/tonemap.h"
#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct ErrorStats {
  double mean = 0.0, median = 0.0, p90 = 0.0, signed_mean = 0.0;
};

ErrorStats error_stats(std::vector<double> relative, double signed_sum) {
  ErrorStats s;
  if (relative.empty()) return s;
  for (double e : relative) s.mean += e;
  s.mean /= double(relative.size());
  s.signed_mean = signed_sum / double(relative.size());
  std::sort(relative.begin(), relative.end());
  s.median = relative[relative.size() / 2];
  s.p90 = relative[std::min(relative.size() - 1, relative.size() * 9 / 10)];
  return s;
}

// |R − P| / P on a black → red → yellow → white ramp reaching white at `full`.
Color heat(double e, double full) {
  const float v = float(std::clamp(e / full, 0.0, 1.0)) * 3.0f;
  return Color(std::min(v, 1.0f), std::clamp(v - 1.0f, 0.0f, 1.0f),
               std::clamp(v - 2.0f, 0.0f, 1.0f));
}

}  // namespace

int run_probes_dynamic(SuiteArgs args) {
  std::string scene_path = data_dir() + "/scenes/cornell-dynamic/cornell-dynamic.illum.json";
  int spp = 256, path_spp = 1024, size = 256, threads = 0;
  float spacing = 0.05f;
  uint64_t seed = 1;
  std::string json_path, images;
  CLI::App app("a dynamic object lit by the probe volume vs the path tracer",
               "illum-bench probes-dynamic");
  app.add_option("--scene", scene_path, "scene with instances marked dynamic")
      ->capture_default_str();
  app.add_option("--spacing", spacing, "metres between probes")
      ->check(CLI::Range(1e-4f, 1e6f))
      ->capture_default_str();
  app.add_option("--spp", spp, "sphere samples per probe")
      ->check(CLI::Range(1, bake::kMaxProbeSpp))
      ->capture_default_str();
  app.add_option("--path-spp", path_spp, "path tracer samples per pixel (even)")
      ->check(CLI::Range(2, 1 << 20))
      ->capture_default_str();
  app.add_option("--size", size, "image width and height")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  app.add_option("--seed", seed, "bake and path tracer seed")->capture_default_str();
  app.add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--images", images, "folder for probes_dynamic_compare.png and _error.png");
  app.add_option("--json", json_path, "write the results to this JSON file");
  if (!parse_args(app, args)) return 0;
  ThreadLimit limit(threads);

  const Scene scene = load_scene(scene_path);
  if (!scene.camera) throw Error(fmt::format("{}: the scene has no camera", scene_path));
  const std::vector<int> dynamic = bake::dynamic_instances(scene);
  if (dynamic.empty())
    throw Error(fmt::format("{}: no instance is marked \"dynamic\": true", scene_path));

  // The probes, baked for the static part.
  const Scene statics = bake::static_part(scene);
  const RayTracer static_tracer(statics);
  bake::ProbeBakeOptions options;
  options.spacing = spacing;
  options.spp = spp;
  options.seed = seed;
  options.threads = threads;
  options.progress = false;
  auto t0 = std::chrono::steady_clock::now();
  const bake::ProbeBake baked = bake::bake_probes(statics, static_tracer, options);
  const double bake_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  realtime::ProbeVolume volume;
  volume.size = baked.grid.size;
  volume.origin = baked.grid.origin;
  volume.spacing = vec3(baked.grid.spacing);
  volume.probes = bake::probe_volume_data(baked.probes);
  volume.instances = dynamic;

  // The real-time frames, lit by the probes alone.
  Scene unlit = scene;
  unlit.lights.clear();
  gpu::Context context{gpu::ContextOptions{}};
  auto frame = [&](const std::string& lookup) {
    realtime::RenderSettings o;
    o.width = o.height = size;
    o.shadows = "none";
    o.set("baked.probe_lookup", lookup);
    realtime::Renderer r(context, unlit, o);
    r.set_probe_volume(volume);
    r.render(*unlit.camera);
    return r.hdr();
  };
  const Image per_pixel = frame("pixel"), per_instance = frame("instance");

  // The path tracer, two half runs (their mean the reference, their difference its noise).
  const RayTracer tracer(scene);
  RenderOptions render;
  render.width = render.height = size;
  render.spp = path_spp / 2;
  render.progress = false;
  t0 = std::chrono::steady_clock::now();
  const auto integrator =
      Integrator::create("path", Params(nlohmann::json::object(), "probes-dynamic"));
  render.seed = seed;
  const Image path_a = integrator->render(tracer, *scene.camera, render);
  render.seed = seed + 1;
  const Image path_b = integrator->render(tracer, *scene.camera, render);
  const double path_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Which pixels show a dynamic object, away from its silhouette.
  std::vector<int> shows(size_t(size) * size_t(size), -1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      Hit hit;
      if (tracer.intersect(scene.camera->generate_ray(x + 0.5f, y + 0.5f, size, size), &hit))
        shows[size_t(y) * size_t(size) + size_t(x)] = int(hit.instance);
    }
  auto is_dynamic = [&](int x, int y) {
    const int i = shows[size_t(y) * size_t(size) + size_t(x)];
    return std::find(dynamic.begin(), dynamic.end(), i) != dynamic.end();
  };
  auto interior = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= size || yy >= size || !is_dynamic(xx, yy)) return false;
      }
    return true;
  };

  Image reference(size, size, 3);
  std::vector<double> rel_pixel, rel_instance, noise;
  double signed_pixel = 0.0, signed_instance = 0.0, path_mean = 0.0;
  int x0 = size, y0 = size, x1 = -1, y1 = -1;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Color a = path_a.rgb(x, y), b = path_b.rgb(x, y);
      reference.set_rgb(x, y, 0.5f * (a + b));
      if (!interior(x, y)) continue;
      x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
      const double p = luminance(0.5f * (a + b));
      const double rp = luminance(per_pixel.rgb(x, y)) - p;
      const double ri = luminance(per_instance.rgb(x, y)) - p;
      rel_pixel.push_back(std::abs(rp));
      rel_instance.push_back(std::abs(ri));
      signed_pixel += rp;
      signed_instance += ri;
      noise.push_back(std::abs(luminance(a) - luminance(b)) / 2.0);
      path_mean += p;
    }
  if (rel_pixel.empty()) throw Error("probes-dynamic: no pixel shows a dynamic object");
  path_mean /= double(rel_pixel.size());
  for (auto* v : {&rel_pixel, &rel_instance, &noise})
    for (double& e : *v) e /= path_mean;
  signed_pixel /= path_mean;
  signed_instance /= path_mean;
  const ErrorStats ep = error_stats(rel_pixel, signed_pixel);
  const ErrorStats ei = error_stats(rel_instance, signed_instance);
  const ErrorStats en = error_stats(noise, 0.0);
  std::printf("%s: %dx%dx%d probes (%.3g m, %lld invalid), %d spp, bake %.2fs; path %d spp %.1fs\n",
              scene.name.c_str(), volume.size.x, volume.size.y, volume.size.z, double(spacing),
              static_cast<long long>(baked.stats.invalid), spp, bake_seconds, path_spp,
              path_seconds);
  std::printf(
      "%zu object pixels, mean path-traced luminance P = %.4g; |R - P| / P mean / median / p90, "
      "signed mean (R - P) / P:\n",
      rel_pixel.size(), path_mean);
  std::printf("  per pixel:    %.4f / %.4f / %.4f, %+.4f\n", ep.mean, ep.median, ep.p90,
              ep.signed_mean);
  std::printf("  per instance: %.4f / %.4f / %.4f, %+.4f\n", ei.mean, ei.median, ei.p90,
              ei.signed_mean);
  std::printf("  path tracer's own standard error per pixel / P: mean %.4f, median %.4f\n", en.mean,
              en.median);

  if (!images.empty()) {
    // Crops around the object (its interior's bounds plus a margin), enlarged 2×.
    const int margin = std::max(4, (x1 - x0) / 8), k = 2;
    x0 = std::max(0, x0 - margin), y0 = std::max(0, y0 - margin);
    x1 = std::min(size - 1, x1 + margin), y1 = std::min(size - 1, y1 + margin);
    const int w = (x1 - x0 + 1) * k, h = (y1 - y0 + 1) * k, gap = 4;
    double peak = 0.0;  // exposure: the reference's brightest object pixel at 0.9
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (is_dynamic(x, y)) peak = std::max(peak, double(luminance(reference.rgb(x, y))));
    const float exposure = float(0.9 / std::max(peak, 1e-6));
    auto panels = [&](int count, const std::function<Color(int, int, int)>& pixel) {
      Image out(count * w + (count - 1) * gap, h, 3);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < out.width(); ++x) out.set_rgb(x, y, Color(1.0f));
      for (int p = 0; p < count; ++p)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            out.set_rgb(p * (w + gap) + x, y, pixel(p, x0 + x / k, y0 + y / k));
      return out;
    };
    const Image* shown[3] = {&reference, &per_pixel, &per_instance};
    const Image compare = panels(3, [&](int p, int x, int y) {
      const Image& from = is_dynamic(x, y) ? *shown[p] : reference;
      const float dim = is_dynamic(x, y) ? 1.0f : 0.35f;
      return glm::clamp(from.rgb(x, y) * exposure * dim, Color(0.0f), Color(1.0f));
    });
    const Image error = panels(2, [&](int p, int x, int y) {
      if (!interior(x, y)) return Color(0.0f, 0.0f, 0.08f);
      const double r = luminance(reference.rgb(x, y));
      const double e = luminance((p == 0 ? per_pixel : per_instance).rgb(x, y));
      return heat(std::abs(e - r) / path_mean, 1.0);
    });
    write_image(images + "/probes_dynamic_compare.png", compare);
    ImageWriteOptions linear;
    linear.srgb = false;
    write_image(images + "/probes_dynamic_error.png", error, linear);
    std::printf("wrote %s/probes_dynamic_compare.png and probes_dynamic_error.png\n",
                images.c_str());
  }
  if (!json_path.empty()) {
    auto stats = [](const ErrorStats& s) {
      return nlohmann::json{
          {"mean", s.mean}, {"median", s.median}, {"p90", s.p90}, {"signed_mean", s.signed_mean}};
    };
    write_json(json_path, {{"suite", "probes-dynamic"},
                           {"scene", scene.name},
                           {"grid", {volume.size.x, volume.size.y, volume.size.z}},
                           {"spacing", spacing},
                           {"spp", spp},
                           {"invalid", baked.stats.invalid},
                           {"path_spp", path_spp},
                           {"object_pixels", rel_pixel.size()},
                           {"path_mean_luminance", path_mean},
                           {"per_pixel", stats(ep)},
                           {"per_instance", stats(ei)},
                           {"path_noise", stats(en)},
                           {"machine", machine_info()}});
  }
  return 0;
}

}  // namespace illum::bench
