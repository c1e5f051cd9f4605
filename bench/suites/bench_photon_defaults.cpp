// `illum-bench photon-defaults`: the photon integrator with its default settings against
// the path tracer at equal time.
//
// 1. A path-traced reference (--reference-spp, default 1024) is rendered once and cached
//    in --out (reused when its file exists, or taken from --reference).
// 2. The photon integrator renders with its defaults (plus any --param override) at
//    --spp; its wall time T includes photon tracing, tree builds and the precomputed
//    irradiance.
// 3. The path tracer renders for the same time T (time budget, progressive passes).
// Both are compared with the reference by
//   relative RMSE: √(mean over pixels and RGB of (B x − B ref)²) / mean(ref), where B is a
//     3×3 box filter (so a biased-but-smooth and a noisy-but-unbiased image are judged on
//     the scale a viewer sees; the filter is applied to the reference too);
//   (over the pixels that do not see an emitter, nor have a neighbour that does: at 16 spp
//   the anti-aliasing noise of the light's edge, 20× brighter than the walls, would
//   otherwise dominate the figure and measure only the camera sample count);
//   region bias: the image cut into a 4×4 grid of blocks, per block the relative difference
//     of the mean luminance, (mean x − mean ref)/mean ref; the largest magnitude is shown.
// The ratio photon/path of the relative RMSE is printed: below 1 photon mapping is the
// better image for the time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
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

constexpr int kRegionGrid = 4;

struct Rendered {
  Image image;
  double seconds = 0.0;
  double cpu_seconds = 0.0;  // process CPU time, all threads: steadier on a shared machine
};

Rendered render(const RayTracer& tracer, const Camera& camera, const std::string& integrator,
                const nlohmann::json& params, int size, int spp, double budget, uint64_t seed,
                int threads) {
  RenderOptions o;
  o.threads = threads;
  o.width = o.height = size;
  o.spp = spp;
  o.seed = seed;
  o.time_budget_s = budget;
  o.progress = false;
  std::unique_ptr<Integrator> in =
      Integrator::create(integrator, Params(params, "photon-defaults bench"));
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  Rendered r;
  r.image = in->render(tracer, camera, o);
  r.cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

Image box3(const Image& img) {
  const int w = img.width(), h = img.height();
  Image out(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Color s(0.0f);
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          s += img.rgb(xx, yy);
          ++n;
        }
      out.set_rgb(x, y, s / static_cast<float>(n));
    }
  return out;
}

struct Error {
  double relative_rmse = 0.0;
  double max_region_bias = 0.0;  // signed, the largest magnitude
};

// Pixels to leave out: any of 4×4 sub-pixel rays of it or of a neighbour hits an emitter.
std::vector<uint8_t> emitter_pixels(const RayTracer& tracer, const Camera& camera, int size) {
  const Scene& scene = tracer.scene();
  std::vector<uint8_t> sees(static_cast<size_t>(size) * size, 0), out(sees.size(), 0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int j = 0; j < 16; ++j) {
        const Ray ray =
            camera.generate_ray(static_cast<float>(x) + (j % 4 + 0.5f) / 4.0f,
                                static_cast<float>(y) + (j / 4 + 0.5f) / 4.0f, size, size);
        Hit hit;
        if (!tracer.intersect(ray, &hit)) continue;
        const Mesh& mesh = scene.meshes[static_cast<size_t>(scene.instances[hit.instance].mesh)];
        if (scene.materials[static_cast<size_t>(mesh.material)].is_emissive())
          sees[static_cast<size_t>(y) * size + x] = 1;
      }
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < size && yy < size &&
              sees[static_cast<size_t>(yy) * size + xx])
            out[static_cast<size_t>(y) * size + x] = 1;
        }
  return out;
}

