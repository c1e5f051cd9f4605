// Normal-mapped PRT transfer (S002 §5.7, ALGORITHMS.md item 15): where the normal-map
// samples of a bake point come from. A texel or vertex stands for a patch of surface that
// covers many normal-map texels, so its transfer is the mean over that footprint of the
// transfer about the perturbed normal n′ — with the seed's two-normal rule, a direction ω
// counts only where it faces both n′ and the surface (interpolated) normal n:
//   T_i = (1/K) Σ_k (1/π) ∫ max(n′_k·ω, 0) [n·ω > 0] Y_i(ω) dω   (× visibility when shadowed)
// The seed averages K random samples of the map in the patch's rectangle and then uses the
// mean *normal*; we average the K *transfers* instead (prt_baker.cpp): transfer is linear
// in the cosine but not in the normal, so the mean normal of a bumpy patch tends to n and
// loses the darkening the bumps cause (docs/prt.md, "Normal maps").
//
// Footprints. A texel: its square in uv1, carried to uv0 by the affine map of the triangle
// its sample lies on (extended past that triangle's edges: a texel on a chart border reads
// the map where the same surface continues). A vertex: its hat function, the triangles
// around it weighted by the vertex's barycentric coordinate (a triangle picked by area, then
// a point with barycentric λ ~ Beta(2, 2), the density ∝ λ). The K points are the first K
// of a scrambled Sobol' sequence in the footprint (a (0, m, 2)-net for K = 2^m: every
// half, quarter… of a texel's square gets its share), seeded per point.
//
// Frame. The map is read in the point's own tangent frame (the texel sample's, or the
// vertex's tangent orthogonalized against its normal, bitangent = n × t · w), as the ray
// tracer reads it (scene/normal_map.h). Meshes without tangents (the loaders give every mesh
// with uv0 its tangents) or without uv0, and materials without a normal map, give no samples.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/scene/scene.h"

namespace illum::bake {

// The triangles around every vertex of one mesh (compressed rows).
struct VertexRing {
  std::vector<uint32_t> first;      // vertex_count + 1 offsets into triangles
  std::vector<uint32_t> triangles;  // triangle indices, grouped by vertex
};
VertexRing vertex_ring(const Mesh& mesh);

// K world-space perturbed normals of texel sample `sample` into `out` (cleared; left empty
// when the point has no normal map). `seed` scrambles the footprint points.
void texel_normal_samples(const Scene& scene, const atlas::TexelRaster& raster,
                          const atlas::TexelSample& sample, int count, uint64_t seed,
                          std::vector<vec3>& out);

// The same for vertex `vertex` of instance `instance`, whose world normal is `normal`;
// `ring` is vertex_ring of the instance's mesh.
void vertex_normal_samples(const Scene& scene, int instance, uint32_t vertex, const vec3& normal,
                           const VertexRing& ring, int count, uint64_t seed,
                           std::vector<vec3>& out);

}  // namespace illum::bake
