// `illum-bench raster FRAME.json...`: every pass of `illum frame --json` runs beside the bound
// of the device it ran on. The bounds are measured here, on the same device, in this run:
//
// * raster: for each attachment configuration a pass's passing fragments use (size, colour
//   formats, depth format; the fragment passes and writes the depth, passes a depth test
//   only, writes or tests only the stencil, blends), a trivial full-screen pass doing
//   exactly that (shaders/bound_fill*: one triangle, a constant colour), as 1 and as 8
//   stacked layers in one rendering: the slope is the time per full-screen layer, one
//   layer's time minus it the rendering's fixed cost for that attachment set. A pass's work is
//   counted in `illum frame`'s counting frame with occlusion queries: the fragments that pass its
//   tests, and all it rasterizes (its draws again, untested) minus those, the rejected ones; its
//   raster bound is, over its renderings, Σ fixed cost + count × the per-layer time (count:
//   fragments / pixels, so coverage and overdraw both count), rejected fragments at the
//   per-layer time of a full-screen rejected layer (hierarchical Z discarding whole tiles:
//   the cheapest rejection), without a fixed cost of their own.
// * geometry: the triangles a pass submits times the per-triangle time of culled one-point
//   triangles (shaders/bound_tris.vert: vertex work and assembly, no setup, no pixel); where
//   the counting frame also counted the triangles that left clipping (pipeline statistics),
//   those are bounded by the mixed and quad bounds below, which set them up on the pass's own
//   attachments. (They were charged here at the setup rate of sub-pixel triangles on a 1024²
//   target, shaders/bound_setup.vert; but that rate depends on the target: the mixed pass set
//   up the d16 cascades' 251k triangles on 4 × 512² with their 4.5 passing layers on top in
//   0.155 ms, where the 1024² rate charged 0.222 for the triangles alone — a bound above work
//   the chip was measured doing: bench/results/raster.md, "H200 device rates".)
// * mixed: where the triangles that left clipping were counted, a trivial pass draws that
//   many set-up triangles covering no sample interleaved with full-target rectangles making
//   the pass's passing layers, into each rendering's attachments (shaders/bound_mixed.vert):
//   the cheapest triangles and the cheapest fragments of the same counts, together, so how
//   the chip overlaps triangle setup with pixel work is measured, not assumed. (Regular grids
//   of equal triangles were tried first: for the cascades' 282k triangles on 4 × 512² they
//   took longer than the pass itself — the same counts, arranged more expensively than the
//   scene's mix of tiny and large triangles — so they bound nothing.) The culled triangles and
//   rejected fragments are added as above.
// * quads: the mixed pass again with the passing layers made of the quads the pass shaded —
//   a fragment shader runs in 2×2 quads, and a quad holding one passing sample occupies the
//   lanes of four — counted in the counting frame by shaders/quad_count.frag (the pass
//   replayed with its own vertex stage and tests; its passing samples must equal the
//   occlusion query's, or the bench stops), as 4 × quads samples of whole quads.
// * shading: for a fragment pass whose work is per-fragment lighting (the forward pass),
//   `illum frame` times that lighting with no scene geometry — one full-screen pass running
//   the pass's light loop over a G-buffer of the same view, each covered pixel once
//   (realtime/measure/shading_bound.h) — and the bench scales its per-pixel part to the lanes the
//   pass ran, 4 × its quads per covered pixel: shading = fixed + (full-screen − fixed) ×
//   4 · quads / pixels, `fixed` the pass's attachment set's fixed cost (the same attachments,
//   rendered once by both). Without a quad count the scale is 1 (each covered pixel once,
//   still at most what the pass shades).
// * memory: a buffer-to-buffer copy of --bandwidth-mib MiB gives the device's copy
//   bandwidth (bytes read + written per second); a compute pass's bound is the bytes of the
//   images and buffers it declares (each read once and written once) at that bandwidth.
//
// A pass's bound is the largest of these: each is work the pass does, done alone. Passes whose
// median is under 20 µs are listed as dispatch-bound (launch and barrier cost, not their
// work). Arithmetic is bounded only where it was timed (the shading bound: the pass's own
// lighting code on its own pixels); no pass declares its operation count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/context.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/gpu/pipeline.h"
#include "raster_passes.h"
#include "suites.h"

