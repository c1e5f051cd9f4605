// The trivial passes `illum-bench raster` measures a GPU with (bench_raster.cpp says what
// each bound is): full-screen fills of an attachment set as 1 and 8 layers, triangles culled
// or set up without covering a sample, the mixed pass of both, and a buffer copy.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/gpu/context.h"
#include "illum/gpu/gpu_timer.h"

namespace illum::bench {

bool is_uint(VkFormat f);

// What a bound pass draws: `layers` full-screen triangles, or, with `setup_triangles` > 0, that
// many triangles covering no sample interleaved with rectangles covering `mixed_layers`
// full-target layers (shaders/bound_mixed.vert).
struct BoundGeometry {
  int layers = 1;
  uint32_t setup_triangles = 0;
  double mixed_layers = 0.0;
};

// The trivial pass into `f`'s attachments, `repeats` times (after 2 untimed), each its own
// rendering scope after a barrier as a frame's passes are; returns the times.
std::vector<double> time_fill(gpu::Context& ctx, const gpu::RasterFill& f, int repeats,
                              const BoundGeometry& geometry);

// The time of one triangle (see raster_passes.cpp): culled one-point triangles, or with
// `rasterized` set-up triangles covering no sample; `runs` receives each run's time.
double ms_per_triangle(gpu::Context& ctx, uint32_t triangles, int repeats,
                       std::vector<double>* runs, bool rasterized = false);

// Copy bandwidth (bytes read + written per ms) of two device-local buffers of `bytes`.
double copy_bytes_per_ms(gpu::Context& ctx, VkDeviceSize bytes, int repeats,
                         std::vector<double>* runs);

}  // namespace illum::bench
