#include "illum/bake/bake_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "illum/core/error.h"
#include "illum/core/log.h"

namespace illum::bake {

namespace {

// Calibration (docs/lightmaps.md, "Memory"): `illum bake cornell --spp 1` at --resolution
// 256, 512, 1024 and 2048 (plain, denoised; 43.7k to 2.96M covered texels), the 1024 bake
// again with --basis sh, with -p denoise=false and with four extra maps, and radiosity at
// 128 and 256, each under /usr/bin/time -f %M. The per-atlas-texel terms are the images the
// bake holds (sample_of 4 B, variance 4 B, 12 B per RGB float layer); the per-covered terms
// are the slope of the maximum RSS after them: 116 B (the TexelSample, 80 B, and the raster's
// and baker's transient state), +8 B and +24 B per layer for the denoiser, 148 B in all for
// a plain denoised bake (the fit is within 3% of the four measured sizes). The base is the
// intercept with Cornell's 32 triangles (16 MB; the two radiosity sizes give the same).
constexpr double kBaseBytes = 16.0e6;
constexpr double kAtlasBytes = 8.0;           // sample_of + variance
constexpr double kAtlasBytesPerLayer = 12.0;  // one RGB float image
constexpr double kCoveredBytes = 116.0;
constexpr double kDenoiseBytes = 8.0;
constexpr double kDenoiseBytesPerLayer = 24.0;  // value and next_value, RGB float
// Raster-sized RGB float images, written out; the pages of uncovered texels are touched by
// dilation, so the full image counts (measured: 5.5 B per atlas texel each at 1024²,
// occupancy 70%: the analytic 12 B bounds it).
constexpr double kExtraMapBytes = 12.0;
// The timed path bake's TexelSums (4 dvec3 + 4 doubles) kept for every texel between passes.
constexpr double kTimedBytes = 128.0;
// Radiosity: the patch (36 B), albedo, unshot and total power (36 B), labels and factors, the
// atlas-sized area image and patch grid: the slope of the two radiosity sizes.
constexpr double kRadiosityBytes = 160.0;
constexpr double kRadiosityBytesPerLayer = 12.0;  // accumulated, per layer
constexpr double kRadiosityAtlasBytes = 8.0;
// Scene, BVH and the atlas's per-mesh layouts per triangle: Sibenik (74,928 triangles) at
// --resolution 600 and 1200 (-p denoise=false) left 522 and 450 B per triangle after the
// texel terms, and a load that stopped at the atlas (too small) 558 B.
constexpr double kTriangleBytes = 500.0;

uint64_t read_cgroup_limit() {
  std::ifstream in("/sys/fs/cgroup/memory.max");
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  return errno == 0 && end && *end == '\0' ? uint64_t(v) : 0;
}

uint64_t parse_limit(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  double scale = 1.0;
  const std::string suffix = end ? std::string(end) : std::string();
  if (suffix == "K" || suffix == "k")
    scale = 1024.0;
  else if (suffix == "M" || suffix == "m")
    scale = 1024.0 * 1024.0;
  else if (suffix == "G" || suffix == "g")
    scale = 1024.0 * 1024.0 * 1024.0;
  else if (!suffix.empty())
    scale = 0.0;
  if (errno != 0 || end == text.c_str() || scale == 0.0 || !(v > 0.0) || !std::isfinite(v) ||
      v * scale > 1.8e19)
    throw Error(fmt::format(
        "ILLUM_MEMORY_LIMIT '{}': must be a positive number of bytes, optionally with a K, M or "
        "G suffix",
        text));
  return static_cast<uint64_t>(v * scale);
}

}  // namespace

std::string format_bytes(uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024.0 * 1024.0) return fmt::format("{:.3g} GiB", b / (1024.0 * 1024 * 1024));
  if (b >= 1024.0 * 1024.0) return fmt::format("{:.3g} MiB", b / (1024.0 * 1024));
  return fmt::format("{:.3g} KiB", b / 1024.0);
}

int64_t chart_texel_bound(const atlas::Atlas& atlas) {
  const int64_t atlas_texels = int64_t(atlas.width) * atlas.height;
  if (atlas.charts.empty()) return atlas_texels;  // an atlas made by hand: no better bound
  int64_t sum = 0;
  for (const atlas::AtlasChart& c : atlas.charts) sum += int64_t(c.width) * c.height;
  return std::min(sum, atlas_texels);
}

BakeMemoryEstimate estimate_bake_memory(const BakeMemoryInput& in) {
  if (in.atlas_texels < 0 || in.chart_texels < 0 || in.layers < 0 || in.extra_maps < 0 ||
      in.scene_triangles < 0)
    throw Error(fmt::format(
        "bake memory estimate: bad input ({} atlas texels, {} chart texels, "
        "{} layers, {} extra maps, {} triangles)",
        in.atlas_texels, in.chart_texels, in.layers, in.extra_maps, in.scene_triangles));
  const double atlas = double(in.atlas_texels), covered = double(in.chart_texels);
  const double layers = in.layers;
  double bytes = kBaseBytes + kTriangleBytes * double(in.scene_triangles);
  bytes += atlas * (kAtlasBytes + kAtlasBytesPerLayer * layers + kExtraMapBytes * in.extra_maps);
  if (in.radiosity) {
    bytes += atlas * kRadiosityAtlasBytes;
    bytes += covered * (kRadiosityBytes + kRadiosityBytesPerLayer * layers);
  } else {
    bytes += covered * kCoveredBytes;
    if (in.denoise) bytes += covered * (kDenoiseBytes + kDenoiseBytesPerLayer * layers);
    if (in.timed) bytes += covered * kTimedBytes;
  }
  BakeMemoryEstimate e;
  e.bytes = static_cast<uint64_t>(bytes);
  e.atlas_texels = in.atlas_texels;
  e.chart_texels = in.chart_texels;
  return e;
}

uint64_t MachineMemory::limit() const {
  uint64_t l = physical;
  for (const uint64_t v : {cgroup, override})
    if (v > 0 && (l == 0 || v < l)) l = v;
  return l;
}

std::string MachineMemory::describe() const {
  std::string s = fmt::format("{} physical", format_bytes(physical));
  if (cgroup > 0) s += fmt::format(", cgroup limit {}", format_bytes(cgroup));
  if (override > 0) s += fmt::format(", ILLUM_MEMORY_LIMIT {}", format_bytes(override));
  return s;
}

MachineMemory machine_memory() {
  MachineMemory m;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) m.physical = uint64_t(pages) * uint64_t(page);
  m.cgroup = read_cgroup_limit();
  if (const char* env = std::getenv("ILLUM_MEMORY_LIMIT"); env && *env)
    m.override = parse_limit(env);
  return m;
}

void check_bake_memory(const BakeMemoryEstimate& estimate, const MachineMemory& machine) {
  const uint64_t limit = machine.limit();
  log::debug("bake: estimated peak memory {} ({} atlas texels, at most {} covered); machine: {}",
             format_bytes(estimate.bytes), estimate.atlas_texels, estimate.chart_texels,
             machine.describe());
  if (limit > 0 && estimate.bytes > limit)
    throw Error(fmt::format(
        "bake needs about {} ({} atlas texels, up to {} covered) but this machine has {} ({}): "
        "lower --resolution or raise --texel-size",
        format_bytes(estimate.bytes), estimate.atlas_texels, estimate.chart_texels,
        format_bytes(limit), machine.describe()));
}

}  // namespace illum::bake
