// `illum-bench prt-vs-path`: relit PRT images against the path tracer. One PRT bake of a
// scene with its own lights removed, relit under each distant light given (--sun, --env),
// beside the path tracer lit (a) by the same band-limited light (the SH projection written
// back into an environment map: what the transfer can represent exactly) and (b) by the true
// light (the delta sun, the full map). Writes one image grid (a row per light: relit, path
// tracer under the band-limited light, path tracer under the true light, |relit − path| ×4,
// one exposure per row) and the error figures, per pixel and per region, as JSON and stdout.
//
// The band-limited light rings negative (a sun above all); the path tracer takes only
// non-negative maps, so it renders the positive and negative parts apart and subtracts
// (transport is linear).
//
// Error figures (relative to the mean of the path-traced pixels compared):
//  - relit vs band-limited path, per pixel, over "flat" pixels (rays on a 9×9 grid across
//    the pixel all hit one instance with one normal: where an edge crosses a pixel the
//    relight's fixed grid and the path tracer's jittered samples weigh its sides differently,
//    which is no error of the transfer): d = R̄ − P̄, each side the mean of two runs (a second
//    bake with the next seed, two path-tracer seeds), σ² the sum of both sides' variances of
//    the mean, (a − b)²/4 pooled over the pixel's flat 3×3 neighbourhood (about 18 degrees of
//    freedom: a Student t puts 99.2 % within 3σ and 99.99 % within 5σ if the transfer is right
//    up to its noise). Reported: bias, RMS of d, RMS of σ, the shares within 3σ and 5σ, worst.
//  - band-limiting error, per region (squares of --region pixels that all see a surface): the
//    path tracer under the true light against the band-limited one, and the relit image
//    against the true light, over all regions and over "smooth" ones (the four quarter-block
//    means of the true-light image within 25 % of their mean: no shadow edge or sun-patch
//    border crosses it).
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
#include "illum/core/tonemap.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "prt_direct_spread.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct PrtVsPathArgs {
  std::string scene = "data/scenes/cornell-opening/cornell-opening.illum.json";
  std::vector<std::string> suns;  // "X,Y,Z,E"
  std::vector<std::string> envs;  // "FILE" or "FILE,DEG"
  int resolution = 64, bands = 4, bake_spp = 64;
  std::string mode = "interreflected";
  int width = 128, height = 128, relight_spp = 16, path_spp = 64, max_bounces = 16, region = 8;
  int threads = 0;
  bool stitch = true, push_out = true;  // as `illum bake --kind prt` does
  int spread_seeds = 16;  // bakes of the seen texels' direct transfer for the relit side's σ
  uint64_t seed = 1;
  double shoot_tolerance = 1e-3, shoot_relative_tolerance = 0.05;
  std::string image_path, json_path;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<float> numbers(const std::string& text, const char* option) {
  std::vector<float> v;
  size_t p = 0;
  while (p <= text.size()) {
    const size_t q = std::min(text.find(',', p), text.size());
    try {
      size_t used = 0;
      const std::string part = text.substr(p, q - p);
      v.push_back(std::stof(part, &used));
      if (used != part.size() || !std::isfinite(v.back())) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw Error(fmt::format("{} '{}': expected comma-separated finite numbers", option, text));
    }
    p = q + 1;
  }
  return v;
}

struct TestLight {
  std::string name;
  bake::ShLight sh;
  Light light;                     // the true light for the path tracer
  std::optional<Environment> env;  // with its map, for kEnvironment
};

// Channel-summed pixel value.
// Pixels judged against their σ: how many, the shares within 3σ and 5σ, the worst |d| / σ.
struct SigmaTally {
  size_t count = 0, within3 = 0, within5 = 0;
  double worst = 0.0;
  void add(double d, double sigma) {
    ++count;
    within3 += std::abs(d) <= 3.0 * sigma;
    within5 += std::abs(d) <= 5.0 * sigma;
    if (sigma > 0.0) worst = std::max(worst, std::abs(d) / sigma);
  }
  double share3() const { return double(within3) / double(std::max<size_t>(count, 1)); }
  double share5() const { return double(within5) / double(std::max<size_t>(count, 1)); }
};

// The unbiased sample variance of k values from their sum s1 and sum of squares s2.
double sample_variance(double s1, double s2, double k) {
  return std::max(0.0, (s2 - s1 * s1 / k) / (k - 1.0));
}

