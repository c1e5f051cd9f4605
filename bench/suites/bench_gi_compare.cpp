// `illum-bench gi-compare`: a real-time frame's indirect light against the path tracer's
// first indirect bounce (`illum render -i path --bounce-mode indirect1`), from EXR files
// that bench/scripts/gi_vs_path.sh writes with the `illum` program (docs/realtime-lpv.md,
// "Validation").
//
// The real-time indirect term is the difference of two frames, one with the technique and
// one without, both with the constant ambient off: shading adds the indirect term to the
// rest, so the difference is the indirect radiance (up to the EXRs' half-float rounding,
// 2⁻¹¹ of each pixel's whole value). The reference is the mean of the path tracer's runs
// (one per seed); two or more also give its noise: the spread of two runs estimates the
// standard error of their mean per pixel, hence the scale's standard error and the floor
// the reference's noise puts under L1 and RMSE.
//
// Figures, on luminance Y: the scale k = ΣL / ΣP (L the real-time term, P the reference);
// then, with k divided out, the relative L1 Σ|L/k − P| / ΣP and RMSE √mean((L/k − P)²) /
// mean P — the scale says whether there is light enough, L1 and RMSE where it goes. Per
// region from the path tracer's normals (`-i normals`): floor (n·y > 0.7), ceiling
// (n·y < −0.7), walls (the rest) and creases (pixels within 2 of a normal turning by
// more than 45°, where contact light gathers and a coarse grid blurs it away); each region's
// own scale and L1 (the global k divided out).
//
// --image: one strip of six panels — the frame without the technique, with it (ACES at the
// first's auto exposure), the real-time indirect term and the path tracer's (ACES at the
// latter's auto exposure), the signed error (L − P) / P̄ (P̄ the reference's image mean) and
// the same with k divided out, (L/k − P) / P̄, which shows where the light goes whatever its
// total: red → yellow where the frame has too much light, blue → cyan too little, black
// none, full colour at ±--heat-range; pixels no camera ray hits are grey.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "illum/core/auto_exposure.h"
#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/core/tonemap.h"
#include "suites.h"

namespace illum::bench {

namespace {

double luminance(const Color& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

enum Region { kFloor, kCeiling, kWalls, kCreases, kRegions };
const char* const kRegionNames[kRegions] = {"floor", "ceiling", "walls", "creases"};

struct Sums {
  double n = 0, l = 0, p = 0, abs_err = 0, sq_err = 0, noise_abs = 0, noise_sq = 0;
};

Image read_sized(const std::string& path, int width, int height) {
  Image image = read_image(path);
  if (width > 0 && (image.width() != width || image.height() != height))
    throw Error(fmt::format("{}: {}x{} pixels, the other images {}x{}", path, image.width(),
                            image.height(), width, height));
  return image;
}

// The signed error on a diverging ramp: positive red → yellow, negative blue → cyan.
Color signed_heat(double e, double full) {
  const float v = float(std::clamp(e / full, -1.0, 1.0));
  const float a = std::abs(v);
  const float main = std::min(1.0f, 2.0f * a), second = std::max(0.0f, 2.0f * a - 1.0f);
  return v >= 0 ? Color(main, second, 0.0f) : Color(0.0f, second, main);
}

}  // namespace

int run_gi_compare(SuiteArgs args) {
  std::string no_gi_path, gi_path, normals_path, image_path, json_path, label = "frame";
  std::vector<std::string> reference_paths;
  double heat_range = 1.0;
  CLI::App app("a real-time frame's indirect light vs the path tracer's first indirect bounce",
               "illum-bench gi-compare");
  app.add_option("--no-gi", no_gi_path, "EXR: the frame without the technique")->required();
  app.add_option("--gi", gi_path, "EXR: the same frame with it")->required();
  app.add_option("--reference", reference_paths,
                 "EXR: the path tracer's indirect1 image (repeatable: one per seed)")
      ->required();
  app.add_option("--normals", normals_path, "EXR: the path tracer's normals (-i normals)")
      ->required();
  app.add_option("--label", label, "the first column of the printed table rows")
      ->capture_default_str();
  app.add_option("--image", image_path, "PNG: the six panels side by side");
  app.add_option("--heat-range", heat_range, "the heat map's full colour, × the reference mean")
      ->check(CLI::Range(1e-3, 1e3))
      ->capture_default_str();
  app.add_option("--json", json_path, "write the figures to this JSON file");
  if (!parse_args(app, args)) return 0;
  check_output_folder(json_path);
  check_output_folder(image_path);

  const Image no_gi = read_image(no_gi_path);
  const int w = no_gi.width(), h = no_gi.height();
  const Image gi = read_sized(gi_path, w, h), normals = read_sized(normals_path, w, h);
  std::vector<Image> refs;
  for (const std::string& p : reference_paths) refs.push_back(read_sized(p, w, h));

  // Per pixel: L, P, the two-run spread, the region (−1: no surface).
  const size_t count = size_t(w) * size_t(h);
  std::vector<double> L(count), P(count), spread(count, 0.0);
  std::vector<vec3> n(count);
  std::vector<int> region(count, -1);
  std::vector<bool> crease(count, false);
  Image reference(w, h, 3), indirect(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const Color rt = gi.rgb(x, y) - no_gi.rgb(x, y);
      Color ref(0.0f);
      for (const Image& r : refs) ref += r.rgb(x, y) / float(refs.size());
      indirect.set_rgb(x, y, rt);
      reference.set_rgb(x, y, ref);
      L[i] = luminance(rt);
      P[i] = luminance(ref);
      if (refs.size() >= 2) spread[i] = luminance(refs[0].rgb(x, y)) - luminance(refs[1].rgb(x, y));
      const Color c = normals.rgb(x, y);
      const vec3 v(2.0f * c[0] - 1.0f, 2.0f * c[1] - 1.0f, 2.0f * c[2] - 1.0f);
      const float len = glm::length(v);
      if (len < 0.5f || len > 1.5f) continue;  // no hit: the view's black is (−1, −1, −1)
      n[i] = v / len;
      region[i] = n[i].y > 0.7f ? kFloor : n[i].y < -0.7f ? kCeiling : kWalls;
    }
  constexpr int kCreaseRadius = 2;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (region[i] < 0) continue;
      for (int dy = -kCreaseRadius; dy <= kCreaseRadius && !crease[i]; ++dy)
        for (int dx = -kCreaseRadius; dx <= kCreaseRadius; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const size_t j = size_t(yy) * w + xx;
          if (region[j] >= 0 && glm::dot(n[i], n[j]) < 0.7071f) {
            crease[i] = true;
            break;
          }
        }
    }