namespace illum::bench {

namespace {

constexpr double kDispatchBoundMs = 0.020;

using Depth = gpu::RasterFill::Depth;

bool rejected(const gpu::RasterFill& f) {
  return f.depth == Depth::kReject || f.depth == Depth::kStencilZFail;
}

gpu::RasterFill fill_from_json(const nlohmann::json& j, const std::string& file) {
  gpu::RasterFill f;
  try {
    f.width = j.at("width").get<uint32_t>();
    f.height = j.at("height").get<uint32_t>();
    for (const auto& c : j.at("colors")) f.colors.push_back(c.at("format").get<VkFormat>());
    f.depth_format = j.at("depth_format").get<VkFormat>();
    const int depth = j.at("depth").get<int>();
    if (depth < 0 || depth > static_cast<int>(Depth::kStencilZFail))
      throw Error(fmt::format("{}: unknown depth mode {}", file, depth));
    f.depth = static_cast<Depth>(depth);
    f.blend = j.at("blend").get<bool>();
    f.uncleared = j.value("uncleared", 0u);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: a pass's work is malformed ({})", file, e.what()));
  }
  if (f.width == 0 || f.height == 0 || f.width > 16384 || f.height > 16384)
    throw Error(fmt::format("{}: fill size {}x{} outside 1..16384", file, f.width, f.height));
  if (f.colors.size() > 4)
    throw Error(fmt::format("{}: {} colour attachments (the bound passes have at most 4)", file,
                            f.colors.size()));
  if ((f.depth == Depth::kNone) != (f.depth_format == VK_FORMAT_UNDEFINED))
    throw Error(fmt::format("{}: a fill's depth mode and depth format disagree", file));
  return f;
}

struct Row {
  std::string name;
  int depth = 0;
  double median_ms = 0.0;
  bool has_work = false;
  double raster_ms = 0.0, memory_ms = 0.0, geometry_ms = 0.0;  // own work's bounds
  double mixed_ms = 0.0;
  double quads_ms = 0.0;  // the mixed bound with the passing samples' quads made whole
  // The shading bound (fragment lighting passes: realtime/measure/shading_bound.h), 0 if none.
  double shading_ms = 0.0;
  nlohmann::json shading;  // how it was made (JSON)
  std::vector<std::string> details;
  double largest() const {
    return std::max({raster_ms, memory_ms, geometry_ms, mixed_ms, quads_ms, shading_ms});
  }
};

}  // namespace

int run_raster(SuiteArgs args) {
  CLI::App app("illum-bench raster",
               "each pass of `illum frame --json` runs beside the raster or memory bound of this "
               "device");
  std::vector<std::string> files;
  int repeats = 20;
  int bandwidth_mib = 256;
  std::string json_path, device;
  app.add_option("frames", files, "JSON files written by `illum frame --json` on this device")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--repeats", repeats, "timed repetitions of each bound pass (median)")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  app.add_option("--bandwidth-mib", bandwidth_mib, "buffer size of the copy-bandwidth pass")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  app.add_option("--device", device, "pick the Vulkan device whose name contains this");
  app.add_option("--json", json_path, "also write the table as JSON");
  if (!parse_args(app, args)) return 0;
  check_output_folder(json_path);

  std::vector<nlohmann::json> frames;
  for (const std::string& file : files) {
    std::ifstream in(file);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("passes") || !j["passes"].is_array() ||
        !j.contains("device"))
      throw Error(fmt::format("{}: not a JSON file of `illum frame --json`", file));
    frames.push_back(std::move(j));
  }

