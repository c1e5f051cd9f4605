// `illum-bench caustics`: caustics through a glass sphere, path tracing vs photon mapping vs
// SPPM (ALGORITHMS.md A.2).
//
// (a) Built-in `caustics` scene, point spot light: a path tracer cannot render the caustic
//     at all (a delta light seen through a delta BSDF: no path vertex can connect to the
//     light). All three run for the same time; images go to --images (caustics-*-spot.png)
//     and the mean radiance in the caustic disc is reported.
// (b) `caustics-sphere-light` (data/scenes): the spot replaced by a 1.5 cm emissive sphere,
//     so path tracing converges (slowly). A long SPPM run is the reference; path, photon and
//     SPPM get the same time each and their relative MSE against it is measured in the
//     caustic disc.
//
// Caustic disc: the floor points with √(x² + z²) ≤ 4 cm (y = 0) seen directly by the camera
// (pixels whose centre ray hits the floor there, not through the glass). Tracing the
// refraction of the spot's rays through the sphere (paraxial focus 0.15 m below the floor)
// puts 90 % of the transmitted flux within 3.2 cm of the axis; 4 cm leaves room for the
// sphere light's penumbra.
// Relative MSE over the disc's pixels P: Σ_P |x − ref|² / Σ_P |ref|² (RGB summed).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/core/tonemap.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {
namespace {

constexpr float kCausticRadius = 0.04f;
int g_threads = 0;  // --threads, for every render of the suite

std::vector<uint8_t> caustic_mask(const RayTracer& tracer, const Camera& camera, int w, int h) {
  std::vector<uint8_t> mask(static_cast<size_t>(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray ray =
          camera.generate_ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, w, h);
      Hit hit;
      if (!tracer.intersect(ray, &hit)) continue;
      const vec3 p = ray.origin + hit.t * ray.direction;
      const Material& m = tracer.scene().materials[static_cast<size_t>(
          tracer.scene()
              .meshes[static_cast<size_t>(tracer.scene().instances[hit.instance].mesh)]
              .material)];
      if (m.type == MaterialType::kLambert && std::abs(p.y) < 1e-3f &&
          std::hypot(p.x, p.z) <= kCausticRadius)
        mask[static_cast<size_t>(y) * w + x] = 1;
    }
  return mask;
}

double region_mean(const Image& img, const std::vector<uint8_t>& mask) {
  double s = 0.0;
  size_t n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      if (mask[static_cast<size_t>(y) * img.width() + x]) {
        s += luminance(img.rgb(x, y));
        ++n;
      }
  return n ? s / static_cast<double>(n) : 0.0;
}

double relative_mse(const Image& img, const Image& ref, const std::vector<uint8_t>& mask) {
  double num = 0.0, den = 0.0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      if (mask[static_cast<size_t>(y) * img.width() + x]) {
        const Color d = img.rgb(x, y) - ref.rgb(x, y);
        const Color r = ref.rgb(x, y);
        num += glm::dot(d, d);
        den += glm::dot(r, r);
      }
  return den > 0.0 ? num / den : 0.0;
}

// Photon mapping does not improve with camera samples once its maps are built, so at equal
// time it should spend a good part of the budget on photons: half of it, measured by
// tracing 200k caustic photons first.
int auto_caustic_photons(const RayTracer& tracer, const Camera& camera, double seconds) {
  RenderOptions o;
  o.width = o.height = 8;
  o.spp = 1;
  o.threads = g_threads;
  o.progress = false;
  const nlohmann::json p = {{"photons", 1}, {"caustic_photons", 200000}, {"final_gather", false}};
  const auto t0 = std::chrono::steady_clock::now();
  Integrator::create("photon", Params(p, "caustics bench"))->render(tracer, camera, o);
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return static_cast<int>(std::clamp(200000.0 * 0.5 * seconds / std::max(t, 1e-3), 1e4, 2e8));
}

struct Run {
  Image image;
  double seconds = 0.0;
};

Run render_for(const RayTracer& tracer, const Camera& camera, const std::string& integrator,
               const nlohmann::json& params, int size, double seconds, uint64_t seed) {
  RenderOptions o;
  o.threads = g_threads;
  o.width = o.height = size;
  o.spp = 1 << 24;  // the time budget decides
  o.seed = seed;
  o.time_budget_s = seconds;
  o.progress = false;
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<Integrator> in = Integrator::create(integrator, Params(params, "caustics bench"));
  Run r;
  r.image = in->render(tracer, camera, o);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void save_png(const std::string& path, const Image& img, float exposure) {
  ImageWriteOptions w;
  w.exposure = 1.0f;
  write_image(path, tone_mapped(img, ToneMapper::kClamp, exposure), w);
}

}  // namespace

int run_caustics(SuiteArgs args) {
  CLI::App app("caustics: path vs photon vs SPPM at equal time", "illum-bench caustics");
  int size = 128;
  double seconds = 20.0, reference_seconds = 300.0;
  std::string out_dir = "bench-out/caustics", images_dir, reference_path, json_path;
  uint64_t seed = 1;
  int caustic_photons = 0, sppm_photons = 200000;
  float exposure = 0.05f;
  app.add_option("--size", size, "image width and height")
      ->capture_default_str()
      ->check(CLI::Range(8, 4096));
  app.add_option("--seconds", seconds, "time per method")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--reference-seconds", reference_seconds, "time of the SPPM reference")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1e7));
  app.add_option("--reference", reference_path,
                 "reuse this reference EXR instead of rendering one");
  app.add_option("--out", out_dir, "folder for EXR images and the JSON")->capture_default_str();
  app.add_option("--images", images_dir, "also write the PNG figures here (e.g. docs/images)");
  app.add_option("--json", json_path, "write the results to this JSON file");
  app.add_option("--seed", seed, "seed")->capture_default_str();
  app.add_option("--caustic-photons", caustic_photons,
                 "photon integrator: caustic photons (0: as many as half of --seconds traces)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 30));
  app.add_option("--sppm-photons", sppm_photons, "SPPM photons per iteration")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 30));
  app.add_option("--threads", g_threads, "worker threads (0: all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  app.add_option("--exposure", exposure, "exposure of the PNG figures")->capture_default_str();
  if (!parse_args(app, args)) return 0;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw Error(
        fmt::format("caustics: cannot create --out folder '{}': {}", out_dir, ec.message()));
  if (!images_dir.empty() && !std::filesystem::is_directory(images_dir))
    throw Error(fmt::format("caustics: --images folder '{}' does not exist", images_dir));

  nlohmann::json photon_params = {{"photons", 200000},
                                  {"caustic_photons", caustic_photons},
                                  {"k", 100},
                                  {"final_gather", false}};
  const nlohmann::json sppm_params = {{"photons_per_iteration", sppm_photons}, {"alpha", 0.7}};
  const nlohmann::json path_params = nlohmann::json::object();
  struct Method {
    const char* name;
    const nlohmann::json* params;
  };
  const Method methods[] = {
      {"path", &path_params}, {"photon", &photon_params}, {"sppm", &sppm_params}};
  nlohmann::json out = {{"suite", "caustics"},
                        {"machine", machine_info()},
                        {"size", size},
                        {"seconds_per_method", seconds},
                        {"threads", g_threads},
                        {"caustic_disc_radius_m", kCausticRadius},
                        {"sppm_params", sppm_params}};

  // (a) Spot light.
  {
    const Scene scene = load_scene("caustics");
    const RayTracer tracer(scene);
    const Camera camera = *scene.camera;
    const std::vector<uint8_t> mask = caustic_mask(tracer, camera, size, size);
    if (caustic_photons == 0)
      photon_params["caustic_photons"] = auto_caustic_photons(tracer, camera, seconds);
    std::printf(
        "(a) caustics, 100 W spot, %dx%d, %.1f s each (photon: %d caustic photons); caustic disc "
        "mean luminance:\n",
        size, size, seconds, photon_params["caustic_photons"].get<int>());
    nlohmann::json part;
    for (const Method& m : methods) {
      const Run r = render_for(tracer, camera, m.name, *m.params, size, seconds, seed);
      const double mean = region_mean(r.image, mask);
      std::printf("  %-7s %8.2f s  disc mean %10.3f W/(sr m^2)\n", m.name, r.seconds, mean);
      part[m.name] = {{"seconds", r.seconds}, {"disc_mean_luminance", mean}, {"params", *m.params}};
      write_image(out_dir + "/caustics-" + m.name + "-spot.exr", r.image);
      if (!images_dir.empty())
        save_png(images_dir + "/caustics-" + m.name + "-spot.png", r.image, exposure);
    }
    out["spot"] = part;
  }

  // (b) Sphere light.
  {
    const std::string path =
        data_dir() + "/scenes/caustics-sphere-light/caustics-sphere-light.illum.json";
    const Scene scene = load_scene(path);
    const RayTracer tracer(scene);
    const Camera camera = *scene.camera;
    const std::vector<uint8_t> mask = caustic_mask(tracer, camera, size, size);
    if (caustic_photons == 0)
      photon_params["caustic_photons"] = auto_caustic_photons(tracer, camera, seconds);
    size_t pixels = 0;
    for (uint8_t v : mask) pixels += v;
    Image reference;
    double reference_time = 0.0;
    if (!reference_path.empty()) {
      reference = read_image(reference_path, false);
      if (reference.width() != size || reference.height() != size)
        throw Error(fmt::format("caustics: --reference '{}' is {}x{}, not {}x{}", reference_path,
                                reference.width(), reference.height(), size, size));
    } else {
      const Run r =
          render_for(tracer, camera, "sppm", sppm_params, size, reference_seconds, seed + 1000);
      reference = r.image;
      reference_time = r.seconds;
      ImageWriteOptions w;
      w.exr_half = false;
      write_image(out_dir + "/caustics-sphere-light-reference.exr", reference, w);
    }
    if (!images_dir.empty())
      save_png(images_dir + "/caustics-sphere-light-reference.png", reference, exposure);
    const double ref_mean = region_mean(reference, mask);
    std::printf(
        "(b) caustics-sphere-light, %dx%d, reference SPPM %.0f s, caustic disc %zu px, mean %.3f "
        "(photon: %d caustic photons)\n",
        size, size, reference_time, pixels, ref_mean, photon_params["caustic_photons"].get<int>());
    nlohmann::json part = {{"reference_seconds", reference_time},
                           {"disc_pixels", pixels},
                           {"reference_disc_mean_luminance", ref_mean}};
    double rel[3] = {0, 0, 0};
    int i = 0;
    for (const Method& m : methods) {
      const Run r = render_for(tracer, camera, m.name, *m.params, size, seconds, seed);
      rel[i] = relative_mse(r.image, reference, mask);
      const double mean = region_mean(r.image, mask);
      std::printf("  %-7s %8.2f s  relMSE %10.5f  disc mean %10.3f\n", m.name, r.seconds, rel[i],
                  mean);
      part[m.name] = {{"seconds", r.seconds},
                      {"relative_mse", rel[i]},
                      {"disc_mean_luminance", mean},
                      {"params", *m.params}};
      write_image(out_dir + "/caustics-sphere-light-" + m.name + ".exr", r.image);
      if (!images_dir.empty())
        save_png(images_dir + "/caustics-sphere-light-" + m.name + ".png", r.image, exposure);
      ++i;
    }
    std::printf("  relMSE ratio path/photon %.2f, path/sppm %.2f\n", rel[0] / rel[1],
                rel[0] / rel[2]);
    part["ratio_path_over_photon"] = rel[0] / rel[1];
    part["ratio_path_over_sppm"] = rel[0] / rel[2];
    out["sphere_light"] = part;
  }
  if (!json_path.empty()) write_json(json_path, out);
  return 0;
}

}  // namespace illum::bench