Error compare(const Image& img, const Image& ref, const std::vector<uint8_t>& excluded) {
  const Image a = box3(img), b = box3(ref);
  double se = 0.0, sum_ref = 0.0;
  const int w = img.width(), h = img.height();
  std::vector<double> region_img(kRegionGrid * kRegionGrid, 0.0), region_ref(region_img);
  size_t used = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (excluded[static_cast<size_t>(y) * w + x]) continue;
      ++used;
      const Color d = a.rgb(x, y) - b.rgb(x, y);
      se += glm::dot(d, d);
      const Color r = b.rgb(x, y);
      sum_ref += r.r + r.g + r.b;
      const size_t region =
          static_cast<size_t>((y * kRegionGrid / h) * kRegionGrid + x * kRegionGrid / w);
      region_img[region] += luminance(img.rgb(x, y));
      region_ref[region] += luminance(ref.rgb(x, y));
    }
  Error e;
  const double n = 3.0 * static_cast<double>(used);
  e.relative_rmse = std::sqrt(se / n) / (sum_ref / n);
  for (size_t i = 0; i < region_img.size(); ++i) {
    if (!(region_ref[i] > 0.0)) continue;
    const double bias = (region_img[i] - region_ref[i]) / region_ref[i];
    if (std::abs(bias) > std::abs(e.max_region_bias)) e.max_region_bias = bias;
  }
  return e;
}

nlohmann::json parse_param(const std::string& kv) {
  const size_t eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    throw illum::Error(fmt::format("photon-defaults: --param '{}' is not key=value", kv));
  const std::string value = kv.substr(eq + 1);
  if (value == "true" || value == "false") return value == "true";
  try {
    size_t used = 0;
    const double d = std::stod(value, &used);
    if (used == value.size()) {
      if (std::floor(d) == d && value.find('.') == std::string::npos)
        return static_cast<int64_t>(d);
      return d;
    }
  } catch (const std::exception&) {
  }
  return value;
}

void save_png(const std::string& path, const Image& img) {
  write_image(path, tone_mapped(img, ToneMapper::kClamp, 1.0f), ImageWriteOptions{});
}

}  // namespace

