// Checks of a light-map UV set (Mesh::uv1) a scene brings with it, before anything reuses
// it instead of charting anew: build_atlas keeps a mesh's own UV1 when mesh_uv1_problem
// finds nothing (AtlasOptions::reuse_uv1).
#pragma once

#include <optional>
#include <string>

#include "illum/scene/scene.h"

namespace illum::atlas {

// Two light-mapped triangles whose uv1 interiors overlap: they would share texels and
// receive one value for two different places.
struct Uv1Overlap {
  int mesh_a = 0, triangle_a = 0;
  int mesh_b = 0, triangle_b = 0;
};

// The first overlap (lowest mesh, then triangle, of the pair's first member; then the
// second's) among every triangle of every mesh that has uv1, across meshes too (all share
// one light-map). Triangles of either winding in uv1 (mirrored charts are legitimate);
// touching along shared edges or corners, within 1e-6 in uv1 (float rounding of [0,1]
// coordinates written by another tool), is no overlap; triangles of zero uv1 area cover
// nothing and are not judged. A uniform grid of about one cell per triangle over [0,1]²
// keeps it near-linear. Throws Error for a malformed light-mapped mesh (uv1 count,
// indices) or a non-finite uv1, naming the mesh.
std::optional<Uv1Overlap> find_uv1_overlap(const Scene& scene);

// Why one mesh's uv1 cannot be its light-map layout, in a few words ("its triangles 3 and 7
// overlap in uv1"), or nothing when it can: uv1 present (one per vertex), finite, inside
// [0,1]², no triangle with surface (in world space, `transform` its instance's) but no uv1
// area, and no two triangles of the mesh overlapping (find_uv1_overlap's rules: mirrored
// triangles and touching edges are fine). Other meshes are not looked at: the atlas gives
// each reused UV1 a region of its own.
std::optional<std::string> mesh_uv1_problem(const Mesh& mesh, const mat4& transform);

// Throws Error when find_uv1_overlap finds one: "uv1 of mesh 'a' triangle i overlaps mesh
// 'b' triangle j (…)", one line.
void check_given_uv1(const Scene& scene);

}  // namespace illum::atlas
