// `illum-bench converge SCENE`: equal-noise efficiency, 1 / (relative variance × seconds),
// of illum's path tracer over a series of sample counts, and of Blender Cycles on the same
// scene when a peer is asked for (or `blender` is on PATH). The estimator is in
// converge_stats.h; the peer's scene comes from peer_export.h and bench/peers/cycles_peer.py.
//
// Per renderer: a reference at --reference-spp (cached in --out, seed + 1000), then at each
// N of --spp two renders with seeds K and K + 1, timed (render call only: illum's ray
// tracer and Cycles' scene sync and BVH are built before the clock starts).
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "converge_stats.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/render/integrator.h"
#include "illum/render/render_setup.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "peer_export.h"
#include "plot_png.h"
#include "suites.h"

#ifndef ILLUM_BENCH_PEERS_DIR
#define ILLUM_BENCH_PEERS_DIR "bench/peers"
#endif

namespace illum::bench {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kReferenceSeedOffset = 1000;

struct Render {
  int spp = 0;
  uint64_t seed = 0;
  std::string exr;
  double seconds = 0.0;
  double cpu_seconds = 0.0;  // process CPU time, all threads
  Image image;
};

struct Point {  // one sample count of one renderer
  int spp = 0;
  double seconds = 0.0;      // mean of the two renders
  double cpu_seconds = 0.0;  // the same in CPU time, which other processes disturb less
  RelativeVariance variance;
  double efficiency = 0.0, efficiency_cpu = 0.0;
};

struct RendererResult {
  std::string name;
  Image reference;
  std::string reference_file;
  double reference_seconds = 0.0;  // 0: taken from the cache
  std::vector<Point> points;
  nlohmann::json extra = nlohmann::json::object();
};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream ss(path);
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
  return false;
}

std::vector<Point> evaluate(const std::vector<Render>& renders, const Image& reference) {
  std::vector<Point> points;
  for (size_t i = 0; i + 1 < renders.size(); i += 2) {
    const Render &a = renders[i], &b = renders[i + 1];
    Point p;
    p.spp = a.spp;
    p.seconds = 0.5 * (a.seconds + b.seconds);
    p.variance = relative_variance(a.image, b.image, reference);
    p.efficiency = efficiency(p.variance.value, p.seconds);
    p.cpu_seconds = 0.5 * (a.cpu_seconds + b.cpu_seconds);
    p.efficiency_cpu = efficiency(p.variance.value, p.cpu_seconds);
    points.push_back(p);
  }
  return points;
}

// The region (of a 4×4 grid) where mean(peer) / mean(illum) is furthest from the whole
// image's ratio: where a mismatch of the scenes would show first.
nlohmann::json mean_match(const Image& illum_ref, const Image& peer_ref) {
  constexpr int kGrid = 4;
  const int w = illum_ref.width(), h = illum_ref.height();
  double si[kGrid * kGrid] = {}, sp[kGrid * kGrid] = {};
  Color ci(0.0f), cp(0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Color a = illum_ref.rgb(x, y), b = peer_ref.rgb(x, y);
      const int r = (y * kGrid / h) * kGrid + x * kGrid / w;
      si[r] += a.r + a.g + a.b;
      sp[r] += b.r + b.g + b.b;
      ci += a;
      cp += b;
    }
  const double overall = image_mean(peer_ref) / image_mean(illum_ref);
  double worst = overall;
  int worst_region = -1;
  for (int r = 0; r < kGrid * kGrid; ++r) {
    if (!(si[r] > 0.0)) continue;
    const double q = sp[r] / si[r];
    if (worst_region < 0 || std::abs(q - overall) > std::abs(worst - overall))
      worst = q, worst_region = r;
  }
  return {{"ratio_peer_over_illum", overall},
          {"ratio_rgb", {cp.r / ci.r, cp.g / ci.g, cp.b / ci.b}},
          {"worst_region", worst_region},
          {"worst_region_ratio", worst}};
}

