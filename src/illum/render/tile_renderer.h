// The pixel loop every offline integrator shares: tiles rendered in parallel, one scrambled
// Sobol' sequence per pixel seeded from hash(seed, x, y), samples added in passes so a time
// budget can stop the render between passes.
//
// Determinism: a pixel's estimate depends only on (seed, x, y, sample count) — never on
// which thread ran it — so the same seed and thread count (indeed any thread count) give a
// bit-identical image when the render stops on `spp`. With a time budget the number of
// passes depends on the machine's speed; the image is then only as deterministic as that.
//
// Budget: passes of 1, 1, 2, 4, 8, 16, 16, ... samples per pixel run until `options.spp`
// samples are done or, when `options.time_budget_s` > 0, until that much time has passed
// at the end of a pass — whichever comes first (pass a large spp for a time-only budget).
// Ctrl-C (core/interrupt.h) stops the render within a tile and throws Interrupted.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/work_split.h"
#include "illum/render/integrator.h"
#include "illum/render/render_setup.h"
#include "illum/scene/camera.h"

namespace illum {

struct RenderStats {
  int spp = 0;  // samples per pixel actually taken
  int passes = 0;
  int64_t samples = 0;   // camera samples (pixels × spp)
  int64_t dropped = 0;   // non-finite samples replaced by black
  double seconds = 0.0;  // wall time of the pixel loop
  // When the last pass began. With a time budget the loop stops after the first pass that
  // ends past it, so this lies before the budget and the overrun is at most that one pass.
  double last_pass_start_s = 0.0;
};

inline constexpr int kRenderTileSize = 16;
inline constexpr int kMaxPassSpp = 16;

// The samples per pixel of the pass after one of `pass_spp`, when `passes_done` passes are
// done: 1, 1, 2, 4, 8, 16, 16, ... (the second pass also 1 spp: a quick early estimate).
inline int next_pass_spp(int pass_spp, int passes_done) {
  return passes_done == 1 ? 1 : std::min(2 * pass_spp, kMaxPassSpp);
}

// `shade(const Ray& camera_ray, SobolSampler& sampler) -> Color` estimates the radiance of
// one camera sample; it receives the sampler after the two film dimensions were taken.
// Returns the linear RGB mean over each pixel's samples (box filter).
template <typename Shade>
Image render_tiles(const Camera& camera, const RenderOptions& options, const std::string& label,
                   Shade&& shade, RenderStats* stats_out = nullptr) {
  validate_render_options(options);
  ThreadLimit thread_limit(options.threads);
  const int width = options.width, height = options.height;
  std::vector<Color> sum(static_cast<size_t>(width) * height, Color(0.0f));
  const int tiles = ((width + kRenderTileSize - 1) / kRenderTileSize) *
                    ((height + kRenderTileSize - 1) / kRenderTileSize);
  Progress progress(label, static_cast<int64_t>(tiles) * options.spp, options.progress);
  std::atomic<int64_t> dropped{0};
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  // Adds samples [first, first + count) of every pixel of `tile` to `sums` (row-major,
  // `stride` pixels a row, starting at the tile's corner); returns the non-finite samples.
  auto render_pass = [&](const Tile& tile, int first, int count, Color* sums, int stride) {
    int64_t bad = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        SobolSampler sampler(
            hash_mix(options.seed, static_cast<uint64_t>(x), static_cast<uint64_t>(y)));
        Color acc(0.0f);
        for (int s = first; s < first + count; ++s) {
          sampler.start_sample(static_cast<uint32_t>(s));
          const vec2 jitter = sampler.next_2d();
          const Ray ray = camera.generate_ray(static_cast<float>(x) + jitter.x,
                                              static_cast<float>(y) + jitter.y, width, height);
          const Color c = shade(ray, sampler);
          if (is_finite(c)) {
            acc += c;
          } else {
            ++bad;
          }
        }
        sums[static_cast<size_t>(y - tile.y0) * stride + (x - tile.x0)] += acc;
      }
    }
    return bad;
  };

  RenderStats stats;
  if (work_split_ranks() > 1) {
    // Across ranks (core/work_split.h): a work item is one tile with all its passes, in the
    // same pass sizes as below, so every pixel sums the same values in the same order and
    // the image is bit-identical to a one-process render. A time budget would make the
    // passes, and so the image, depend on each rank's speed: refused.
    if (options.time_budget_s > 0.0)
      throw Error(
          fmt::format("--time {} cannot be used with {} MPI ranks (the image would "
                      "depend on the rank count); give --spp instead",
                      options.time_budget_s, work_split_ranks()));
    const int tiles_x = (width + kRenderTileSize - 1) / kRenderTileSize;
    struct TileRecord {
      Color sum[kRenderTileSize * kRenderTileSize];
      int64_t dropped;
    };
    auto tile_of = [&](int64_t i) {
      const int tx = static_cast<int>(i % tiles_x), ty = static_cast<int>(i / tiles_x);
      return Tile{tx * kRenderTileSize, ty * kRenderTileSize,
                  std::min(width, (tx + 1) * kRenderTileSize),
                  std::min(height, (ty + 1) * kRenderTileSize), static_cast<int>(i)};
    };
    split_items<TileRecord>(
        tiles, 1,
        [&](int64_t i) {
          TileRecord record{};
          const Tile tile = tile_of(i);
          int passes = 0;
          for (int first = 0, pass_spp = 1; first < options.spp;) {
            // Ctrl-C (or mpirun's SIGTERM): a tile holds all its passes, so poll between
            // them as the one-process loop does; the split throws after the unit.
            if (interrupt_requested()) return record;
            const int count = std::min(pass_spp, options.spp - first);
            record.dropped += render_pass(tile, first, count, record.sum, kRenderTileSize);
            first += count;
            pass_spp = next_pass_spp(pass_spp, ++passes);
          }
          return record;
        },
        [&](int64_t i, const TileRecord& record) {
          const Tile tile = tile_of(i);
          for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
              sum[static_cast<size_t>(y) * width + x] =
                  record.sum[(y - tile.y0) * kRenderTileSize + (x - tile.x0)];
          dropped += record.dropped;
          progress.advance(options.spp);
        });
    if (interrupt_requested()) {
      progress.finish();
      throw Interrupted{};
    }
    stats.spp = options.spp;
    for (int first = 0, pass_spp = 1; first < options.spp; ++stats.passes) {
      first += std::min(pass_spp, options.spp - first);
      pass_spp = next_pass_spp(pass_spp, stats.passes + 1);
    }
  }
  int pass_spp = 1;
  double pass_end_s = 0.0;  // the budget check's clock reading, also the next pass's start
  while (stats.spp < options.spp) {
    const int first = stats.spp;
    const int count = std::min(pass_spp, options.spp - first);
    stats.last_pass_start_s = pass_end_s;
    parallel_for_tiles(width, height, kRenderTileSize, [&](const Tile& tile) {
      if (interrupt_requested()) return;  // Ctrl-C: finish quickly, throw below
      const int64_t bad = render_pass(tile, first, count,
                                      &sum[static_cast<size_t>(tile.y0) * width + tile.x0], width);
      if (bad) dropped += bad;
      progress.advance(count);
    });
    if (interrupt_requested()) {
      progress.finish();
      throw Interrupted{};
    }
    stats.spp += count;
    ++stats.passes;
    pass_spp = next_pass_spp(pass_spp, stats.passes);
    pass_end_s = elapsed();
    if (options.time_budget_s > 0.0 && pass_end_s >= options.time_budget_s) break;
  }
  progress.finish();
  stats.seconds = elapsed();
  stats.samples = static_cast<int64_t>(stats.spp) * width * height;
  stats.dropped = dropped.load();
  if (stats.dropped > 0)
    log::warn("{}: {} non-finite samples were replaced by black", label, stats.dropped);

  Image image(width, height, 3);
  const float inv = 1.0f / static_cast<float>(stats.spp);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.set_rgb(x, y, sum[static_cast<size_t>(y) * width + x] * inv);
  if (stats_out) *stats_out = stats;
  return image;
}

}  // namespace illum