  double sum_l = 0, sum_p = 0;
  for (size_t i = 0; i < count; ++i) sum_l += L[i], sum_p += P[i];
  if (!(sum_p > 0.0))
    throw Error(fmt::format("{}: the reference has no indirect light", reference_paths[0]));
  const double k = sum_l / sum_p;
  const double safe_k = k > 0.0 ? k : 1.0;
  Sums all, per[kRegions];
  const auto add = [&](Sums& s, size_t i) {
    const double e = L[i] / safe_k - P[i];
    s.n += 1, s.l += L[i], s.p += P[i], s.abs_err += std::abs(e), s.sq_err += e * e;
    s.noise_abs += std::abs(spread[i]) / 2.0, s.noise_sq += spread[i] * spread[i] / 4.0;
  };
  for (size_t i = 0; i < count; ++i) {
    add(all, i);
    if (region[i] >= 0) add(per[region[i]], i);
    if (crease[i]) add(per[kCreases], i);
  }
  const bool noise = refs.size() >= 2;
  const auto figures = [&](const Sums& s) {
    const double mean_p = s.p / std::max(s.n, 1.0);
    nlohmann::json j = {{"pixels", s.n},
                        {"mean_realtime", s.l / std::max(s.n, 1.0)},
                        {"mean_reference", mean_p},
                        {"scale", s.p > 0 ? s.l / s.p : 0.0},
                        {"rel_l1", s.p > 0 ? s.abs_err / s.p : 0.0},
                        {"rel_rmse", mean_p > 0 ? std::sqrt(s.sq_err / s.n) / mean_p : 0.0}};
    if (noise) {
      // σ of the mean of two runs per pixel is |a − b|/2; E|mean − truth| of a normal
      // variable is that σ·√(2/π), as is E|a − b|/2, so the L1 floor is Σ|a − b|/2 / ΣP.
      j["reference_rel_se_of_mean"] = s.p > 0 ? std::sqrt(s.noise_sq) / s.p : 0.0;
      j["reference_rel_l1"] = s.p > 0 ? s.noise_abs / s.p : 0.0;
      j["reference_rel_rmse"] = mean_p > 0 ? std::sqrt(s.noise_sq / s.n) / mean_p : 0.0;
    }
    return j;
  };
  nlohmann::json result = {
      {"suite", "gi-compare"},         {"label", label},       {"width", w}, {"height", h},
      {"reference_runs", refs.size()}, {"image", figures(all)}};
  double channel_scale[3];
  for (int c = 0; c < 3; ++c) {
    double sl = 0, sp = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) sl += indirect.rgb(x, y)[c], sp += reference.rgb(x, y)[c];
    channel_scale[c] = sp > 0 ? sl / sp : 0.0;
  }
  result["image"]["scale_rgb"] = {channel_scale[0], channel_scale[1], channel_scale[2]};
  for (int r = 0; r < kRegions; ++r) result["regions"][kRegionNames[r]] = figures(per[r]);

