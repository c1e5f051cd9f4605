// `illum-bench lightmap-extras`: the extra light-map maps (bake/lightmap_extras.h) on the
// Cornell box (or another scene):
//  1. baked AO against the offline `ao` integrator at every covered texel: a 1×1 render from
//     a camera just off the texel's point along its normal (field of view 1e-4 rad) is the
//     integrator's estimate at that point; per texel z = (baked − integrator) /
//     √(2·p(1−p)·(1/n_baked + 1/n_integrator)) (binomial variances, ×2 for scrambled nets);
//     summary figures and, with --images, a heat map of |baked − integrator| in atlas layout;
//  2. the global-line obscurance map against the per-texel one at (about) equal ray queries,
//     both against a per-texel reference with 16× the rays: seconds, rays and RMSE over the
//     texels the lines reached;
//  3. with --images DIR: lightmap-extras-SCENE-{ao,obscurance,obscurance_color}.png (the
//     maps as sRGB previews, nearest-neighbour ×--zoom) and lightmap-extras-SCENE-ao_error.png.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_extras.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct ExtrasArgs {
  std::string scene = "cornell";
  int resolution = 64;
  int rays = bake::kDefaultExtraRays;
  int integrator_spp = 16;      // camera samples per texel
  int integrator_samples = 64;  // AO rays per camera sample
  float dmax = bake::kDefaultObscuranceDmax;
  int zoom = 4;
  uint64_t seed = 1;
  int threads = 0;
  std::string images, json_path;
};

Image zoomed(const Image& src, int zoom) {
  Image out(src.width() * zoom, src.height() * zoom, 3);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) out.set_rgb(x, y, src.rgb(x / zoom, y / zoom));
  return out;
}

// Black (0) → blue → red → yellow (≥ top); uncovered texels dark grey. The error map tops
// out at 0.05 in AO units, about 5 times the RMS difference at the defaults.
constexpr double kHeatTop = 0.05;
Color heat(double v, double top) {
  const float t = float(std::clamp(v / top, 0.0, 1.0));
  if (t < 0.33f) return Color(0.0f, 0.0f, t / 0.33f);
  if (t < 0.66f) return Color((t - 0.33f) / 0.33f, 0.0f, 1.0f - (t - 0.33f) / 0.33f);
  return Color(1.0f, (t - 0.66f) / 0.34f, 0.0f);
}

double ao_integrator_at(const RayTracer& tracer, Integrator& ao, const atlas::TexelSample& t,
                        int spp, uint64_t seed) {
  Camera cam;
  cam.position = t.position + 1e-3f * t.normal;
  cam.look_at = t.position;
  cam.up = std::abs(t.normal.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
  cam.fov_y = 1e-4f;
  RenderOptions ro;
  ro.width = ro.height = 1;
  ro.spp = spp;
  ro.seed = seed;
  ro.progress = false;
  return ao.render(tracer, cam, ro).pixel(0, 0)[0];
}

std::string image_path(const std::filesystem::path& dir, const std::string& scene,
                       const char* map) {
  return (dir / fmt::format("lightmap-extras-{}-{}.png", scene, map)).string();
}

}  // namespace

