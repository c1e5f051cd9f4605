// Precomputed radiance transfer for diffuse surfaces (ALGORITHMS.md item 14, S002 §5.2–5.4:
// CaSHL's SHL-maps, and the same per vertex). For every covered texel of a light-map atlas
// and every vertex of the (atlas-applied) scene, an RGB vector T of bands² SH coefficients
// such that, under distant light of world-space SH radiance coefficients L_i (convention:
// core/sh.h, world frame, z the pole),
//   E/π = Σ_i T_i L_i        and the outgoing radiance of the surface is albedo × E/π,
// where E is the irradiance the point receives (direct and, in `interreflected` mode,
// bounced). T carries no albedo of its own point — as the light-map's plain layer (E/π),
// the renderer multiplies by the texture-resolved albedo — but the albedos of the surfaces
// the light bounced off are in it (that is why T is RGB). Modes:
//   unshadowed      T_i = (1/π) ∫ max(n·ω, 0) Y_i(ω) dω = (Λ_l/π) Y_i(n) (closed form,
//                   core/sh zonal_along with the clamped-cosine factors; no rays)
//   shadowed        T_i = (1/π) ∫ V(ω) max(n·ω, 0) Y_i(ω) dω, V = 1 when the ray to ω escapes;
//                   `spp` cosine-distributed rays, T_i = (1/N) Σ V(ω_k) Y_i(ω_k)
//   interreflected  shadowed + the light bounced between surfaces, by progressive shooting
//                   of SH vectors (prt_shooting.h, S002 §5.4.3)
// n is the interpolated (shading) normal; directions below the geometric surface count
// zero, as in the light-map baker. On a normal-mapped material n is the map's perturbed
// normal, averaged over the point's footprint, and directions below the interpolated
// normal count zero too (prt_normal_map.h); unshadowed is then estimated with `spp`
// untraced rays, the same estimator as shadowed without the visibility test.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/bake/prt_shooting.h"
#include "illum/baked/prt_file.h"
#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

// The transfer's data types are the PRT folder's (baked/prt_file.h).
using baked::kMaxPrtBands;
using baked::kMinPrtBands;
using baked::prt_mode_from_string;
using baked::PrtMode;
using baked::to_string;
using baked::TransferMap;

struct PrtBakeOptions {
  int bands = 4;  // 2..8 (n² coefficients)
  PrtMode mode = PrtMode::kShadowed;
  int spp = 256;  // visibility rays per texel or vertex, and shooting rays per patch
  // Shooting stops when the unshot transfer (Σ area·Σ|c| over patches) is below this share
  // of the direct transfer's, or after max_rounds rounds (prt_shooting.h).
  double shoot_tolerance = 1e-3;
  // And when the mean over patches of their unshot / what they reflect is below this
  // (TransferShootingOptions::relative_tolerance; 1: off).
  double shoot_relative_tolerance = 0.05;
  int max_rounds = 64;
  int dilate = 4;  // border passes of atlas::dilate on every coefficient map
  // Seam stitching of the SHL-map after dilation, each coefficient as a light-map layer
  // (lightmap_seams.h), and with it coplanar neighbours (lightmap_coplanar.h). Off here, so
  // a caller that fills this struct gets the baked transfer as it is; from_params turns it
  // on (keys stitch, stitch_coplanar).
  bool stitch = false;
  bool stitch_coplanar = true;
  uint64_t seed = 0;
  bool texels = true;    // bake the SHL-map (per covered texel of the raster)
  bool vertices = true;  // bake per vertex of every instance
  // Normal maps (prt_normal_map.h): a point whose material has one gets the mean transfer
  // of `normal_map_samples` perturbed normals read across its footprint; false bakes every
  // point about its interpolated normal, as if no material had a map.
  bool normal_maps = true;
  int normal_map_samples = 16;
  int threads = 0;
  bool progress = true;

  // Keys: bands (2..8), mode, spp (1..2²⁰), shoot_tolerance and shoot_relative_tolerance
  // (1e-6..1), max_rounds
  // (0..10000), dilate (0..64), stitch and stitch_coplanar (bool, default true), seed,
  // normal_maps (bool), normal_map_samples (1..4096). Throws Error for out-of-range values or
  // unknown names.
  static PrtBakeOptions from_params(const Params& params);
  void validate() const;  // the same ranges; throws Error
};

// Transfer vectors, each coefficient_count(bands) RGB triples laid out [point][i][rgb].
struct PrtBake {
  int bands = 0;
  PrtMode mode = PrtMode::kShadowed;
  // Raster-sized, 3·bands² channels ([i][rgb] per texel), dilated: uncovered texels next
  // to charts filled by atlas::dilate, the rest zero. Empty when texels were not baked.
  TransferMap texel_transfer;
  // Per instance (Scene::instances order), per vertex of its mesh.
  std::vector<std::vector<float>> vertex_transfer;
  double seconds = 0.0;
  double shoot_seconds = 0.0;    // part of seconds
  double stitch_seconds = 0.0;   // part of seconds: finding the seams and solving
  int64_t seam_edges = 0;        // seam edges stitched (0 without stitching)
  int64_t coplanar_edges = 0;    // coplanar edge pairs joined
  int shoot_rounds = 0;          // texel and vertex shooting together
  double unshot_fraction = 0.0;  // the larger of the two sets' unshot / direct at the end
  double relative_unshot = 0.0;  // the larger of the two sets' (TransferShootingResult)
  // Where the texel shooting's light went (the vertex set's when texels were not baked), and
  // how many patches' back sides received some (prt_shooting.h).
  TransferShotShares shot_shares;
  int64_t back_sides = 0;
  int64_t rays = 0;
  size_t texels = 0;  // covered texels baked
  size_t vertices = 0;
};

// The shooting's figures for a manifest's "bake" object: shoot_rounds, unshot_fraction,
// relative_unshot, shot_shares {front, back, escaped, lost, below} and back_sides.
nlohmann::json shooting_record(const PrtBake& baked);

// The patches the interreflected mode shoots between, and where a hit lands: one per covered
// texel of `raster` (area: the world area of the texel's part of the charts, by clipping
// each triangle's uv1 to the texel) or one per vertex of every instance (area: a third of
// the adjacent triangles'; a hit is received by its triangle's corners by barycentric
// weight). A hit against the winding lands on the back sides of the same patches. The
// receiver refers to `scene` and `raster`, which must outlive it.
struct PrtPatches {
  std::vector<TransferPatch> patches;
  TransferReceiver receiver;
};
PrtPatches texel_patches(const Scene& scene, const atlas::TexelRaster& raster);
PrtPatches vertex_patches(const Scene& scene);

// Bakes every covered texel of `raster` (may be empty when options.texels is false) and
// every vertex. `tracer` must be built from `scene`. Polls interrupt_requested() and throws
// Interrupted; throws Error for bad options.
PrtBake bake_prt(const Scene& scene, const RayTracer& tracer, const atlas::TexelRaster& raster,
                 const PrtBakeOptions& options);

}  // namespace illum::bake
