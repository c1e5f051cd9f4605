// A light-map bake's peak memory, estimated from the atlas before the texels are rasterized,
// and the check that refuses a bake the machine cannot hold: a 16384²
// atlas of a large scene needs tens of GB, and a bake killed by the kernel after an hour of
// rasterizing says nothing. The estimate is a sum of the arrays the bake holds at its peak,
// per atlas texel (images) and per covered texel (samples, baker and denoiser state), with
// per-texel constants calibrated against /usr/bin/time's maximum RSS (docs/lightmaps.md,
// "Memory"); covered texels are bounded from above by the charts' rectangles.
#pragma once

#include <cstdint>
#include <string>

#include "illum/atlas/atlas.h"

namespace illum::bake {

struct BakeMemoryInput {
  int64_t atlas_texels = 0;  // width · height
  int64_t chart_texels = 0;  // covered texels, or an upper bound (chart_texel_bound)
  int layers = 1;            // basis layers (1 plain, 3 rnm, 4 sh; 0: only extra maps)
  int extra_maps = 0;        // raster-sized RGB extra images (ao, obscurance, ...)
  bool radiosity = false;    // the radiosity baker's per-patch state instead of the path's
  bool denoise = true;       // the path baker's denoiser buffers
  bool timed = false;        // the path baker's per-texel sums kept between --time passes
  int64_t scene_triangles = 0;
};

struct BakeMemoryEstimate {
  uint64_t bytes = 0;
  int64_t atlas_texels = 0, chart_texels = 0;
};

// Σ over the atlas's charts of their rectangles' texels, capped at width · height: at least
// the texels the raster will cover (every chart's texels lie in its rectangle).
int64_t chart_texel_bound(const atlas::Atlas& atlas);

BakeMemoryEstimate estimate_bake_memory(const BakeMemoryInput& input);

// What this process may use: physical memory, the cgroup v2 limit (/sys/fs/cgroup/memory.max
// when it holds a number), and ILLUM_MEMORY_LIMIT when set (bytes, or a number with a K, M
// or G suffix, powers of 1024): the smallest of them. ILLUM_MEMORY_LIMIT lets tests and
// users see the refusal without a machine too small for the bake.
struct MachineMemory {
  uint64_t physical = 0;
  uint64_t cgroup = 0;    // 0: no limit set
  uint64_t override = 0;  // 0: ILLUM_MEMORY_LIMIT not set
  uint64_t limit() const;
  std::string describe() const;  // "23.5 GiB physical, cgroup limit 8 GiB"
};
// Throws Error on a malformed ILLUM_MEMORY_LIMIT.
MachineMemory machine_memory();

// Throws Error, naming the estimate and the machine's memory, when the estimate exceeds it.
void check_bake_memory(const BakeMemoryEstimate& estimate, const MachineMemory& machine);

std::string format_bytes(uint64_t bytes);  // "1.23 GiB", "512 MiB"

}  // namespace illum::bake