void print_points(const RendererResult& r) {
  std::printf("  %-7s %6s %10s %10s %12s %10s %12s %12s\n", r.name.c_str(), "spp", "seconds",
              "cpu s", "rel.var", "rel.err", "efficiency", "eff. (cpu)");
  for (const Point& p : r.points)
    std::printf("  %-7s %6d %10.3f %10.3f %12.4e %10.4f %12.4g %12.4g\n", "", p.spp, p.seconds,
                p.cpu_seconds, p.variance.value, std::sqrt(p.variance.value), p.efficiency,
                p.efficiency_cpu);
}

nlohmann::json points_json(const RendererResult& r) {
  nlohmann::json a = nlohmann::json::array();
  for (const Point& p : r.points)
    a.push_back({{"spp", p.spp},
                 {"seconds", p.seconds},
                 {"relative_variance", p.variance.value},
                 {"epsilon", p.variance.epsilon},
                 {"relative_error", std::sqrt(p.variance.value)},
                 {"efficiency", p.efficiency},
                 {"cpu_seconds", p.cpu_seconds},
                 {"efficiency_cpu", p.efficiency_cpu}});
  return a;
}

}  // namespace

int run_converge(SuiteArgs args) {
  CLI::App app("converge: equal-noise efficiency 1/(variance x time), illum vs Blender Cycles",
               "illum-bench converge");
  std::string scene_arg, out_dir = "bench-out/converge", peer = "auto", blender = "blender",
                         peer_script = std::string(ILLUM_BENCH_PEERS_DIR) + "/cycles_peer.py",
                         json_path, plot_path;
  int width = 256, height = 256, reference_spp = 1024, max_bounces = 8, threads = 0;
  std::vector<int> spp_series{16, 64, 256};
  std::vector<std::string> path_params;  // key=value for illum's path integrator
  uint64_t seed = 1;
  app.add_option("scene", scene_arg, "built-in scene name or scene file")->required();
  app.add_option("--width", width, "image width")
      ->capture_default_str()
      ->check(CLI::Range(8, 8192));
  app.add_option("--height", height, "image height")
      ->capture_default_str()
      ->check(CLI::Range(8, 8192));
  app.add_option("--spp", spp_series, "sample counts of the series (two renders each)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--reference-spp", reference_spp, "reference samples per pixel (cached in --out)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 24));
  app.add_option("--max-bounces", max_bounces, "illum's path length limit (Cycles gets one less)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  app.add_option("--threads", threads, "threads for both renderers (0 = all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  app.add_option("--seed", seed, "seed of the first render of each pair")->capture_default_str();
  app.add_option("--out", out_dir, "folder for renders, references, peer scene and plot")
      ->capture_default_str();
  app.add_option("--peer", peer, "peer renderer: auto (cycles if blender is on PATH), cycles, none")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "cycles", "none"}));
  app.add_option("--blender", blender, "Blender executable")->capture_default_str();
  app.add_option("--peer-script", peer_script, "the Cycles peer's Blender script")
      ->capture_default_str();
  app.add_option("--plot", plot_path,
                 "PNG of relative error against time (default OUT/converge-SCENE.png)");
  app.add_option("--json", json_path, "write the results to this JSON file");
  app.add_option("-p,--param", path_params,
                 "illum path integrator parameter key=value (repeatable), e.g. rr_depth=2, to "
                 "weigh a setting that keeps the estimate unbiased: a cached reference is "
                 "reused whatever they are");
  if (!parse_args(app, args)) return 0;
  nlohmann::json path_json = nlohmann::json::object();
  for (const std::string& kv : path_params) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == kv.size())
      throw Error(fmt::format("converge: --param '{}' must look like key=value", kv));
    const std::string key = kv.substr(0, eq), text = kv.substr(eq + 1);
    if (key == "max_bounces" || path_json.contains(key))
      throw Error(fmt::format("converge: --param '{}' is given twice (or is --max-bounces)", key));
    const nlohmann::json value = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    path_json[key] = value.is_discarded() ? nlohmann::json(text) : value;
  }
  path_json["max_bounces"] = max_bounces;
  check_output_folder(json_path);
  check_output_folder(plot_path);
  std::sort(spp_series.begin(), spp_series.end());
  spp_series.erase(std::unique(spp_series.begin(), spp_series.end()), spp_series.end());
  const bool want_peer =
      peer == "cycles" || (peer == "auto" && (blender.find('/') != std::string::npos
                                                  ? ::access(blender.c_str(), X_OK) == 0
                                                  : on_path(blender)));
  if (peer == "cycles" && blender.find('/') == std::string::npos && !on_path(blender))
    throw Error(fmt::format("converge: --peer cycles: '{}' is not on PATH", blender));
  if (want_peer && !fs::is_regular_file(peer_script))
    throw Error(fmt::format("converge: --peer-script '{}' does not exist", peer_script));
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec)
    throw Error(
        fmt::format("converge: cannot create --out folder '{}': {}", out_dir, ec.message()));
  const int thread_count = threads > 0 ? threads : ThreadLimit::hardware_threads();

  const Scene scene = load_scene(scene_arg);
  const RayTracer tracer(scene);
  const Camera camera = scene_camera(scene, static_cast<float>(width) / static_cast<float>(height));
  const std::string stem = fs::path(scene.name).stem().string();
  const std::string key = fmt::format("{}-{}x{}-b{}", stem, width, height, max_bounces);
  const std::string plot_file =
      plot_path.empty() ? fmt::format("{}/converge-{}.png", out_dir, key) : plot_path;
  std::printf("converge %s %dx%d, max_bounces %d (illum), %d threads, spp", stem.c_str(), width,
              height, max_bounces, thread_count);
  for (int n : spp_series) std::printf(" %d", n);
  std::printf(", reference %d spp\n", reference_spp);
  std::fflush(stdout);

  // --- illum --------------------------------------------------------------------------------
  auto illum_render = [&](int spp, uint64_t s) {
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.spp = spp;
    o.seed = s;
    o.threads = threads;
    o.progress = false;
    std::unique_ptr<Integrator> integrator =
        Integrator::create("path", Params(path_json, "illum-bench converge"));
    Render r;
    r.spp = spp;
    r.seed = s;
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    r.image = integrator->render(tracer, camera, o);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    return r;
  };
  RendererResult illum;
  illum.name = "illum";
  illum.reference_file =
      fmt::format("{}/reference-illum-{}-{}spp.exr", out_dir, key, reference_spp);
  if (fs::exists(illum.reference_file)) {
    illum.reference = read_image(illum.reference_file, false);
  } else {
    Render ref = illum_render(reference_spp, seed + kReferenceSeedOffset);
    illum.reference = std::move(ref.image);
    illum.reference_seconds = ref.seconds;
    ImageWriteOptions w;
    w.exr_half = false;
    write_image(illum.reference_file, illum.reference, w);
  }
  if (illum.reference.width() != width || illum.reference.height() != height)
    throw Error(fmt::format("{}: cached reference is {}x{}, not {}x{}", illum.reference_file,
                            illum.reference.width(), illum.reference.height(), width, height));
  std::vector<Render> illum_renders;
  for (int n : spp_series)
    for (uint64_t s : {seed, seed + 1}) {
      illum_renders.push_back(illum_render(n, s));
      ImageWriteOptions w;
      w.exr_half = false;
      illum_renders.back().exr = fmt::format("{}/illum-{}-{}spp-seed{}.exr", out_dir, key, n, s);
      write_image(illum_renders.back().exr, illum_renders.back().image, w);
    }
  illum.points = evaluate(illum_renders, illum.reference);

  // --- Cycles -------------------------------------------------------------------------------
  std::optional<RendererResult> cycles;
  if (want_peer) {
    RendererResult c;
    c.name = "cycles";
    const std::string peer_dir = out_dir + "/peer";
    fs::create_directories(peer_dir, ec);
    if (ec) throw Error(fmt::format("converge: cannot create '{}': {}", peer_dir, ec.message()));
    const std::string scene_stem = fmt::format("{}/{}", peer_dir, key);
    PeerRenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.max_bounces = max_bounces;
    export_peer_scene(scene, camera, settings, scene_stem);
    c.reference_file = fmt::format("{}/reference-cycles-{}-{}spp.exr", out_dir, key, reference_spp);
    nlohmann::json jobs;
    jobs["scene"] = fs::absolute(scene_stem + ".json").string();
    jobs["threads"] = thread_count;
    jobs["renders"] = nlohmann::json::array();
    const bool render_reference = !fs::exists(c.reference_file);
    if (render_reference)
      jobs["renders"].push_back({{"spp", reference_spp},
                                 {"seed", seed + kReferenceSeedOffset},
                                 {"exr", fs::absolute(c.reference_file).string()}});
    std::vector<Render> renders;
    for (int n : spp_series)
      for (uint64_t s : {seed, seed + 1}) {
        Render r;
        r.spp = n;
        r.seed = s;
        r.exr =
            fs::absolute(fmt::format("{}/cycles-{}-{}spp-seed{}.exr", out_dir, key, n, s)).string();
        jobs["renders"].push_back({{"spp", n}, {"seed", s}, {"exr", r.exr}});
        renders.push_back(r);
      }
    const std::string timings = fs::absolute(scene_stem + "-timings.json").string();
    fs::remove(timings, ec);
    jobs["timings"] = timings;
    const std::string jobs_file = scene_stem + "-jobs.json";
    write_json(jobs_file, jobs);
    const std::string log_file = scene_stem + "-blender.log";
    const std::string command = fmt::format(
        "{} -b --factory-startup --python-exit-code 1 --python {} -- --jobs {} > {} 2>&1",
        shell_quote(blender), shell_quote(peer_script),
        shell_quote(fs::absolute(jobs_file).string()), shell_quote(log_file));
    std::printf("  running Blender Cycles (log: %s)\n", log_file.c_str());
    std::fflush(stdout);
    if (std::system(command.c_str()) != 0 || !fs::exists(timings))
      throw Error(fmt::format("converge: the Cycles peer failed; see {}", log_file));
    nlohmann::json t;
    {
      std::ifstream in(timings);
      in >> t;
    }
    size_t k = 0;
    if (render_reference) c.reference_seconds = t["renders"][k++]["seconds"].get<double>();
    for (Render& r : renders) {
      const nlohmann::json& tr = t["renders"].at(k++);
      if (tr["exr"].get<std::string>() != r.exr)
        throw Error(fmt::format("converge: {} lists {} where {} was expected", timings,
                                tr["exr"].get<std::string>(), r.exr));
      r.seconds = tr["seconds"].get<double>();
      r.cpu_seconds = tr["cpu_seconds"].get<double>();
      r.image = read_image(r.exr, false);
    }
    c.reference = read_image(c.reference_file, false);
    c.points = evaluate(renders, c.reference);
    c.extra = {{"blender", t.value("blender", "")},
               {"settings", t.value("settings", nlohmann::json::object())},
               {"scene_json", scene_stem + ".json"}};
    cycles = std::move(c);
  }

  // --- report -------------------------------------------------------------------------------
  std::printf(
      "  efficiency = 1 / (relative variance x seconds per render); rel.err = sqrt(rel.var)\n");
  print_points(illum);
  if (cycles) print_points(*cycles);
  nlohmann::json j;
  j["suite"] = "converge";
  j["scene"] = scene_arg;
  j["width"] = width;
  j["height"] = height;
  j["max_bounces"] = max_bounces;
  j["spp"] = spp_series;
  j["seed"] = seed;
  j["threads"] = thread_count;
  j["reference_spp"] = reference_spp;
  j["relative_floor"] = kRelativeFloor;
  j["machine"] = machine_info();
  std::vector<std::string> warnings;
  auto renderer_json = [&](const RendererResult& r) {
    const Point& last = r.points.back();
    const double ref_var =
        reference_relative_variance(last.variance.value, last.spp, reference_spp);
    if (ref_var > kMaxReferenceVariance)
      warnings.push_back(fmt::format(
          "  WARNING: {} reference's own relative variance {:.3g} > {:.3g}: raise --reference-spp",
          r.name, ref_var, kMaxReferenceVariance));
    nlohmann::json o = {{"reference", r.reference_file},
                        {"reference_seconds", r.reference_seconds},
                        {"reference_relative_variance", ref_var},
                        {"reference_mean", image_mean(r.reference)},
                        {"points", points_json(r)}};
    o.update(r.extra);
    return o;
  };
  j["illum"] = renderer_json(illum);
  std::printf("  reference relative variance (estimated): illum %.3g",
              j["illum"]["reference_relative_variance"].get<double>());
  if (cycles) {
    j["cycles"] = renderer_json(*cycles);
    std::printf(", cycles %.3g", j["cycles"]["reference_relative_variance"].get<double>());
  }
  std::printf("\n");
  for (const std::string& w : warnings) std::printf("%s\n", w.c_str());

  LogLogPlot plot;
  plot.title = fmt::format("{} {}x{}: relative error vs time", stem, width, height);
  plot.x_label = "seconds per render";
  plot.y_label = "relative error";
  plot.guide = true;
  plot.guide_label = "slope -1/2";
  auto series = [&](const RendererResult& r, std::array<float, 3> rgb) {
    PlotSeries s;
    s.label = r.name;
    s.rgb = rgb;
    for (const Point& p : r.points) {
      s.x.push_back(p.seconds);
      s.y.push_back(std::sqrt(p.variance.value));
      s.point_labels.push_back(fmt::format("{}", p.spp));
    }
    return s;
  };
  plot.series.push_back(series(illum, {0.12f, 0.35f, 0.75f}));
  if (cycles) {
    plot.series.push_back(series(*cycles, {0.9f, 0.45f, 0.05f}));
    nlohmann::json ratios = nlohmann::json::array();
    double log_sum = 0.0, log_sum_cpu = 0.0;
    std::printf("  efficiency ratio illum/cycles (wall time; CPU time):");
    for (size_t i = 0; i < illum.points.size(); ++i) {
      const double q = illum.points[i].efficiency / cycles->points[i].efficiency;
      const double var_q = illum.points[i].variance.value / cycles->points[i].variance.value;
      const double time_q = illum.points[i].seconds / cycles->points[i].seconds;
      const double q_cpu = illum.points[i].efficiency_cpu / cycles->points[i].efficiency_cpu;
      log_sum_cpu += std::log(q_cpu);
      ratios.push_back({{"spp", illum.points[i].spp},
                        {"efficiency_ratio", q},
                        {"efficiency_ratio_cpu", q_cpu},
                        {"variance_ratio", var_q},
                        {"time_ratio", time_q}});
      log_sum += std::log(q);
      std::printf("\n    %5d spp: %.3f; %.3f  (variance x%.3f, wall time x%.3f)",
                  illum.points[i].spp, q, q_cpu, var_q, time_q);
    }
    const double geo = std::exp(log_sum / static_cast<double>(illum.points.size()));
    const double geo_cpu = std::exp(log_sum_cpu / static_cast<double>(illum.points.size()));
    std::printf(
        "\n  efficiency ratio illum/cycles, geometric mean over the series: %.3f (CPU time: "
        "%.3f)\n",
        geo, geo_cpu);
    j["efficiency_ratio_cpu_geometric_mean"] = geo_cpu;
    const nlohmann::json match = mean_match(illum.reference, cycles->reference);
    std::printf(
        "  reference means: cycles/illum %.4f (R %.4f G %.4f B %.4f), furthest 4x4 region %d: "
        "%.4f\n",
        match["ratio_peer_over_illum"].get<double>(), match["ratio_rgb"][0].get<double>(),
        match["ratio_rgb"][1].get<double>(), match["ratio_rgb"][2].get<double>(),
        match["worst_region"].get<int>(), match["worst_region_ratio"].get<double>());
    j["ratios"] = ratios;
    j["efficiency_ratio_geometric_mean"] = geo;
    j["reference_mean_match"] = match;
  }
  write_loglog_png(plot, plot_file);
  std::printf("  plot: %s\n", plot_file.c_str());
  j["plot"] = plot_file;
  if (!json_path.empty()) write_json(json_path, j);
  return 0;
}

}  // namespace illum::bench