int run_lightmap_extras(SuiteArgs args) {
  CLI::App app(
      "Light-map extra maps: baked AO vs the ao integrator, global-line vs per-texel "
      "obscurance, preview images",
      "illum-bench lightmap-extras");
  ExtrasArgs a;
  app.add_option("--scene", a.scene, "built-in scene name or scene file (default: cornell)");
  app.add_option("--resolution", a.resolution, "atlas side in texels")->check(CLI::Range(16, 4096));
  app.add_option("--rays", a.rays, "directions per texel of the baked maps")
      ->check(CLI::Range(1, bake::kMaxExtraRays));
  app.add_option("--integrator-spp", a.integrator_spp, "ao integrator camera samples per texel")
      ->check(CLI::Range(1, 1 << 16));
  app.add_option("--integrator-samples", a.integrator_samples,
                 "ao integrator rays per camera sample")
      ->check(CLI::Range(1, 1024));
  app.add_option("--dmax", a.dmax, "obscurance d_max (scene units)")
      ->check(CLI::Range(1e-6f, 1e6f));
  app.add_option("--zoom", a.zoom, "nearest-neighbour enlargement of the images")
      ->check(CLI::Range(1, 16));
  app.add_option("--seed", a.seed, "sampler seed");
  app.add_option("--threads", a.threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--images", a.images,
                 "write lightmap-extras-SCENE-{ao,obscurance,obscurance_color,ao_error}.png "
                 "into this existing folder");
  app.add_option("--json", a.json_path, "write the results here");
  if (!parse_args(app, args)) return 0;
  check_output_folder(a.json_path);
  if (!a.images.empty() && !std::filesystem::is_directory(a.images))
    throw Error(fmt::format("--images: folder '{}' does not exist", a.images));
  ThreadLimit limit(a.threads);

  Scene scene = load_scene(a.scene);
  const atlas::Atlas atl = atlas::chart_scene(scene, {.resolution = a.resolution});
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atl.width, atl.height);

  bake::LightmapExtrasOptions o;
  o.ao = o.obscurance = o.bent_normal = true;
  o.rays = a.rays;
  o.obscurance_dmax = a.dmax;
  o.seed = a.seed;
  o.threads = a.threads;
  o.progress = false;
  o.dilate = 0;  // compare covered texels only; the images show them undilated
  const bake::LightmapExtras e = bake::bake_lightmap_extras(scene, tracer, raster, o);
  std::printf(
      "lightmap-extras: %s %dx%d, %zu texels, %d rays/texel: %.3f s, %lld rays, AO "
      "distance %.4g, d_max %.4g\n",
      scene.name.c_str(), atl.width, atl.height, raster.covered(), a.rays, e.seconds,
      (long long)e.rays, double(e.ao_distance), double(a.dmax));

  // 1. AO against the integrator, texel by texel.
  const auto ao = Integrator::create(
      "ao", Params({{"samples", a.integrator_samples}, {"distance", e.ao_distance}}, "bench"));
  const int n_int = a.integrator_spp * a.integrator_samples;
  Image error_map(atl.width, atl.height, 3, 0.15f);
  double sum_diff = 0, sum_sq = 0, sum_var = 0, worst_z = 0;
  size_t beyond3 = 0;
  for (size_t i = 0; i < raster.samples.size(); ++i) {
    const atlas::TexelSample& t = raster.samples[i];
    const double b = e.ao.rgb(t.x, t.y).x;
    const double r = ao_integrator_at(tracer, *ao, t, a.integrator_spp, a.seed + 1000 + i);
    const double p = 0.5 * (b + r);
    const double var = 2.0 * p * (1 - p) * (1.0 / a.rays + 1.0 / n_int);
    const double z = var > 0 ? (b - r) / std::sqrt(var) : (b == r ? 0.0 : INFINITY);
    worst_z = std::max(worst_z, std::abs(z));
    beyond3 += std::abs(z) > 3.0;
    sum_diff += b - r;
    sum_sq += (b - r) * (b - r);
    sum_var += var;
    error_map.set_rgb(t.x, t.y, heat(std::abs(b - r), kHeatTop));
  }
  const double n = double(raster.covered());
  std::printf(
      "AO vs ao integrator (%d rays/texel): mean diff %+.5f, RMS diff %.4f (expected "
      "from the variances ≤ %.4f), pooled z %.2f, worst |z| %.2f, |z| > 3 at %zu of "
      "%zu texels\n",
      n_int, sum_diff / n, std::sqrt(sum_sq / n), std::sqrt(sum_var / n),
      sum_diff / std::sqrt(sum_var), worst_z, beyond3, raster.covered());

  // 2. Global lines against per texel at equal rays.
  bake::LightmapExtrasOptions ref = o;
  ref.ao = ref.bent_normal = false;
  ref.rays = 16 * a.rays;
  ref.seed = a.seed + 7;
  const bake::LightmapExtras reference = bake::bake_lightmap_extras(scene, tracer, raster, ref);
  bake::LightmapExtrasOptions pt = ref;
  pt.rays = a.rays;
  pt.seed = a.seed;
  const bake::LightmapExtras per_texel = bake::bake_lightmap_extras(scene, tracer, raster, pt);
  bake::GlobalLineObscuranceOptions g;
  g.obscurance_dmax = a.dmax;
  g.seed = a.seed;
  g.threads = a.threads;
  bake::GlobalLineObscuranceOptions trial = g;
  trial.directions = 8;
  trial.lines_per_direction = 2000;
  const auto tr = bake::obscurance_global_lines(scene, tracer, raster, trial);
  const double rays_per_line = double(tr.rays) / double(8 * 2000);
  g.lines_per_direction = std::max<int64_t>(
      1, int64_t(double(per_texel.rays) / (rays_per_line * double(g.directions))));
  const auto gl = bake::obscurance_global_lines(scene, tracer, raster, g);
  double e_gl = 0, e_pt = 0, e_pt_all = 0;
  size_t reached = 0;
  for (const atlas::TexelSample& t : raster.samples) {
    const double r = reference.obscurance.rgb(t.x, t.y).x;
    const double d_pt = per_texel.obscurance.rgb(t.x, t.y).x - r;
    e_pt_all += d_pt * d_pt;
    if (gl.count.pixel(t.x, t.y)[0] > 0) {
      const double d = gl.obscurance.rgb(t.x, t.y).x - r;
      e_gl += d * d;
      e_pt += d_pt * d_pt;
      ++reached;
    }
  }
  std::printf(
      "obscurance (d_max %.3g), against per texel at %d rays: per texel %d rays: %lld "
      "rays, %.3f s, RMSE %.4f (all texels %.4f); global lines %d directions x %lld "
      "lines: %lld rays, %.3f s, RMSE %.4f over the %zu of %zu texels reached\n",
      double(a.dmax), ref.rays, a.rays, (long long)per_texel.rays, per_texel.seconds,
      std::sqrt(e_pt / double(std::max<size_t>(reached, 1))), std::sqrt(e_pt_all / n), g.directions,
      (long long)g.lines_per_direction, (long long)gl.rays, gl.seconds,
      std::sqrt(e_gl / double(std::max<size_t>(reached, 1))), reached, raster.covered());

  if (!a.images.empty()) {
    const std::filesystem::path dir(a.images);
    write_image(image_path(dir, scene.name, "ao"), zoomed(e.ao, a.zoom));
    write_image(image_path(dir, scene.name, "obscurance"), zoomed(e.obscurance, a.zoom));
    write_image(image_path(dir, scene.name, "obscurance_color"),
                zoomed(e.obscurance_color, a.zoom));
    ImageWriteOptions raw;
    raw.srgb = false;  // the heat scale is already a display colour
    write_image(image_path(dir, scene.name, "ao_error"), zoomed(error_map, a.zoom), raw);
  }
  if (!a.json_path.empty())
    write_json(a.json_path,
               {{"suite", "lightmap-extras"},
                {"scene", scene.name},
                {"resolution", a.resolution},
                {"texels", raster.covered()},
                {"rays", a.rays},
                {"ao",
                 {{"mean_diff", sum_diff / n},
                  {"rms_diff", std::sqrt(sum_sq / n)},
                  {"pooled_z", sum_diff / std::sqrt(sum_var)},
                  {"worst_z", worst_z}}},
                {"obscurance",
                 {{"per_texel_rays", per_texel.rays},
                  {"per_texel_seconds", per_texel.seconds},
                  {"per_texel_rmse", std::sqrt(e_pt / double(std::max<size_t>(reached, 1)))},
                  {"global_line_rays", gl.rays},
                  {"global_line_seconds", gl.seconds},
                  {"global_line_rmse", std::sqrt(e_gl / double(std::max<size_t>(reached, 1)))},
                  {"texels_reached", reached}}},
                {"machine", machine_info()}});
  return 0;
}

}  // namespace illum::bench
