// Reconciliation of coplanar neighbours (S002 §3.3.6, the seed's second border step):
// chart-boundary edges of surfaces in one plane that meet only in part — a
// T-junction (one long edge beside two short ones), two objects abutting with differently
// split edges, or edges a hair apart — matched along their overlapping sub-segments. The
// matches become seam samples of the same least-squares stitching system as seams whose end
// points coincide (lightmap_seams.h: find_seams calls this, stitch_seams solves both).
// docs/lightmaps.md (Seams and leaks) shows the before and after.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/core/math.h"

namespace illum::bake {

struct SeamSample;

// A triangle edge no other triangle edge shares both end points with (an open edge: a chart
// or mesh boundary that the end-point matching of find_seams left alone), in world space.
struct OpenEdge {
  vec3 p[2];          // world end points
  vec2 uv[2];         // texel coordinates (uv1 × atlas size) at the end points
  vec3 normal[2];     // shading normals at the end points (unit; the plane's when absent)
  vec3 plane_normal;  // the triangle's geometric normal (unit)
  vec3 inward;        // unit, in the triangle's plane, across the edge into the triangle
};

// One plane: geometric normals within this cosine (about 1.1°), the edges parallel within
// it. Tighter than kSeamNormalCos: the pairs are not known to be one surface's pieces, so
// only surfaces that are flat together are joined; a fold (even one smooth shading normals
// hide) is left to the light.
inline constexpr float kCoplanarCos = 0.9998f;
// Edges whose lines lie within this many texels (world size of the coarser side's texel)
// of each other are neighbours ("near-neighbours", the seed's words). A gap this small
// cannot be resolved by either light-map; anything thicker between two floors (a wall of
// 5 cm at 4 cm texels is 1.25 texels) keeps them apart, so no light is carried across it.
inline constexpr float kCoplanarGapTexels = 0.1f;

// Pairs of open edges that (a) lie in one plane (geometric normals within kCoplanarCos) and
// face the same way, (b) are parallel with both ends of their overlap within
// max(`tolerance`, kCoplanarGapTexels texels) of the other edge, (c) overlap along a
// sub-segment longer than that distance, (d) have their triangles on opposite sides of the
// common line (no overlapping coplanar surfaces), (e) have shading normals within
// kSeamNormalCos at both ends of the overlap (as find_seams: smooth there), and (f) are cut
// in uv1 (the two sides' uv differ by more than 1e-3 texel at an end of the overlap).
// For each pair, kSeamSamplesPerTexel samples per texel of overlap (≥ 2), side 0 the lower
// index, are appended to `samples`. Candidates come from a uniform grid, each pair is tested
// once, in edge order (deterministic). Returns the number of pairs.
int64_t find_coplanar_seams(const std::vector<OpenEdge>& edges, float tolerance,
                            std::vector<SeamSample>& samples);

}  // namespace illum::bake
