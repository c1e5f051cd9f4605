// Internal to illum::atlas: the chart a mesh piece becomes (charting.cpp) and what packs
// charts into the atlas (packing.cpp); build_atlas (atlas.cpp) joins the two. Not installed
// for other layers: the public interface is atlas.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum::atlas::detail {

using glm::dvec2;
using glm::dvec3;

// A finished chart: local 2-D coordinates in metres, rotated to the minimal-area bounding
// rectangle, lying (size.x ≥ size.y), with its minimum corner at the origin.
struct Chart {
  int mesh = 0;
  std::vector<uint32_t> triangles;
  std::vector<dvec2> corners;  // 3 per triangle, in `triangles` order
  dvec2 size{0.0};
  double area = 0.0;  // of the projected triangles, m²
  // The mesh's own texel size (scene file "lightmap": {"texel_size"}); 0: the atlas's.
  double texel_size = 0.0;

  // Metres per texel of this chart when the atlas's texel size is s.
  double texel(double s) const { return texel_size > 0.0 ? texel_size : s; }

  double fill() const { return size.x * size.y > 0.0 ? area / (size.x * size.y) : 1.0; }
};

std::string mesh_label(const Mesh& mesh, size_t index);

// Charts of one mesh in world space (`transform`: its instance's), every normal of a chart
// within acos(cos_max) of its projection axis; sparse charts wasting more than
// `waste_limit` m² of their rectangle are cut. Throws Error for malformed meshes.
std::vector<Chart> chart_mesh(const Mesh& mesh, size_t mesh_index, const mat4& transform,
                              double cos_max, double waste_limit);

// Scales a chart uniformly so that its area is `world_area`: a projected chart loses
// cos θ of each triangle's area (θ its angle to the axis), and a given UV1 has a scale of
// its own; scaled, the chart holds as many texels as its surface has at the nominal density
// (curved surfaces are no longer packed coarser than flat ones). The angle limit bounds
// each triangle's density to [cos θmax, 1 / cos θmax] of the nominal one.
void scale_to_area(Chart& chart, double world_area);

// A mesh's own UV1 (checked by mesh_uv1_problem) as its one chart: turned to its
// minimal-area rectangle and scaled to the nominal density on average (the density of
// each triangle is the author's).
Chart chart_from_uv1(const Mesh& mesh, size_t mesh_index, const mat4& transform);

// Texel cells a chart of `size` metres reserves at texel size `s`.
ivec2 cells_of(const dvec2& size, double s);
// Where a chart sits in its cells (texels from the cells' first corner).
dvec2 offset_in_cells(const Chart& chart, const ivec2& cells, double s);
// Packs every chart at texel size `s` (charts with a texel size of their own at theirs):
// origins[c] is the first texel of chart c's cells.
bool pack_charts(const std::vector<Chart>& charts, double s, int resolution, int padding,
                 std::vector<ivec2>* origins);
// The finest float texel size that packs (0 if none does). Charts with their own texel
// size keep it; at least one chart must have none.
float finest_texel_size(const std::vector<Chart>& charts, int resolution, int padding);

}  // namespace illum::atlas::detail
