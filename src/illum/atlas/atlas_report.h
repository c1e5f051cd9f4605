// What an atlas makes of a scene, measured from its layouts alone: charts, how much of the
// atlas the triangles fill, and the texel density and stretch of every triangle against
// the nominal density (one texel per texel_size², the mesh's own texel size where its scene
// entry gives one). Used by `illum-bench atlas`, by `illum bake` (the density of reused
// UV1) and by the tests.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/atlas/atlas.h"
#include "illum/scene/scene.h"

namespace illum::atlas {

// Per triangle, with σ1 ≥ σ2 the singular values of the map from the world triangle to
// uv1 in texels, times the nominal texel size (1, 1 at the nominal density without
// distortion): density = σ1σ2 (uv1 area / nominal area), L2 stretch = √((σ1² + σ2²)/2)
// (Sander et al. 2001), anisotropy = σ1/σ2.
struct DensityStats {
  double world_area = 0.0;      // m², non-degenerate triangles
  double nominal_texels = 0.0;  // Σ world area / texel_size²
  double uv_texels = 0.0;       // Σ uv1 area in texels
  double mean_density = 0.0;    // uv_texels / nominal_texels
  double min_density = 0.0;     // over triangles
  double max_density = 0.0;
  double rms_l2_stretch = 0.0;  // area-weighted root mean square of the L2 stretch
  double max_anisotropy = 0.0;  // over triangles
  size_t triangles = 0;         // judged (non-degenerate in world and in uv1)
};

struct AtlasStats {
  int charts = 0;
  double chart_texels = 0.0;  // Σ chart rectangles (cells), texels
  // uv1 area of every triangle / atlas area: the share of texels the surfaces fill (exact
  // areas; conservative coverage adds the texels triangles only graze).
  double utilisation = 0.0;
  DensityStats all;
  std::vector<DensityStats> meshes;  // per Scene::meshes entry (empty stats: no instance)
};

// `scene` carries the atlas (apply_atlas done: Mesh::uv1 is its layout); the atlas gives
// the size, the texel size and the charts. Throws Error for a mesh without uv1.
AtlasStats measure_atlas(const Scene& scene, const Atlas& atlas);

}  // namespace illum::atlas
