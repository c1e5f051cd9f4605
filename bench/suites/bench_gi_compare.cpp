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

#include "gi_compare.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/core/tonemap.h"
#include "suites.h"

namespace illum::bench {

namespace {

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

  GiComparison cmp = compare_gi(no_gi, gi, refs, normals);
  nlohmann::json& result = cmp.figures;
  result["suite"] = "gi-compare";
  result["label"] = label;
  const size_t count = size_t(w) * size_t(h);
  const bool noise = refs.size() >= 2;
  const auto& L = cmp.L;
  const auto& P = cmp.P;
  const auto& region = cmp.region;
  const double safe_k = cmp.scale > 0.0 ? cmp.scale : 1.0, mean_p = cmp.mean_p;
  const Image &indirect = cmp.indirect, &reference = cmp.reference;
  const nlohmann::json& im = result["image"];
  fmt::print("{}: {}x{}, reference from {} run(s)\n", label, w, h, refs.size());
  fmt::print("  scale (mean real-time / mean path) {:.3f}  (R {:.3f} G {:.3f} B {:.3f})\n",
             im["scale"].get<double>(), im["scale_rgb"][0].get<double>(),
             im["scale_rgb"][1].get<double>(), im["scale_rgb"][2].get<double>());
  fmt::print("  at that scale: rel. L1 {:.3f}, rel. RMSE {:.3f}\n", im["rel_l1"].get<double>(),
             im["rel_rmse"].get<double>());
  if (noise)
    fmt::print(
        "  reference noise: rel. s.e. of the mean {:.4f}, rel. L1 {:.3f}, rel. RMSE {:.3f}\n",
        im["reference_rel_se_of_mean"].get<double>(), im["reference_rel_l1"].get<double>(),
        im["reference_rel_rmse"].get<double>());
  for (int r = 0; r < kGiRegions; ++r) {
    const nlohmann::json& g = result["regions"][kGiRegionNames[r]];
    fmt::print(
        "  {:8} {:5.1f} % of pixels, scale {:.3f}, rel. L1 {:.3f}{}\n", kGiRegionNames[r],
        100.0 * g["pixels"].get<double>() / double(count), g["scale"].get<double>(),
        g["rel_l1"].get<double>(),
        noise ? fmt::format(" (reference noise {:.3f})", g["reference_rel_l1"].get<double>()) : "");
  }
  // One markdown row: label | scale | L1 | RMSE | per region scale / L1.
  std::string row =
      fmt::format("| {} | {:.2f} | {:.2f} | {:.2f} |", label, im["scale"].get<double>(),
                  im["rel_l1"].get<double>(), im["rel_rmse"].get<double>());
  for (int r = 0; r < kGiRegions; ++r) {
    const nlohmann::json& g = result["regions"][kGiRegionNames[r]];
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
