// The figures of `illum-bench gi-compare` (bench_gi_compare.cpp has the definitions and the
// reasons), apart from file input and drawing so tests/bench can check them on images with
// known answers.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "illum/core/image.h"

namespace illum::bench {

enum GiRegion { kGiFloor, kGiCeiling, kGiWalls, kGiCreases, kGiRegions };
inline constexpr const char* kGiRegionNames[kGiRegions] = {"floor", "ceiling", "walls", "creases"};

struct GiComparison {
  nlohmann::json figures;     // "image" and "regions"/NAME: scale, rel_l1, rel_rmse, noise, ...
  Image indirect, reference;  // the real-time term gi − no_gi; the runs' mean
  std::vector<double> L, P;   // per pixel luminance of the two
  std::vector<int> region;    // per pixel: kGiFloor … kGiWalls, −1 no surface
  double scale = 0.0, mean_p = 0.0;  // ΣL/ΣP; the reference's image mean
};

// All images of one size (the caller checks); `references` not empty. Throws Error when the
// reference has no light.
GiComparison compare_gi(const Image& no_gi, const Image& gi, const std::vector<Image>& references,
                        const Image& normals);

}  // namespace illum::bench
