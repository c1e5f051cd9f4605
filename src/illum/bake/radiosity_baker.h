// Radiosity light-maps (CaLight, S002 §3.3; ALGORITHMS.md item 6): one patch per covered
// texel of the atlas's texel raster, progressive-refinement shooting
// (progressive_shooting.h) with ray-tested visibility. The maps hold what the path-traced
// baker's do (lightmap_baker.h: plain E/π, Source RNM, radiance SH-L1 in the texel's tangent
// frame), so the real-time renderer shows either; diffuse interreflection only (every
// surface reflects its diffuse albedo, at the texel's uv0).
//
// Initial unshot energy (the seed's direct-lighting phase, §3.3.2–3.3.3):
//   point, spot, sun  irradiance at the texel's point from one shadow ray (exact, no noise);
//                     spots with the hard cone edge and Φ/Ω intensity of the path tracer
//   sky (environment) `sky_rays` scrambled-Sobol' directions per texel (the seed's
//                     "multisampled" sun rays, for a sky of any shape)
//   area, emissive    the emitting texels' exitance πL_e, shot like any other patch
// Each texel re-emits its albedo × what arrives; the light-map records what arrives, by
// direction for the directional bases (a shot arrives from the source's centre, a point or
// sun light from its direction).
#pragma once

#include <cstdint>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

inline constexpr double kDefaultRadiosityThreshold = 1e-3;
inline constexpr double kDefaultRadiosityRelativeThreshold = 0.05;  // as PRT's
// Measured (bench/results/lightmaps.md#radiosity): at 0.1 the relative RMSE
// against the path-traced reference rises 10.80% → 10.87% on Sibenik 384² and 2.98% → 3.34%
// on Cornell 128², for 1.5× and 1.75× less time; 0.2 saves little more (Sibenik: 1.6×).
inline constexpr float kDefaultClusterRatio = 0.1f;

struct RadiosityBakeOptions {
  LightmapBasis basis = LightmapBasis::kPlain;
  LightmapContent content = LightmapContent::kAll;
  // Shooting stops when the unshot power is at most threshold × the initial unshot power
  // (direct light and emission): the map's area-weighted mean then lacks at most that
  // share of the converged solution's indirect part (0 < threshold < 1).
  double threshold = kDefaultRadiosityThreshold;
  // ... and when the texels' area-weighted mean relative unshot (each texel's unshot against
  // all it has re-emitted, progressive_shooting.h) is at most relative_threshold: a dim
  // region beside a bright one (a nave beside a sunlit town) is converged too. (0, 1]; 1: off.
  double relative_threshold = kDefaultRadiosityRelativeThreshold;
  int samples_per_surface = 10;  // the seed's random shooter samples per surface
  int group_size = 3;            // the seed's n: n×n texels shoot as one (1..15)
  int sky_rays = 64;             // environment directions per texel (1..65536)
  // Rays per shot estimating the share of the shooter's hemisphere that lands on surfaces;
  // the shot's form factors are scaled to it (power conservation, progressive_shooting.h).
  // 0 turns the scaling off.
  int reach_rays = 256;
  // Receiver clusters (shooting_clusters.h): a far cluster of receiver texels whose size is
  // at most cluster_ratio × its distance from the shooter shares the visibility of its four
  // probe rays when they agree; 0: one visibility ray per receiver texel (the O(N²) bake).
  float cluster_ratio = kDefaultClusterRatio;
  int dilate = 4;
  // Seam stitching after dilation (lightmap_seams.h: stitch_seams), every layer (for
  // dominant: the SH-L1 sums it is made from). Off here, so a caller that fills this struct
  // gets the shot values as they are; from_params turns it on (key stitch).
  bool stitch = false;
  // With stitch: also join coplanar neighbours meeting in part (lightmap_coplanar.h).
  bool stitch_coplanar = true;
  uint64_t seed = 0;
  double time_budget_s = 0.0;  // 0: none; else stop shooting after it (the map is kept)
  int threads = 0;             // 0 = all cores
  bool progress = true;

  // Keys: basis, content, threshold, relative_threshold (0..1], samples_per_surface (1..1000),
  // group_size (1..15), sky_rays, reach_rays (0..65536), cluster_ratio (0..0.5), dilate (0..64),
  // stitch (bool, default true), stitch_coplanar (bool, default true), seed. Throws Error on values
  // out of range (NaN included) or unknown names.
  static RadiosityBakeOptions from_params(const Params& params);
};

struct RadiosityBake {
  LightmapBasis basis = LightmapBasis::kPlain;
  LightmapContent content = LightmapContent::kAll;
  std::vector<Image> layers;  // as LightmapBake::layers
  Image area;                 // one channel: each covered texel's world area (m²), 0 elsewhere
  double seconds = 0.0;
  double stitch_seconds = 0.0;  // part of `seconds`
  int64_t seam_edges = 0;       // seam edges stitched (0 without stitching)
  int64_t coplanar_edges = 0;   // coplanar edge pairs joined (lightmap_coplanar.h)
  int64_t shots = 0;
  int64_t rays = 0;
  int64_t visibility_rays = 0;  // the shots' form-factor rays (part of `rays`)
  int64_t shared_clusters = 0;  // receiver clusters that shared their probes' visibility
  size_t texels = 0;
  double initial_power = 0.0;    // W, Σ over texels of the initial unshot exitance × area
  double remaining_power = 0.0;  // W, left unshot when shooting stopped
  double relative_unshot = 0.0;  // the texels' mean relative unshot when shooting stopped
  int64_t relative_shots = 0;    // shots made after the total rule held, for the relative one
  bool converged = false;        // false: stopped by the time budget
  // Power conservation's scale on the form factors per shot (ShootingStats): extremes and
  // power-weighted mean (1 with reach_rays 0).
  double scale_min = 1.0, scale_max = 1.0, scale_mean = 1.0;
};

// World area of each covered texel: the uv1 overlap of every triangle with the texel,
// times the triangle's world/uv1 area ratio (so the areas of a chart sum to its triangles').
// Raster size, one channel.
Image texel_areas(const Scene& scene, const atlas::TexelRaster& raster);

// Throws Error when the scene has no light at all (no point, spot, directional or
// environment light and no emissive surface on a light-mapped mesh), naming it; polls
// Ctrl-C and throws Interrupted. `tracer` must be built from `scene`.
RadiosityBake bake_radiosity(const Scene& scene, const RayTracer& tracer,
                             const atlas::TexelRaster& raster, const RadiosityBakeOptions& options);

}  // namespace illum::bake
