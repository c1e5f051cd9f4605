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
// full-target layers (shaders/bound_mixed.vert). The triangles share vertices in `patch` ×
// `patch` grids of cells (2·patch² triangles on (patch + 1)² vertices), each grid inside the
// corner of one pixel: as a mesh's triangles share their vertices, so a triangle costs the
// chip less than three vertices' work (patch 1: two triangles on four vertices).
struct BoundGeometry {
  int layers = 1;
  uint32_t setup_triangles = 0;
  double mixed_layers = 0.0;
  uint32_t patch = 1;
  bool scatter = false;  // patch k in pixel k (row by row), or in a pixel scattered by k
  // Instead, each triangle covers one sample: cells of 2 × 1 pixels, patches tiling the target.
  bool cover = false;
};

// Vertices of `triangles` triangles in patches of `patch` (the last one may be partial), and
// triangle t's indices appended to `indices`, counting from vertex 0.
uint32_t patch_vertices(uint32_t triangles, uint32_t patch);
void append_patch_triangle(std::vector<uint32_t>& indices, uint32_t t, uint32_t patch);

// The trivial pass into `f`'s attachments, `repeats` times (after 2 untimed), each its own
// rendering scope after a barrier as a frame's passes are; returns the times.
// With setup triangles and `vertex_invocations`, that receives the vertex shader invocations of
// one repetition (−1 where the device does not count them).
std::vector<double> time_fill(gpu::Context& ctx, const gpu::RasterFill& f, int repeats,
                              const BoundGeometry& geometry, double* vertex_invocations = nullptr);

// The time of one triangle (see raster_passes.cpp): culled one-point triangles, or set-up
// triangles covering no sample; both in `patch` grids of shared vertices. `runs` receives each
// run's time.
double ms_per_triangle(gpu::Context& ctx, uint32_t triangles, int repeats,
                       std::vector<double>* runs, uint32_t patch);
double setup_ms_per_triangle(gpu::Context& ctx, uint32_t triangles, int repeats,
                             std::vector<double>* runs, uint32_t patch, bool scatter,
                             double* vertex_invocations);
// Triangles covering one sample each (BoundGeometry::cover) into the attachments of `f`, in
// `patch` grids; ms per triangle.
double covering_ms_per_triangle(gpu::Context& ctx, const gpu::RasterFill& f, uint32_t triangles,
                                int repeats, std::vector<double>* runs, uint32_t patch);

// Copy bandwidth (bytes read + written per ms) of two device-local buffers of `bytes`.
double copy_bytes_per_ms(gpu::Context& ctx, VkDeviceSize bytes, int repeats,
                         std::vector<double>* runs);

}  // namespace illum::bench