int run_photon_defaults(SuiteArgs args) {
  CLI::App app("photon-defaults: photon integrator defaults vs the path tracer at equal time",
               "illum-bench photon-defaults");
  std::string scene_arg = "cornell", out_dir = "bench-out/photon-defaults", reference_path,
              images_dir, json_path;
  int size = 256, spp = 16, reference_spp = 1024, threads = 0;
  uint64_t seed = 1;
  std::vector<std::string> overrides;
  app.add_option("scene", scene_arg, "scene")->capture_default_str();
  app.add_option("--size", size, "image width and height")
      ->capture_default_str()
      ->check(CLI::Range(8, 4096));
  app.add_option("--spp", spp, "photon integrator samples per pixel")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--reference-spp", reference_spp, "path-traced reference samples per pixel")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 24));
  app.add_option("--reference", reference_path, "reuse this reference EXR");
  app.add_option("--param", overrides, "photon parameter key=value overriding a default");
  app.add_option("--out", out_dir, "folder for the images and the cached reference")
      ->capture_default_str();
  app.add_option("--images", images_dir, "also write PNG figures here (e.g. docs/images)");
  app.add_option("--json", json_path, "write the results to this JSON file");
  app.add_option("--seed", seed, "seed")->capture_default_str();
  app.add_option("--threads", threads, "worker threads (0: all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  if (!parse_args(app, args)) return 0;
  check_output_folder(json_path);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw illum::Error(
        fmt::format("photon-defaults: cannot create --out folder '{}': {}", out_dir, ec.message()));
  if (!images_dir.empty() && !std::filesystem::is_directory(images_dir))
    throw illum::Error(
        fmt::format("photon-defaults: --images folder '{}' does not exist", images_dir));
  nlohmann::json photon_params = nlohmann::json::object();
  for (const std::string& kv : overrides)
    photon_params[kv.substr(0, kv.find('='))] = parse_param(kv);

  const Scene scene = load_scene(scene_arg);
  const RayTracer tracer(scene);
  if (!scene.camera)
    throw illum::Error(fmt::format("photon-defaults: '{}' has no camera", scene_arg));
  const Camera camera = *scene.camera;
  const std::string stem = std::filesystem::path(scene_arg).stem().string();

  Image reference;
  double reference_seconds = 0.0;
  const std::string cached =
      fmt::format("{}/reference-{}-{}-{}spp.exr", out_dir, stem, size, reference_spp);
  const std::string ref_file = !reference_path.empty() ? reference_path : cached;
  if (std::filesystem::exists(ref_file)) {
    reference = read_image(ref_file, false);
    if (reference.width() != size || reference.height() != size)
      throw illum::Error(fmt::format("photon-defaults: reference '{}' is {}x{}, not {}x{}",
                                     ref_file, reference.width(), reference.height(), size, size));
  } else if (!reference_path.empty()) {
    throw illum::Error(fmt::format("photon-defaults: --reference '{}' does not exist", ref_file));
  } else {
    const Rendered r = render(tracer, camera, "path", nlohmann::json::object(), size, reference_spp,
                              0.0, seed + 1000, threads);
    reference = r.image;
    reference_seconds = r.seconds;
    ImageWriteOptions w;
    w.exr_half = false;
    write_image(cached, reference, w);
  }

  const Rendered photon =
      render(tracer, camera, "photon", photon_params, size, spp, 0.0, seed, threads);
  const Rendered path = render(tracer, camera, "path", nlohmann::json::object(), size, 1 << 24,
                               photon.seconds, seed, threads);
  const std::vector<uint8_t> excluded = emitter_pixels(tracer, camera, size);
  const Error pe = compare(photon.image, reference, excluded),
              qe = compare(path.image, reference, excluded);
  std::printf("%s %dx%d, reference: path %d spp (%s)\n", stem.c_str(), size, size, reference_spp,
              reference_seconds > 0.0
                  ? fmt::format("rendered in {:.1f} s", reference_seconds).c_str()
                  : ref_file.c_str());
  std::printf(
      "  photon %s, %d spp: %6.2f s (CPU %.2f s), relRMSE(3x3) %.4f, max region bias %+.4f\n",
      photon_params.dump().c_str(), spp, photon.seconds, photon.cpu_seconds, pe.relative_rmse,
      pe.max_region_bias);
  std::printf(
      "  path at equal time: %6.2f s (CPU %.2f s), relRMSE(3x3) %.4f, max region bias %+.4f\n",
      path.seconds, path.cpu_seconds, qe.relative_rmse, qe.max_region_bias);
  std::printf("  relRMSE ratio photon/path %.3f\n", pe.relative_rmse / qe.relative_rmse);
  write_image(out_dir + "/" + stem + "-photon.exr", photon.image);
  write_image(out_dir + "/" + stem + "-path-equal-time.exr", path.image);
  if (!images_dir.empty()) {
    save_png(images_dir + "/" + stem + "-photon-defaults.png", photon.image);
    save_png(images_dir + "/" + stem + "-path-equal-time.png", path.image);
    save_png(images_dir + "/" + stem + "-path-reference.png", reference);
  }
  if (!json_path.empty())
    write_json(json_path,
               {{"suite", "photon-defaults"},
                {"scene", scene_arg},
                {"size", size},
                {"machine", machine_info()},
                {"threads", threads},
                {"reference_spp", reference_spp},
                {"photon",
                 {{"params", photon_params},
                  {"seconds", photon.seconds},
                  {"cpu_seconds", photon.cpu_seconds},
                  {"spp", spp},
                  {"relative_rmse_box3", pe.relative_rmse},
                  {"max_region_bias", pe.max_region_bias}}},
                {"path_equal_time",
                 {{"seconds", path.seconds},
                  {"cpu_seconds", path.cpu_seconds},
                  {"relative_rmse_box3", qe.relative_rmse},
                  {"max_region_bias", qe.max_region_bias}}},
                {"relative_rmse_ratio_photon_over_path", pe.relative_rmse / qe.relative_rmse}});
  return 0;
}

}  // namespace illum::bench
