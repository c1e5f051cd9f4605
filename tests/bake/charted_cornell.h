// The built-in Cornell box charted at `resolution` texels, with its tracer and texel raster:
// the shared fixture of the baker tests that bake a real atlas (extras, PRT, split loops).
#pragma once

#include <memory>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/scene/load.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::test {

struct ChartedCornell {
  explicit ChartedCornell(int resolution = 32) : scene(load_scene("cornell")) {
    atlas::make_meshes_unique(scene);
    atlas::AtlasOptions options;
    options.resolution = resolution;
    const atlas::Atlas a = atlas::build_atlas(scene, options);
    atlas::apply_atlas(scene, a);
    tracer = std::make_unique<RayTracer>(scene);
    raster = atlas::rasterize_texels(scene, a.width, a.height);
  }
  Scene scene;
  std::unique_ptr<RayTracer> tracer;
  atlas::TexelRaster raster;
};

}  // namespace illum::test