  gpu::ContextOptions options;
  options.device_filter = device;
  gpu::Context ctx(options);
  if (!ctx.timestamps())
    throw Error(fmt::format("device '{}' has no timestamp queries", ctx.device_name()));
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i]["device"] != ctx.device_name())
      throw Error(fmt::format("{}: timed on '{}', this device is '{}' (--device picks one)",
                              files[i], frames[i]["device"].get<std::string>(), ctx.device_name()));

  // Every distinct fill, measured once.
  std::map<std::string, gpu::RasterFill> fills;
  for (size_t i = 0; i < frames.size(); ++i)
    for (const auto& p : frames[i]["passes"])
      if (p.contains("work"))
        for (const auto& f : p["work"].at("fills")) {
          const gpu::RasterFill fill = fill_from_json(f, files[i]);
          fills.emplace(fill.key(), fill);
        }
  std::printf("illum-bench raster: device '%s' (%s), %d repetitions a bound\n",
              ctx.device_name().c_str(), ctx.driver().c_str(), repeats);
  std::vector<double> copy_runs;
  const double bytes_per_ms =
      copy_bytes_per_ms(ctx, VkDeviceSize(bandwidth_mib) << 20, repeats, &copy_runs);
  std::printf("  copy bandwidth %.1f GB/s (%d MiB buffer-to-buffer, read + written)\n",
              bytes_per_ms * 1e-6, bandwidth_mib);
  double most_triangles = 0.0;
  for (const auto& fr : frames)
    for (const auto& p : fr["passes"])
      if (p.contains("work"))
        most_triangles = std::max(most_triangles, p["work"].value("triangles", 0.0));
  // At least 64k triangles, so launch overhead does not dominate the rate.
  const uint32_t measured_triangles =
      static_cast<uint32_t>(std::clamp(most_triangles, 65536.0, 16777216.0));
  // The cheapest triangles: the bound's triangles share their vertices in patches of 1–8
  // cells a side, placed row by row or scattered over the target, and every arrangement is
  // timed with its vertex shader invocations counted. On the H200 a vertex costs about as much
  // as setting up a triangle, so a bound shading three vertices a triangle is beaten by a scene
  // ordered for vertex reuse; and the cheapest arrangement (4×4 patches: 25 vertices for 32
  // triangles, one hardware batch) reuses more than any mesh drawn through the chip's batches.
  // A pass is therefore bounded by the fastest arrangement that runs no more vertices a
  // triangle than the pass itself ran (its counting frame counts them), and by the fastest of
  // all where it did not count them.
  struct Arrangement {
    uint32_t patch;
    bool scatter;
    double culled_ms, setup_ms, vertices_per_triangle;
    std::vector<double> culled_runs, setup_runs;
  };
  std::vector<Arrangement> arrangements;
  for (uint32_t patch : {1u, 2u, 4u, 8u})
    for (bool scatter : {false, true}) {
      Arrangement a{patch, scatter, 0.0, 0.0, -1.0, {}, {}};
      if (!scatter)  // culled triangles sit at one point: no pixel to scatter over
        a.culled_ms = ms_per_triangle(ctx, measured_triangles, repeats, &a.culled_runs, patch);
      double invocations = -1.0;
      a.setup_ms = setup_ms_per_triangle(ctx, measured_triangles, repeats, &a.setup_runs, patch,
                                         scatter, &invocations);
      if (invocations >= 0.0) a.vertices_per_triangle = invocations / measured_triangles;
      std::printf(
          "  triangles in %u×%u patches%s: %s%.0f Mtriangles/s set up, %.2f vertices a triangle\n",
          patch, patch, scatter ? ", scattered" : "",
          scatter ? "" : fmt::format("{:.0f} Mtriangles/s culled, ", 1e-3 / a.culled_ms).c_str(),
          1e-3 / a.setup_ms, a.vertices_per_triangle);
      arrangements.push_back(std::move(a));
    }
  const Arrangement* culled = &arrangements[0];
  const Arrangement* fastest = &arrangements[0];
  for (const Arrangement& a : arrangements) {
    if (!a.scatter && a.culled_ms < culled->culled_ms) culled = &a;
    if (a.setup_ms < fastest->setup_ms) fastest = &a;
  }
  // The arrangement bounding a pass that ran `vertices` vertex shader invocations a triangle
  // (negative: not counted).
  auto arrangement_for = [&](double vertices) {
    const Arrangement* best = nullptr;
    if (vertices < 0.0) return fastest;
    for (const Arrangement& a : arrangements)
      if (a.vertices_per_triangle >= 0.0 && a.vertices_per_triangle <= vertices &&
          (!best || a.setup_ms < best->setup_ms))
        best = &a;
    return best ? best : fastest;
  };
  const double triangle_ms = culled->culled_ms, setup_ms = fastest->setup_ms;
  std::printf("  triangle rate %.0f Mtriangles/s (%u culled one-point triangles, %u×%u patches)\n",
              1e-3 / triangle_ms, measured_triangles, culled->patch, culled->patch);
  std::printf(
      "  setup rate %.0f Mtriangles/s (%u sub-pixel triangles covering no sample, %u×%u "
      "patches%s, %.2f vertices a triangle)\n",
      1e-3 / setup_ms, measured_triangles, fastest->patch, fastest->patch,
      fastest->scatter ? ", scattered" : "", fastest->vertices_per_triangle);
  // Triangles that each cover one sample (informational: what a triangle costs the chip
  // once it writes or tests a sample, beside the set-up triangles that cover none), into each
  // depth-only attachment set the frames use, in the patches the setup rate was fastest in.
  nlohmann::json covering = nlohmann::json::array();
  for (const auto& [key, fill] : fills) {
    if (!fill.colors.empty()) continue;
    std::vector<double> runs;
    const double ms =
        covering_ms_per_triangle(ctx, fill, measured_triangles, repeats, &runs, fastest->patch);
    std::printf(
        "  covering rate %.0f Mtriangles/s (%u triangles of one sample, %u×%u patches, %s)\n",
        1e-3 / ms, measured_triangles, fastest->patch, fastest->patch, key.c_str());
    covering.push_back(
        {{"key", key}, {"patch", fastest->patch}, {"ms_per_triangle", ms}, {"runs_ms", runs}});
  }
  std::map<std::string, double> bound_ms, fixed_ms;
  nlohmann::json bounds = nlohmann::json::array();
  std::printf("  %-44s %10s %12s\n", "raster bound (ms per full-screen layer)", "ms", "Gpixel/s");
  for (const auto& [key, fill] : fills) {
    // The per-layer cost: the slope between 1 and 8 stacked full-screen layers in one pass,
    // so a rendering's fixed cost (clears, setup) is not charged per fragment.
    const std::vector<double> one = time_fill(ctx, fill, repeats, {1});
    const std::vector<double> eight = time_fill(ctx, fill, repeats, {8});
    const double m = std::max(0.0, (median(eight) - median(one)) / 7.0);
    bound_ms[key] = m;
    // The rest of one layer's time is the rendering's fixed cost for this attachment set
    // (on the H200 far above clearing and storing its bytes: end-of-pass work).
    fixed_ms[key] = std::max(0.0, median(one) - m);
    const double gpix = m > 0.0 ? static_cast<double>(fill.width) * fill.height / m * 1e-6 : 0.0;
    std::printf("  %-44s %10.4f %12.2f\n", key.c_str(), m, gpix);
    bounds.push_back({{"key", key},
                      {"ms_per_layer", m},
                      {"fixed_ms", fixed_ms[key]},
                      {"one_layer_runs_ms", one},
                      {"eight_layer_runs_ms", eight},
                      {"gpixel_per_s", gpix}});
  }

  // The mixed bound of a pass: its rasterized triangles and its passing fragments drawn
  // together by a trivial pass (make_mixed) into each rendering's attachments, so the chip's
  // own overlap of setup and fill is measured instead of assumed (the larger of the two is
  // below what the chip can do when both are large; their sum above it). The triangles are
  // shared among the renderings in proportion to their passing layers; rejected fragments
  // are charged as in the raster bound.
  std::map<std::string, double> mixed_cache;
  nlohmann::json mixed_bounds = nlohmann::json::array();
  // `quad_scale` multiplies the passing layers: 4 × quads / passing samples for the bound at
  // quad granularity (a fragment shader runs in 2×2 quads: a quad with one passing sample
  // costs the chip the lanes of four).
  auto mixed_bound = [&](const nlohmann::json& fills_json, const std::string& file, double raster,
                         double quad_scale, const Arrangement& arrangement) {
    std::map<std::string, std::pair<int, double>> renderings;  // key: (renderings, layers)
    double passing = 0.0, rejected_ms = 0.0;
    for (const auto& f : fills_json) {
      const gpu::RasterFill fill = fill_from_json(f, file);
      const double count = f.at("count").get<double>();
      if (rejected(fill)) {
        rejected_ms += count * bound_ms.at(fill.key());
        continue;
      }
      auto& [n, layers] = renderings[fill.key()];
      ++n;
      layers += quad_scale * count;
      passing += quad_scale * count;
    }
    double total = rejected_ms;
    for (const auto& [key, rendering] : renderings) {
      const auto [n, layers] = rendering;
      if (passing <= 0.0 || layers <= 0.0) {
        total += n * fixed_ms.at(key);
        continue;
      }
      const double each_layers = layers / n;
      const uint32_t each_triangles = static_cast<uint32_t>(
          std::clamp(std::round(raster * layers / passing / n), 1.0, 16777216.0));
      const std::string id =
          fmt::format("{} {} triangles {:.4f} layers {}{}", key, each_triangles, each_layers,
                      arrangement.patch, arrangement.scatter ? "s" : "");
      auto it = mixed_cache.find(id);
      if (it == mixed_cache.end()) {
        const std::vector<double> runs =
            time_fill(ctx, fills.at(key), repeats,
                      {1, each_triangles, each_layers, arrangement.patch, arrangement.scatter});
        it = mixed_cache.emplace(id, median(runs)).first;
        mixed_bounds.push_back({{"key", key},
                                {"triangles", each_triangles},
                                {"layers", each_layers},
                                {"patch", arrangement.patch},
                                {"scattered", arrangement.scatter},
                                {"runs_ms", runs},
                                {"ms", it->second}});
      }
      total += n * it->second;
    }
    return total;
  };

  // The shading bound (realtime/measure/shading_bound.h): the full-screen lighting's median, its
  // per-pixel part scaled to the lanes the pass ran (4 × quads per covered pixel), its fixed
  // part — the attachment set's, which the pass pays once too — not.
  auto shading_bound = [&](const nlohmann::json& work, const std::string& file, Row* r) {
    const nlohmann::json& sh = work["shading"];
    const double full_screen = median(sh.at("runs_ms").get<std::vector<double>>());
    const double pixels = sh.at("pixels").get<double>();
    if (pixels <= 0.0 || full_screen <= 0.0) return;  // nothing on screen
    const double quads = work.value("quads", -1.0), samples = work.value("quad_samples", -1.0);
    // The pass (depth EQUAL after its pre-pass) passes at least one sample at each covered
    // pixel; fewer means the bound shaded pixels the pass did not.
    if (samples >= 0.0 && samples < pixels * (1.0 - 1e-3))
      throw Error(
          fmt::format("{}: pass {}: the shading bound shaded {} pixels, the pass passed "
                      "only {} samples",
                      file, r->name, pixels, samples));
    const double lanes = quads > 0.0 ? 4.0 * quads / pixels : 1.0;
    double fixed = 0.0;
    for (const auto& f : work.at("fills")) {
      const gpu::RasterFill fill = fill_from_json(f, file);
      if (!rejected(fill)) fixed = std::max(fixed, fixed_ms.at(fill.key()));
    }
    fixed = std::min(fixed, full_screen);
    r->shading_ms = fixed + (full_screen - fixed) * lanes;
    const double input_ms = sh.value("input_bytes", 0.0) / bytes_per_ms;
    r->shading = {{"full_screen_ms", full_screen},
                  {"runs_ms", sh.at("runs_ms")},
                  {"pixels", pixels},
                  {"lanes_per_pixel", lanes},
                  {"fixed_ms", fixed},
                  {"input_bytes", sh.value("input_bytes", 0.0)},
                  {"input_ms", input_ms}};
    r->details.push_back(fmt::format(
        "shading {:.4f} (full screen {:.4f} over {:.0f} pixels × {:.3f} lanes; its "
        "G-buffer reads {:.1f} MB, {:.4f} ms at copy bandwidth)",
        r->shading_ms, full_screen, pixels, lanes, sh.value("input_bytes", 0.0) * 1e-6, input_ms));
  };

  nlohmann::json out_frames = nlohmann::json::array();
  for (size_t i = 0; i < frames.size(); ++i) {
    const nlohmann::json& fr = frames[i];
    std::vector<Row> rows;
    for (const auto& p : fr["passes"]) {
      Row r;
      r.name = p.at("name").get<std::string>();
      r.depth = p.at("depth").get<int>();
      r.median_ms = p.at("median_ms").get<double>();
      if (p.contains("work")) {
        r.has_work = true;
        // Fills of one configuration (the views of a cube map) are listed once, summed.
        std::vector<std::pair<std::string, double>> counts;
        double passing_samples = 0.0;
        for (const auto& f : p["work"]["fills"]) {
          const gpu::RasterFill fill = fill_from_json(f, files[i]);
          const double count = f.at("count").get<double>();
          if (!rejected(fill)) passing_samples += count * fill.width * fill.height;
          // Each passing fill is one rendering: its fixed cost, then its passing layers.
          // Rejected fragments (behind what is drawn, or z-fail volume samples) belong to
          // the same rendering: only the per-layer slope of a full-screen rejected layer,
          // the cheapest rejection there is (hierarchical Z discards whole tiles of it),
          // is charged. (Charging a whole rejected layer's time, fixed cost included, gave
          // ratios below 1: docs/realtime.md.)
          r.raster_ms +=
              (rejected(fill) ? 0.0 : fixed_ms.at(fill.key())) + count * bound_ms.at(fill.key());
          auto it = std::find_if(counts.begin(), counts.end(),
                                 [&](const auto& c) { return c.first == fill.key(); });
          if (it == counts.end())
            counts.emplace_back(fill.key(), count);
          else
            it->second += count;
        }
        for (const auto& [key, count] : counts)
          r.details.push_back(fmt::format("{:.3g}× {}", count, key));
        const double triangles = p["work"].value("triangles", 0.0);
        if (triangles > 0.0) {
          // Counted ones (clip output) at the setup time, the rest at the culled time; clipping
          // may split a triangle, so at most the triangles submitted are charged as set up.
          const double raster = std::min(triangles, p["work"].value("rasterized_triangles", 0.0));
          const double vertices =
              p["work"].contains("vertex_invocations")
                  ? p["work"]["vertex_invocations"].get<double>() / std::max(triangles, 1.0)
                  : -1.0;
          const Arrangement& arrangement = *arrangement_for(vertices);
          // The triangles culled before rasterization; the rasterized ones are set up on the
          // pass's own targets by the mixed and quad bounds below, which add these.
          r.geometry_ms = (triangles - raster) * triangle_ms;
          if (raster >= 1.0) {
            r.mixed_ms =
                mixed_bound(p["work"]["fills"], files[i], raster, 1.0, arrangement) + r.geometry_ms;
            r.details.push_back(fmt::format("mixed {:.4f}", r.mixed_ms));
            const double quads = p["work"].value("quads", -1.0);
            const double counted = p["work"].value("quad_samples", -1.0);
            if (quads > 0.0 && counted > 0.0 && passing_samples > 0.0) {
              // The quad count replays the pass; it must have passed what the pass passed.
              if (std::abs(counted - passing_samples) > 1e-3 * passing_samples)
                throw Error(fmt::format(
                    "{}: pass {}: the quad count saw {} passing samples, the occlusion query {}",
                    files[i], r.name, counted, passing_samples));
              const double scale = 4.0 * quads / counted;
              r.quads_ms = mixed_bound(p["work"]["fills"], files[i], raster, scale, arrangement) +
                           r.geometry_ms;
              r.details.push_back(fmt::format("quads {:.4f} ({:.4g} quads, {:.3f}× the samples)",
                                              r.quads_ms, quads, scale));
            }
          }
          r.details.push_back(
              p["work"].contains("rasterized_triangles")
                  ? fmt::format("{:.4g} triangles ({:.4g} rasterized)", triangles, raster)
                  : fmt::format("{:.4g} triangles", triangles));
          // Vertex shader invocations a triangle submitted (3 without vertex reuse), and the
          // arrangement of the bound's triangles that runs no more.
          if (vertices >= 0.0)
            r.details.push_back(fmt::format(
                "{:.2f} vertices a triangle, bound on {}×{} patches{} "
                "({:.2f})",
                vertices, arrangement.patch, arrangement.patch,
                arrangement.scatter ? " scattered" : "", arrangement.vertices_per_triangle));
        }
        if (p["work"].contains("shading")) shading_bound(p["work"], files[i], &r);
        const double bytes = p["work"].at("bytes").get<double>();
        if (bytes > 0.0) {
          r.memory_ms = bytes / bytes_per_ms;
          r.details.push_back(fmt::format("{:.1f} MB", bytes * 1e-6));
        }
      }
      rows.push_back(std::move(r));
    }
    std::printf("\n%s: %s %dx%d, %s, shadows %s; frame %.4f ms (GPU, median of %d)\n",
                files[i].c_str(), fr.value("scene", "?").c_str(), fr.value("width", 0),
                fr.value("height", 0), fr.value("technique", "?").c_str(),
                fr.value("shadows", "?").c_str(), fr.value("frame_gpu_median_ms", 0.0),
                fr.value("frames", 0));
    std::printf("  %-22s %10s %10s %7s %16s  %-9s %s\n", "pass", "median ms", "bound ms", "ratio",
                "shading bound ms", "bound", "work");
    nlohmann::json passes = nlohmann::json::array();
    for (size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      std::string kind = "none";
      double bound = 0.0;
      std::vector<std::string> details = r.details;
      if (r.name.rfind("cpu:", 0) == 0) {
        kind = "cpu";
      } else if (r.median_ms < kDispatchBoundMs) {
        kind = "dispatch";
      } else if (r.has_work) {
        bound = r.largest();
        kind = bound == r.shading_ms    ? "shading"
               : bound == r.raster_ms   ? "raster"
               : bound == r.geometry_ms ? "geometry"
               : bound == r.mixed_ms    ? "mixed"
               : bound == r.quads_ms    ? "quads"
                                        : "memory";
        if (bound <= 0.0) kind = "none";  // rejected fragments only (listed, not bounded)
      } else {
        // A scope of nested steps only (per-light scopes): the sum of theirs.
        bool any = false;
        for (size_t c = k + 1; c < rows.size() && rows[c].depth > r.depth; ++c)
          if (rows[c].depth == r.depth + 1 && rows[c].has_work) {
            bound += rows[c].largest();
            any = true;
          }
        if (any) {
          kind = "nested";
          details = {"sum of its steps' bounds"};
        }
      }
      const double ratio = bound > 0.0 ? r.median_ms / bound : 0.0;
      const std::string label = std::string(2 * static_cast<size_t>(r.depth), ' ') + r.name;
      std::printf("  %-22s %10.4f %10s %7s %16s  %-9s %s\n", label.c_str(), r.median_ms,
                  bound > 0.0 ? fmt::format("{:.4f}", bound).c_str() : "-",
                  bound > 0.0 ? fmt::format("{:.2f}", ratio).c_str() : "-",
                  r.shading_ms > 0.0 ? fmt::format("{:.4f}", r.shading_ms).c_str() : "-",
                  kind.c_str(), fmt::format("{}", fmt::join(details, ", ")).c_str());
      nlohmann::json jp = {{"name", r.name},
                           {"depth", r.depth},
                           {"median_ms", r.median_ms},
                           {"bound", kind},
                           {"work", details}};
      if (bound > 0.0) {
        jp["bound_ms"] = bound;
        jp["ratio"] = ratio;
      }
      if (r.shading_ms > 0.0) {
        jp["shading_bound_ms"] = r.shading_ms;
        jp["shading"] = r.shading;
      }
      passes.push_back(jp);
    }
    out_frames.push_back({{"file", files[i]},
                          {"scene", fr.value("scene", "")},
                          {"technique", fr.value("technique", "")},
                          {"shadows", fr.value("shadows", "")},
                          {"techniques", fr.value("techniques", nlohmann::json::array())},
                          {"width", fr.value("width", 0)},
                          {"height", fr.value("height", 0)},
                          {"frames", fr.value("frames", 0)},
                          {"frame_gpu_median_ms", fr.value("frame_gpu_median_ms", 0.0)},
                          {"passes", passes}});
  }
  if (!json_path.empty()) {
    nlohmann::json j;
    j["suite"] = "raster";
    j["device"] = ctx.device_name();
    j["driver"] = ctx.driver();
    j["repeats"] = repeats;
    j["dispatch_bound_ms"] = kDispatchBoundMs;
    j["copy"] = {{"mib", bandwidth_mib}, {"gb_per_s", bytes_per_ms * 1e-6}, {"runs_ms", copy_runs}};
    j["raster_bounds"] = bounds;
    j["mixed_bounds"] = mixed_bounds;
    j["triangles"] = {{"count", measured_triangles},
                      {"ms_per_triangle", triangle_ms},
                      {"patch", culled->patch},
                      {"runs_ms", culled->culled_runs}};
    j["setup_triangles"] = {{"count", measured_triangles},
                            {"ms_per_triangle", setup_ms},
                            {"patch", fastest->patch},
                            {"scattered", fastest->scatter},
                            {"vertices_per_triangle", fastest->vertices_per_triangle},
                            {"runs_ms", fastest->setup_runs}};
    nlohmann::json tried = nlohmann::json::array();
    for (const Arrangement& a : arrangements)
      tried.push_back(
          {{"patch", a.patch},
           {"scattered", a.scatter},
           {"culled_ms_per_triangle", a.scatter ? nlohmann::json() : nlohmann::json(a.culled_ms)},
           {"setup_ms_per_triangle", a.setup_ms},
           {"vertices_per_triangle", a.vertices_per_triangle}});
    j["triangle_arrangements"] = tried;
    j["covering_triangles"] = covering;
    j["frames"] = out_frames;
    j["validation_messages"] = ctx.validation_message_count();
    j["machine"] = machine_info();
    write_json(json_path, j);
  }
  return 0;
}

}  // namespace illum::bench