  const nlohmann::json& im = result["image"];
  fmt::print("{}: {}x{}, reference from {} run(s)\n", label, w, h, refs.size());
  fmt::print("  scale (mean real-time / mean path) {:.3f}  (R {:.3f} G {:.3f} B {:.3f})\n",
             im["scale"].get<double>(), channel_scale[0], channel_scale[1], channel_scale[2]);
  fmt::print("  at that scale: rel. L1 {:.3f}, rel. RMSE {:.3f}\n", im["rel_l1"].get<double>(),
             im["rel_rmse"].get<double>());
  if (noise)
    fmt::print(
        "  reference noise: rel. s.e. of the mean {:.4f}, rel. L1 {:.3f}, rel. RMSE {:.3f}\n",
        im["reference_rel_se_of_mean"].get<double>(), im["reference_rel_l1"].get<double>(),
        im["reference_rel_rmse"].get<double>());
  for (int r = 0; r < kRegions; ++r) {
    const nlohmann::json& g = result["regions"][kRegionNames[r]];
    fmt::print(
        "  {:8} {:5.1f} % of pixels, scale {:.3f}, rel. L1 {:.3f}{}\n", kRegionNames[r],
        100.0 * g["pixels"].get<double>() / double(count), g["scale"].get<double>(),
        g["rel_l1"].get<double>(),
        noise ? fmt::format(" (reference noise {:.3f})", g["reference_rel_l1"].get<double>()) : "");
  }
  // One markdown row: label | scale | L1 | RMSE | per region scale / L1.
  std::string row =
      fmt::format("| {} | {:.2f} | {:.2f} | {:.2f} |", label, im["scale"].get<double>(),
                  im["rel_l1"].get<double>(), im["rel_rmse"].get<double>());
  for (int r = 0; r < kRegions; ++r) {
    const nlohmann::json& g = result["regions"][kRegionNames[r]];
    row +=
        g["pixels"].get<double>() > 0
            ? fmt::format(" {:.2f} / {:.2f} |", g["scale"].get<double>(), g["rel_l1"].get<double>())
            : " — |";
  }
  fmt::print("row {}\n", row);

  if (!image_path.empty()) {
    const float frame_exposure = auto_exposure(no_gi).exposure;
    const float indirect_exposure = auto_exposure(reference).exposure;
    const Image panels[4] = {tone_mapped(no_gi, ToneMapper::kAces, frame_exposure),
                             tone_mapped(gi, ToneMapper::kAces, frame_exposure),
                             tone_mapped(indirect, ToneMapper::kAces, indirect_exposure),
                             tone_mapped(reference, ToneMapper::kAces, indirect_exposure)};
    constexpr int kGap = 4;
    Image strip(6 * w + 5 * kGap, h, 3, 1.0f);
    const double mean_p = sum_p / double(count);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int p = 0; p < 4; ++p) strip.set_rgb(p * (w + kGap) + x, y, panels[p].rgb(x, y));
        const size_t i = size_t(y) * w + x;
        const bool none = region[i] < 0;
        strip.set_rgb(4 * (w + kGap) + x, y,
                      none ? Color(0.15f) : signed_heat((L[i] - P[i]) / mean_p, heat_range));
        strip.set_rgb(
            5 * (w + kGap) + x, y,
            none ? Color(0.15f) : signed_heat((L[i] / safe_k - P[i]) / mean_p, heat_range));
      }
    write_image(image_path, strip);
    fmt::print("wrote {}\n", image_path);
  }
  if (!json_path.empty()) {
    result["machine"] = machine_info();
    write_json(json_path, result);
  }
  return 0;
}

}  // namespace illum::bench
