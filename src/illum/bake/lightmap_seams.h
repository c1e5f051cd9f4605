// Seams and leaks of light-maps (S000 §2.7.1, S002 §3.3.6):
//   keep_texels_out_of_geometry  texel sample points never inside or behind geometry (run
//                                once on the raster, before any baker reads it);
//   find_seams                   chart edges to join: same end points, or coplanar
//                                neighbours meeting in part (lightmap_coplanar.h);
//   stitch_seams                 least-squares agreement of the bilinear lookups on both
//                                sides of every such edge (run on the baked layers).
// docs/lightmaps.md (Seams and leaks) shows what each does and the commands.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/core/image.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

struct TexelPushOut {
  int64_t moved = 0;     // samples moved out of (or off the back of) geometry
  int64_t rejected = 0;  // samples no position could be found for: now uncovered
};

// For every covered texel, casts 8 rays in the sample's tangent plane (±t, ±b and the four
// diagonals of the geometric normal's frame), lifted off the surface as rays leaving it
// are, each as long as the texel's world size h (largest singular value of the triangle's
// uv1 → world map, in texels). A ray that first hits a back face (winding normal along the
// ray) means the point lies inside or behind something: a floor continuing under a wall, a
// wall passing through a ceiling. The sample is moved along the nearest such ray to just
// past that face (0.01·h beyond it, in the sample's plane; the barycentric stays that of
// the original point, used only for the material's uv0), and the test is run again from
// there. If it still sees a back face, or no ray was free to move along, the texel is
// rejected: it becomes uncovered, so the bakers skip it and dilation fills it from its
// neighbours. Front-face hits leave a sample alone (a floor texel beside a wall is lit
// correctly from where it is). Deterministic (each texel on its own); parallel. Every
// baker reads the fixed raster, so the path, radiosity, PRT and extra maps agree.
TexelPushOut keep_texels_out_of_geometry(const Scene& scene, const RayTracer& tracer,
                                         atlas::TexelRaster& raster);

// One point of a seam edge as each of its two sides maps it into the atlas: texel
// coordinates (uv1 × atlas size, texel centres at +0.5), where the renderer's bilinear
// lookup of either side lands.
struct SeamSample {
  vec2 side[2];
};

struct Seams {
  int64_t edges = 0;            // seam edges (pairs of triangle edges with the same ends)
  int64_t within_instance = 0;  // of which both sides belong to one instance
  int64_t coplanar_pairs = 0;   // pairs of coplanar open edges joined along their overlap
  // kSeamSamplesPerTexel per texel of edge (or overlap) length, ≥ 2 per edge; the seams
  // with the same ends first, then the coplanar pairs'.
  std::vector<SeamSample> samples;
};

// Samples per texel of seam length: ≥ 2 so the piecewise-bilinear lookup along an edge is
// pinned between texel centres, not only at them.
inline constexpr int kSeamSamplesPerTexel = 3;
// Shading normals within this cosine (about 8°) on both sides at both ends: the surface
// is smooth there, so its light is continuous across the edge. A crease (a box's corner),
// or the two faces of a thin wall, is no seam: the light may differ there, and stitching
// would leak it.
inline constexpr float kSeamNormalCos = 0.99f;

struct SeamFindOptions {
  float tolerance = 0.0f;  // end points this close are one; 0: 1e-6 of the scene's extent
  // Also join coplanar neighbours meeting in part (T-junctions, near neighbours): the open
  // edges (no other edge shares both end points) go to find_coplanar_seams.
  bool coplanar = true;
};

// Finds every seam edge of the light-mapped instances of `scene` (uv1 applied, the atlas
// `width` × `height`): two triangle edges with the same world end points (within the
// tolerance), within one instance or between two, whose uv1 differ at either end by more
// than 1e-3 texel, and whose shading normals agree (kSeamNormalCos) at both ends. With
// `options.coplanar`, then the pairs of open edges that lie in one plane and overlap in
// part (lightmap_coplanar.h). Deterministic (triangle order).
Seams find_seams(const Scene& scene, int width, int height, const SeamFindOptions& options = {});

// The renderer's bilinear lookup of an RGB layer at texel coordinates (centres at +0.5,
// clamped at the border, as the sampler's clamp-to-edge).
Color bilinear_lookup(const Image& layer, const vec2& texel);

struct SeamStitchOptions {
  // The regulariser's weights per texel against each seam sample's weight 1: how strongly
  // a texel keeps its baked value. Covered texels (their value was estimated) hold on
  // harder than gutter texels (filled by dilation only so bilinear lookups read no black).
  float covered_weight = 0.005f;
  float gutter_weight = 0.0005f;
  int max_iterations = 1000;
  double tolerance = 1e-6;  // CG stops at this relative residual
};

struct SeamStitchStats {
  int64_t samples = 0;          // seam samples (least-squares rows)
  int64_t texels = 0;           // texels the lookups touch (unknowns per channel)
  int iterations = 0;           // CG iterations (all channels solved together), every round
  int held_at_zero_rounds = 0;  // extra solves with more entries held at zero
  int64_t held_at_zero = 0;     // texel channels the solve would have made negative
  double seconds = 0.0;
};

// Solves after the first that hold more texel channels at zero (the active set of the
// non-negativity constraint) before the stitch gives up and clamps what is left.
inline constexpr int kMaxNonNegativeRounds = 8;

// Seam stitching: moves the texels under `seams`' lookups so the bilinear values on both
// sides of every seam sample agree, in the least-squares sense with a regulariser that
// keeps each texel near its value: minimise over the touched texels x, per channel,
//   Σ_samples (B₀x − B₁x)² + Σ_texels λ_i (x_i − x⁰_i)²
// (B_k: the bilinear weights of side k; λ_i from `options`), subject to x ≥ 0, by
// conjugate gradients with a Jacobi preconditioner on the normal equations, matrix-free;
// the constraint by an active set (texel channels driven below zero are held at zero and
// the rest solved again, kMaxNonNegativeRounds at most). Every layer (same size) is
// stitched, each channel on its own with the same matrix; texels no lookup touches are
// left alone. Deterministic.
// Throws Error for layers not of the raster's size.
SeamStitchStats stitch_seams(const Seams& seams, const atlas::TexelRaster& raster,
                             std::vector<Image>& layers, const SeamStitchOptions& options = {});

// What a baker runs after dilation: find_seams (coplanar neighbours when `coplanar`) and
// stitch_seams on `layers`, timed from the start of the search.
struct StitchReport {
  int64_t seam_edges = 0;
  int64_t coplanar_edges = 0;  // Seams::coplanar_pairs
  SeamStitchStats solve;
  double seconds = 0.0;  // finding and solving
};
StitchReport stitch_baked_layers(const Scene& scene, const atlas::TexelRaster& raster,
                                 std::vector<Image>& layers, bool coplanar);

// World size of one texel at a sample (metres per texel along the stretchiest uv1
// direction of its triangle).
float texel_world_size(const Scene& scene, const atlas::TexelRaster& raster,
                       const atlas::TexelSample& sample);

}  // namespace illum::bake