double sum_of(const Image& image, int x, int y) {
  const Color c = image.rgb(x, y);
  return double(c.x) + double(c.y) + double(c.z);
}

Image path_traced(Scene scene, const Light& light, const std::optional<Environment>& env,
                  const Camera& camera, const RenderOptions& render, int max_bounces) {
  scene.lights = {light};
  scene.environment = env;
  const RayTracer tracer(scene);
  return Integrator::create("path", Params({{"max_bounces", max_bounces}}, "prt-vs-path"))
      ->render(tracer, camera, render);
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 1.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

}  // namespace

int run_prt_vs_path(SuiteArgs args) {
  CLI::App app(
      "PRT relit from one bake vs the path tracer under band-limited and true distant light",
      "illum-bench prt-vs-path");
  PrtVsPathArgs a;
  app.add_option("--scene", a.scene, "scene (its own lights and emission are removed)");
  app.add_option("--sun", a.suns,
                 "X,Y,Z,E: a sun travelling along X,Y,Z, irradiance E (repeatable)");
  app.add_option("--env", a.envs, "FILE[,DEG]: an equirectangular HDR turned DEG about +y");
  app.add_option("--resolution", a.resolution, "atlas side")->check(CLI::Range(16, 4096));
  app.add_option("--bands", a.bands, "SH bands")
      ->check(CLI::Range(bake::kMinPrtBands, bake::kMaxPrtBands));
  app.add_option("--bake-spp", a.bake_spp, "transfer rays a texel")->check(CLI::Range(1, 1 << 16));
  app.add_option("--mode", a.mode, "unshadowed, shadowed or interreflected");
  app.add_option("--width", a.width, "image width")->check(CLI::Range(8, 4096));
  app.add_option("--height", a.height, "image height")->check(CLI::Range(8, 4096));
  app.add_option("--relight-spp", a.relight_spp, "relight rays a pixel (grid)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--path-spp", a.path_spp, "path-tracer samples a pixel")
      ->check(CLI::Range(1, 1 << 16));
  app.add_option("--max-bounces", a.max_bounces, "path-tracer bounces")->check(CLI::Range(1, 1024));
  app.add_option("--region", a.region, "region side in pixels")->check(CLI::Range(2, 256));
  app.add_option("--shoot-tolerance", a.shoot_tolerance,
                 "interreflected: stop shooting at this share of the initial unshot transfer")
      ->check(CLI::Range(2e-6, 1.0));
  app.add_option("--shoot-relative-tolerance", a.shoot_relative_tolerance,
                 "interreflected: and at this mean share of each patch's light unshot (1: off)")
      ->check(CLI::Range(2e-6, 1.0));
  app.add_option("--threads", a.threads, "worker threads (0: all)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", a.seed, "bake seed (path tracer: seed + 10, + 11, + 12)");
  app.add_option("--stitch", a.stitch, "stitch the SHL-map's seams (as the CLI's bake)");
  app.add_option("--push-out", a.push_out,
                 "move texel samples out of geometry first (as the CLI's bake)");
  app.add_option("--spread-seeds", a.spread_seeds,
                 "direct-transfer bakes of the texels seen, for the relit side's sigma "
                 "(0: two-run sigma only)")
      ->check(CLI::Range(0, 1024));
  app.add_option("--image", a.image_path, "write the image grid (PNG) here");
  app.add_option("--json", a.json_path, "write the figures here");
  if (!parse_args(app, args)) return 0;
  if (a.spread_seeds == 1 || a.spread_seeds == 2)
    throw Error("prt-vs-path: --spread-seeds must be 0 (off) or at least 3");
  if (a.suns.empty() && a.envs.empty())
    throw Error("prt-vs-path: give at least one --sun or --env");
  check_output_folder(a.json_path);
  check_output_folder(a.image_path);
  ThreadLimit limit(a.threads);

  Scene scene = load_scene(a.scene);
  for (Material& m : scene.materials) m.emission = Color(0.0f);
  scene.lights.clear();
  scene.environment.reset();

  std::vector<TestLight> lights;
  for (const std::string& s : a.suns) {
    const std::vector<float> v = numbers(s, "--sun");
    if (v.size() != 4) throw Error(fmt::format("--sun '{}': expected X,Y,Z,E", s));
    TestLight t;
    t.name = "sun " + s;
    t.sh = bake::sun_light(a.bands, vec3(v[0], v[1], v[2]), Color(v[3]));
    t.light.name = "sun";
    t.light.type = LightType::kDirectional;
    t.light.direction = glm::normalize(vec3(v[0], v[1], v[2]));
    t.light.irradiance = Color(v[3]);
    lights.push_back(std::move(t));
  }
  for (const std::string& s : a.envs) {
    const size_t comma = s.rfind(',');
    Environment env;
    env.path = comma == std::string::npos ? s : s.substr(0, comma);
    env.rotation_y =
        comma == std::string::npos ? 0.0f : radians(numbers(s.substr(comma + 1), "--env")[0]);
    env.radiance = read_image(env.path, false);
    TestLight t;
    t.name = "env " + s;
    t.sh = bake::environment_light(a.bands, env);
    t.light.name = "environment";
    t.light.type = LightType::kEnvironment;
    t.env = std::move(env);
    lights.push_back(std::move(t));
  }

  // One bake.
  atlas::make_meshes_unique(scene);
  atlas::AtlasOptions atlas_options;
  atlas_options.resolution = a.resolution;
  const atlas::Atlas atlas = atlas::build_atlas(scene, atlas_options);
  atlas::apply_atlas(scene, atlas);
  const RayTracer tracer(scene);
  atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);
  if (a.push_out) {
    const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(scene, tracer, raster);
    std::printf("texels pushed out of geometry: %lld moved, %lld rejected\n",
                (long long)pushed.moved, (long long)pushed.rejected);
  }
  bake::PrtBakeOptions bake_options = bake::PrtBakeOptions::from_params(
      Params({{"bands", a.bands},
              {"mode", a.mode},
              {"spp", a.bake_spp},
              {"seed", a.seed},
              {"stitch", a.stitch},
              {"shoot_tolerance", a.shoot_tolerance},
              {"shoot_relative_tolerance", a.shoot_relative_tolerance}},
             "prt-vs-path"));
  bake_options.progress = false;
  bake_options.vertices = false;
  // The bake shown, and a second one (the next seed) that only serves to estimate the
  // transfer's Monte-Carlo error.
  std::vector<baked::PrtSet> sets(2);
  bake::PrtBake baked;
  for (size_t k = 0; k < sets.size(); ++k) {
    bake_options.seed = a.seed + k;
    baked = bake::bake_prt(scene, tracer, raster, bake_options);
    sets[k].bands = baked.bands;
    sets[k].mode = baked.mode;
    sets[k].texel_transfer = std::move(baked.texel_transfer);
    std::printf(
        "bake (seed %llu): %s, %d bands, atlas %dx%d, %zu texels, %d rays a texel, %.2f s "
        "(shooting %.2f s, %d rounds, unshot %.3g, relative %.3g; light shot: %.4f to fronts, %.4f "
        "to %lld "
        "back sides, %.4f escaped, %.4f lost, %.4f below the surface)\n",
        (unsigned long long)bake_options.seed, scene.name.c_str(), baked.bands, atlas.width,
        atlas.height, baked.texels, a.bake_spp, baked.seconds, baked.shoot_seconds,
        baked.shoot_rounds, baked.unshot_fraction, baked.relative_unshot, baked.shot_shares.front,
        baked.shot_shares.back, (long long)baked.back_sides, baked.shot_shares.escaped,
        baked.shot_shares.lost, baked.shot_shares.below);
  }
  const baked::PrtSet& set = sets[0];

  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  const int w = a.width, h = a.height;
  // Per-pixel figures use the flat pixels only (bake::pixel_footprints says why); regions use
  // every pixel that sees surface over its whole footprint.
  const std::vector<bake::PixelFootprint> footprints = bake::pixel_footprints(tracer, camera, w, h);
  std::vector<char> surface(footprints.size()), flat(footprints.size());
  for (size_t i = 0; i < footprints.size(); ++i) {
    surface[i] = footprints[i] != bake::PixelFootprint::kMiss;
    flat[i] = footprints[i] == bake::PixelFootprint::kFlat;
  }

  bake::RelightOptions ro;
  ro.width = w;
  ro.height = h;
  ro.samples = a.relight_spp;
  ro.background = false;
  // The relit side's σ from many bakes of the direct transfer of the texels seen (as much of
  // the bake's noise as is heavy-tailed; prt_direct_spread.h says why two runs fall short).
  // Seeds a.seed, a.seed + 1 are the two bakes' own direct transfer (stitching aside).
  std::vector<std::vector<Image>> spread;
  size_t spread_texels = 0;
  if (a.spread_seeds > 0) {
    const auto t0 = std::chrono::steady_clock::now();
    // dilate + 1: an uncovered tap's value comes from texels up to `dilate` passes away.
    const atlas::TexelRaster seen =
        texels_seen(tracer, raster, camera, ro, bake_options.dilate + 1);
    spread_texels = seen.samples.size();
    std::vector<bake::ShLight> shs;
    for (const TestLight& t : lights) shs.push_back(t.sh);
    spread = direct_relit_over_seeds(scene, tracer, seen, shs, camera, ro, bake_options, a.seed,
                                     a.spread_seeds);
    std::printf("direct-transfer spread: %d bakes of %zu texels seen, %.2f s\n", a.spread_seeds,
                spread_texels, seconds_since(t0));
  }

  // Flat pixels whose lookups read only texels of the surface they show (the rest read a
  // dilated border texel, another chart or the far side of a crease: discretization).
  const std::vector<char> interior = interior_lookups(tracer, raster, camera, ro);

  const int cols = 4, gap = 2;
  Image grid(cols * w + (cols - 1) * gap, int(lights.size()) * (h + gap) - gap, 3, 1.0f);
  nlohmann::json out = {{"suite", "prt-vs-path"},
                        {"machine", machine_info()},
                        {"scene", a.scene},
                        {"bands", set.bands},
                        {"mode", a.mode},
                        {"stitch", a.stitch},
                        {"push_out", a.push_out},
                        {"atlas", {atlas.width, atlas.height}},
                        {"texels", baked.texels},
                        {"bake_spp", a.bake_spp},
                        {"bake_seconds", baked.seconds},
                        {"image", {w, h}},
                        {"relight_spp", a.relight_spp},
                        {"path_spp", a.path_spp},
                        {"max_bounces", a.max_bounces},
                        {"region", a.region},
                        {"lights", nlohmann::json::array()}};
  out.update(bake::shooting_record(baked));
  for (size_t li = 0; li < lights.size(); ++li) {
    const TestLight& t = lights[li];
    auto t0 = std::chrono::steady_clock::now();
    const Image relit = bake::relight(scene, tracer, sets[0], t.sh, camera, ro);
    const double relight_s = seconds_since(t0);
    const Image relit2 = bake::relight(scene, tracer, sets[1], t.sh, camera, ro);

    // The band-limited light goes negative where the truncated series rings (a sun above
    // all); the path tracer takes non-negative maps, and transport is linear, so it renders
    // the positive and the negative parts apart and subtracts.
    Environment positive, negative;
    positive.radiance = bake::sh_environment_map(t.sh, 512);
    negative.radiance = positive.radiance;
    bool rings = false;
    for (size_t i = 0; i < positive.radiance.data().size(); ++i) {
      float& p = positive.radiance.data()[i];
      float& q = negative.radiance.data()[i];
      rings = rings || p < 0.0f;
      q = std::max(-p, 0.0f);
      p = std::max(p, 0.0f);
    }
    Light env_light;
    env_light.name = "environment";
    env_light.type = LightType::kEnvironment;
    RenderOptions render;
    render.width = w;
    render.height = h;
    render.spp = a.path_spp;
    render.progress = false;
    t0 = std::chrono::steady_clock::now();
    const auto band_limited = [&](uint64_t seed) {
      render.seed = seed;
      Image image = path_traced(scene, env_light, positive, camera, render, a.max_bounces);
      if (rings) {
        render.seed = seed + 100;
        const Image minus = path_traced(scene, env_light, negative, camera, render, a.max_bounces);
        for (size_t i = 0; i < image.data().size(); ++i) image.data()[i] -= minus.data()[i];
      }
      return image;
    };
    const Image p1 = band_limited(a.seed + 10);
    const Image p2 = band_limited(a.seed + 11);
    render.seed = a.seed + 12;
    const Image truth = path_traced(scene, t.light, t.env, camera, render, a.max_bounces);
    const double path_s = seconds_since(t0);

    // Per pixel (flat pixels): each side's mean of its two runs, and the variance of that
    // mean, (a − b)²/4, pooled over the pixel's flat 3×3 neighbourhood.
    const size_t np = size_t(w) * h;
    std::vector<double> mp(np), mq(np), vp(np), vq(np);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const double r1 = sum_of(relit, x, y), r2 = sum_of(relit2, x, y);
        const double q1 = sum_of(p1, x, y), q2 = sum_of(p2, x, y);
        mp[i] = 0.5 * (r1 + r2);
        mq[i] = 0.5 * (q1 + q2);
        vp[i] = 0.25 * (r1 - r2) * (r1 - r2);
        vq[i] = 0.25 * (q1 - q2) * (q1 - q2);
      }
    // The spread bakes' variance of one bake's pixel, over 2: that of the mean of two.
    std::vector<double> vs(np, 0.0);
    for (size_t i = 0; i < np && !spread.empty(); ++i) {
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      double s1 = 0.0, s2 = 0.0;
      for (const std::vector<Image>& images : spread) {
        const double v = sum_of(images[li], x, y);
        s1 += v;
        s2 += v * v;
      }
      vs[i] = sample_variance(s1, s2, double(spread.size())) / 2.0;
    }
    const auto pooled = [&](const std::vector<double>& v, int x, int y) {
      double sum = 0.0;
      int count = 0;
      for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
        for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx)
          if (flat[size_t(yy) * w + xx]) sum += v[size_t(yy) * w + xx], ++count;
      return sum / double(std::max(count, 1));
    };
    // σ² of a pixel: the path tracer's pooled two-run variance plus the relit side's — the
    // spread bakes' where there are (shadowed: that is the bake's whole noise; interreflected:
    // the larger of it and the pooled two-run variance, which holds the bounce's noise), else
    // the pooled two-run variance. The two-run figures are kept beside for comparison.
    const bool shadowed = a.mode == "shadowed";
    double sum_q = 0.0, sum_d = 0.0, sum_d2 = 0.0, sum_s2 = 0.0, sum_vq = 0.0;
    double sum_s2_two_run = 0.0;
    SigmaTally tally, tally_two_run, tally_interior;
    struct Outlier {
      double t;
      int x, y;
      double relit, path, sigma;
    };
    std::vector<Outlier> outliers;
    double interior_q = 0.0, interior_d = 0.0;
    std::vector<double> spread_sum(spread.size(), 0.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        if (!flat[i]) continue;
        const double d = mp[i] - mq[i];
        const double relit_var_two_run = pooled(vp, x, y);
        const double relit_var = spread.empty() ? relit_var_two_run
                                 : shadowed     ? vs[i]
                                                : std::max(vs[i], relit_var_two_run);
        const double sigma = std::sqrt(relit_var + pooled(vq, x, y));
        const double sigma_two_run = std::sqrt(relit_var_two_run + pooled(vq, x, y));
        sum_q += mq[i];
        sum_d += d;
        sum_d2 += d * d;
        sum_s2 += sigma * sigma;
        sum_s2_two_run += sigma_two_run * sigma_two_run;
        sum_vq += vq[i];
        tally.add(d, sigma);
        tally_two_run.add(d, sigma_two_run);
        if (sigma > 0.0 && std::abs(d) > 5.0 * sigma)
          outliers.push_back({d / sigma, x, y, mp[i], mq[i], sigma});
        if (interior[i]) {
          interior_q += mq[i];
          interior_d += d;
          tally_interior.add(d, sigma);
        }
        for (size_t j = 0; j < spread.size(); ++j) spread_sum[j] += sum_of(spread[j][li], x, y);
      }
    const size_t count = tally.count;
    if (count == 0) throw Error("prt-vs-path: no flat surface pixel in the image");
    const double mean = sum_q / double(count);
    // The bias's standard error. Pixels are not independent on the relit side (neighbours
    // read the same texels, and a texel's error is heavy-tailed), so RMS σ/√count
    // understates it; the spread bakes give the bake's part directly: the spread over seeds
    // of one bake's image mean, over √2 for the mean of two. The path tracer's pixels are
    // independent: its part is √(Σ v_q)/count.
    double bias_se = std::sqrt(sum_vq) / double(count);
    double spread_bias_sd = 0.0;
    if (spread.size() >= 2) {
      double s1 = 0.0, s2 = 0.0;
      for (double v : spread_sum)
        s1 += v / double(count), s2 += (v / double(count)) * (v / double(count));
      spread_bias_sd = std::sqrt(sample_variance(s1, s2, double(spread.size())));
      bias_se = std::sqrt(bias_se * bias_se + spread_bias_sd * spread_bias_sd / 2.0);
    }
    // Per region: means over its pixels, kept where every pixel is a surface.
    const int rs = a.region, rx_n = w / rs, ry_n = h / rs;
    struct Region {
      bool full = true;
      double relit = 0.0, path = 0.0, truth = 0.0, quarter[4] = {0, 0, 0, 0};
    };
    std::vector<Region> regions(size_t(rx_n) * ry_n);
    for (int y = 0; y < ry_n * rs; ++y)
      for (int x = 0; x < rx_n * rs; ++x) {
        Region& r = regions[size_t(y / rs) * rx_n + x / rs];
        const size_t i = size_t(y) * w + x;
        if (!surface[i]) r.full = false;
        const double inv = 1.0 / double(rs * rs);
        r.relit += mp[i] * inv;
        r.path += mq[i] * inv;
        r.truth += sum_of(truth, x, y) * inv;
        r.quarter[2 * ((y % rs) * 2 / rs) + (x % rs) * 2 / rs] += sum_of(truth, x, y) * 4.0 * inv;
      }
    std::vector<double> band_all, band_smooth, relit_true_smooth, region_rel;
    for (const Region& r : regions) {
      if (!r.full || r.path <= 0.0 || r.truth <= 0.0) continue;
      region_rel.push_back(std::abs(r.relit - r.path) / r.path);
      const double band = std::abs(r.path - r.truth) / r.truth;
      band_all.push_back(band);
      const double q_mean = 0.25 * (r.quarter[0] + r.quarter[1] + r.quarter[2] + r.quarter[3]);
      bool smooth = q_mean > 0.0;
      for (double q : r.quarter) smooth = smooth && std::abs(q - q_mean) <= 0.25 * q_mean;
      if (smooth) {
        band_smooth.push_back(band);
        relit_true_smooth.push_back(std::abs(r.relit - r.truth) / r.truth);
      }
    }
    const auto stats = [](std::vector<double> v) {
      if (v.empty()) return nlohmann::json{{"regions", 0}};
      return nlohmann::json{{"regions", v.size()},
                            {"median", percentile(v, 0.5)},
                            {"max", *std::max_element(v.begin(), v.end())}};
    };
    const auto biggest = [](const std::vector<double>& v) {
      return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
    };
    nlohmann::json row = {{"light", t.name},
                          {"relight_seconds", relight_s},
                          {"path_seconds", path_s},
                          {"band_limited_light_negative", rings},
                          {"flat_pixels", count},
                          {"relit_vs_path_bias", sum_d / double(count) / mean},
                          {"relit_vs_path_rms", std::sqrt(sum_d2 / double(count)) / mean},
                          {"sigma_rms", std::sqrt(sum_s2 / double(count)) / mean},
                          {"pixels_within_3_sigma", tally.share3()},
                          {"pixels_within_5_sigma", tally.share5()},
                          {"worst_d_over_sigma", tally.worst},
                          {"bias_standard_error", bias_se / mean},
                          {"interior_pixels", tally_interior.count},
                          {"interior_bias", interior_q > 0.0 ? interior_d / interior_q : 0.0},
                          {"interior_within_3_sigma", tally_interior.share3()},
                          {"interior_within_5_sigma", tally_interior.share5()},
                          {"interior_worst_d_over_sigma", tally_interior.worst},
                          {"spread_seeds", spread.size()},
                          {"spread_texels", spread_texels},
                          {"spread_bias_sd", spread_bias_sd / mean},
                          {"two_run_sigma_rms", std::sqrt(sum_s2_two_run / double(count)) / mean},
                          {"two_run_within_3_sigma", tally_two_run.share3()},
                          {"two_run_within_5_sigma", tally_two_run.share5()},
                          {"two_run_worst_d_over_sigma", tally_two_run.worst},
                          {"relit_vs_path_region", stats(region_rel)},
                          {"band_limiting_all_regions", stats(band_all)},
                          {"band_limiting_smooth_regions", stats(band_smooth)},
                          {"relit_vs_true_smooth_regions", stats(relit_true_smooth)}};
    std::printf(
        "%s%s: relight %.3f s, path %.1f s\n"
        "  relit vs band-limited path, %zu flat pixels (relative to the mean %.4g): bias %+.4f, "
        "± %.4f (%.1f se; one bake's image mean spreads %.4f over %zu seeds), rms %.4f, rms sigma "
        "%.4f; within 3 sigma %.4f, within 5 sigma %.4f, worst %.2f sigma (two-run sigma: rms "
        "%.4f, within 3 %.4f, within 5 %.4f, worst %.2f)\n"
        "  interior lookups, %zu flat pixels: bias %+.4f, within 3 sigma %.4f, within 5 sigma "
        "%.4f, worst %.2f sigma\n"
        "  per region (%zu): median %.4f, max %.4f\n"
        "  band-limiting error (path, true vs band-limited light): all regions median %.4f max "
        "%.4f; smooth regions (%zu) median %.4f max %.4f; relit vs true light on smooth regions "
        "median %.4f max %.4f\n",
        t.name.c_str(), rings ? " (band-limited light rings negative)" : "", relight_s, path_s,
        count, mean, sum_d / double(count) / mean, bias_se / mean,
        bias_se > 0.0 ? std::abs(sum_d / double(count)) / bias_se : 0.0, spread_bias_sd / mean,
        spread.size(), std::sqrt(sum_d2 / double(count)) / mean,
        std::sqrt(sum_s2 / double(count)) / mean, tally.share3(), tally.share5(), tally.worst,
        std::sqrt(sum_s2_two_run / double(count)) / mean, tally_two_run.share3(),
        tally_two_run.share5(), tally_two_run.worst, tally_interior.count,
        interior_q > 0.0 ? interior_d / interior_q : 0.0, tally_interior.share3(),
        tally_interior.share5(), tally_interior.worst, region_rel.size(),
        percentile(region_rel, 0.5), biggest(region_rel), percentile(band_all, 0.5),
        biggest(band_all), band_smooth.size(), percentile(band_smooth, 0.5), biggest(band_smooth),
        percentile(relit_true_smooth, 0.5), biggest(relit_true_smooth));
    // The worst pixels, to look at (x right, y down, as the grid).
    std::sort(outliers.begin(), outliers.end(),
              [](const Outlier& p, const Outlier& q) { return std::abs(p.t) > std::abs(q.t); });
    nlohmann::json worst_pixels = nlohmann::json::array();
    for (size_t k = 0; k < std::min<size_t>(outliers.size(), 8); ++k) {
      const Outlier& o = outliers[k];
      worst_pixels.push_back({{"x", o.x},
                              {"y", o.y},
                              {"d_over_sigma", o.t},
                              {"relit", o.relit / mean},
                              {"path", o.path / mean},
                              {"interior", bool(interior[size_t(o.y) * w + o.x])}});
      std::printf("  beyond 5 sigma: pixel (%d, %d) %+.1f sigma, relit %.4g path %.4g (x mean)%s\n",
                  o.x, o.y, o.t, o.relit / mean, o.path / mean,
                  interior[size_t(o.y) * w + o.x] ? ", interior lookups" : "");
    }
    row["worst_pixels"] = worst_pixels;
    std::fflush(stdout);
    out["lights"].push_back(row);

    // The grid row, exposed so the 95th percentile of the band-limited path image is 0.8.
    std::vector<double> values;
    for (size_t i = 0; i < mq.size(); ++i)
      if (surface[i]) values.push_back(mq[i] / 3.0);
    const float exposure = float(0.8 / std::max(1e-12, percentile(values, 0.95)));
    const Image* shown[3] = {&relit, &p1, &truth};  // the second column: one of the two runs
    const int top = int(li) * (h + gap);
    for (int c = 0; c < cols; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t i = size_t(y) * w + x;
          const double d = sum_of(relit, x, y) - mq[i];
          Color v;
          if (c < 3)
            v = tone_map(shown[c]->rgb(x, y) * exposure, ToneMapper::kClamp);
          else if (surface[i])  // |relit − path| ×4 on the same exposure, grey
            v = Color(std::min(1.0f, float(std::abs(d) / 3.0) * exposure * 4.0f));
          else  // no surface: dark blue
            v = Color(0.0f, 0.0f, 0.25f);
          grid.set_rgb(c * (w + gap) + x, top + y, v);
        }
  }
  if (!a.image_path.empty()) write_image(a.image_path, grid);
  if (!a.json_path.empty()) write_json(a.json_path, out);
  return 0;
}

}  // namespace illum::bench
