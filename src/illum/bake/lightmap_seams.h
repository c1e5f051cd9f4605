// Seams and leaks of light-maps (issue 12 part 4; S000 §2.7.1, S002 §3.3.6):
//   keep_texels_out_of_geometry  texel sample points never inside or behind geometry (run
//                                once on the raster, before any baker reads it);
//   stitch_seams                 least-squares agreement of the bilinear lookups on both
//                                sides of every chart edge (run on the baked layers).
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

// World size of one texel at a sample (metres per texel along the stretchiest uv1
// direction of its triangle).
float texel_world_size(const Scene& scene, const atlas::TexelRaster& raster,
                       const atlas::TexelSample& sample);

}  // namespace illum::bake
