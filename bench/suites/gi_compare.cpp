#include "gi_compare.h"

#include <algorithm>
#include <cmath>

#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/core/math.h"

namespace illum::bench {

namespace {

double luminance(const Color& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

struct Sums {
  double n = 0, l = 0, p = 0, abs_err = 0, sq_err = 0, noise_abs = 0, noise_sq = 0;
};

}  // namespace

GiComparison compare_gi(const Image& no_gi, const Image& gi, const std::vector<Image>& references,
                        const Image& normals) {
  const int w = no_gi.width(), h = no_gi.height();
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
      for (const Image& r : references) ref += r.rgb(x, y) / float(references.size());
      indirect.set_rgb(x, y, rt);
      reference.set_rgb(x, y, ref);
      L[i] = luminance(rt);
      P[i] = luminance(ref);
      if (references.size() >= 2)
        spread[i] = luminance(references[0].rgb(x, y)) - luminance(references[1].rgb(x, y));
      const Color c = normals.rgb(x, y);
      const vec3 v(2.0f * c[0] - 1.0f, 2.0f * c[1] - 1.0f, 2.0f * c[2] - 1.0f);
      const float len = glm::length(v);
      if (len < 0.5f || len > 1.5f) continue;  // no hit: the view's black is (−1, −1, −1)
      n[i] = v / len;
      region[i] = n[i].y > 0.7f ? kGiFloor : n[i].y < -0.7f ? kGiCeiling : kGiWalls;
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
  if (!(sum_p > 0.0)) throw Error("the reference has no indirect light");
  const double k = sum_l / sum_p;
  const double safe_k = k > 0.0 ? k : 1.0;
  Sums all, per[kGiRegions];
  const auto add = [&](Sums& s, size_t i) {
    const double e = L[i] / safe_k - P[i];
    s.n += 1, s.l += L[i], s.p += P[i], s.abs_err += std::abs(e), s.sq_err += e * e;
    s.noise_abs += std::abs(spread[i]) / 2.0, s.noise_sq += spread[i] * spread[i] / 4.0;
  };
  for (size_t i = 0; i < count; ++i) {
    add(all, i);
    if (region[i] >= 0) add(per[region[i]], i);
    if (crease[i]) add(per[kGiCreases], i);
  }
  const bool noise = references.size() >= 2;
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
      {"width", w}, {"height", h}, {"reference_runs", references.size()}, {"image", figures(all)}};
  double channel_scale[3];
  for (int c = 0; c < 3; ++c) {
    double sl = 0, sp = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) sl += indirect.rgb(x, y)[c], sp += reference.rgb(x, y)[c];
    channel_scale[c] = sp > 0 ? sl / sp : 0.0;
  }
  result["image"]["scale_rgb"] = {channel_scale[0], channel_scale[1], channel_scale[2]};
  for (int r = 0; r < kGiRegions; ++r) result["regions"][kGiRegionNames[r]] = figures(per[r]);

  GiComparison out;
  out.figures = std::move(result);
  out.indirect = std::move(indirect);
  out.reference = std::move(reference);
  out.L = std::move(L);
  out.P = std::move(P);
  out.region = std::move(region);
  out.scale = k;
  out.mean_p = sum_p / double(count);
  return out;
}

}  // namespace illum::bench
