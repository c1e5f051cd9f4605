// The spread of a per-texel PRT bake's direct (shadowed) transfer over bake seeds, as it
// shows in relit images: what `illum-bench prt-vs-path` needs for an honest σ of the relit
// side. Two bakes cannot give it under a peaked light seen through small openings (a
// band-limited sun or an environment's sun, Sibenik's windows): a texel's cosine-distributed
// rays find the light's lobe only rarely, so its estimate is heavy-tailed — most bakes miss
// the lobe (too dark), a few hit it (far too bright) — and (a − b)²/4 of two bakes is most
// often far below the true variance (docs/prt.md, "Where the direct light's deficit went").
#pragma once

#include <vector>

#include "illum/atlas/texel_raster.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/core/image.h"
#include "illum/scene/camera.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bench {

// The covered texels that relight's lookups from `camera` can read (the four bilinear taps
// of every primary ray of its sample grid) and those within `margin` texels of them (what
// the dilation of an uncovered tap reads), as a raster of their own: baking it gives those
// texels exactly the values a bake of the whole raster gives them (a texel's rays are
// seeded by its own coordinates), at the cost of a few thousand texels.
atlas::TexelRaster texels_seen(const RayTracer& tracer, const atlas::TexelRaster& raster,
                               const Camera& camera, const bake::RelightOptions& relight,
                               int margin);

// Per pixel of relight's image: whether every bilinear tap of every primary ray of its
// sample grid is a covered texel whose sample lies on the hit's instance and plane (no tap
// in a dilated border texel, in another chart packed alongside, or across a crease or
// contact line): where the lookup interpolates only the surface the pixel shows.
std::vector<char> interior_lookups(const RayTracer& tracer, const atlas::TexelRaster& raster,
                                   const Camera& camera, const bake::RelightOptions& relight);

// images[j][l]: the relit image under lights[l] of the shadowed transfer baked on `seen`
// with seed first_seed + j, for j < seeds (stitching off: it solves over the whole atlas).
std::vector<std::vector<Image>> direct_relit_over_seeds(const Scene& scene, const RayTracer& tracer,
                                                        const atlas::TexelRaster& seen,
                                                        const std::vector<bake::ShLight>& lights,
                                                        const Camera& camera,
                                                        const bake::RelightOptions& relight,
                                                        bake::PrtBakeOptions options,
                                                        uint64_t first_seed, int seeds);

}  // namespace illum::bench
