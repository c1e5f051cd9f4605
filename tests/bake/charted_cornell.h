// A scene (or the built-in Cornell box) charted by the atlas, with its tracer and texel
// raster: the shared fixture of the baker tests that bake a real atlas (extras, PRT, split
// loops, radiosity, seams).
#pragma once

#include <memory>
#include <utility>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/scene/load.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::test {

// Any scene charted by the atlas (every mesh gets uv1), with its tracer and texel raster.
struct ChartedScene {
  ChartedScene(Scene s, const atlas::AtlasOptions& options) : scene(std::move(s)) {
    const atlas::Atlas a = atlas::chart_scene(scene, options);
    texel_size = a.texel_size;
    tracer = std::make_unique<RayTracer>(scene);
    raster = atlas::rasterize_texels(scene, a.width, a.height);
  }
  ChartedScene(Scene s, int resolution)
      : ChartedScene(std::move(s), atlas::AtlasOptions{.resolution = resolution}) {}
  Scene scene;
  float texel_size = 0.0f;
  std::unique_ptr<RayTracer> tracer;
  atlas::TexelRaster raster;
};

struct ChartedCornell : ChartedScene {
  explicit ChartedCornell(int resolution = 32) : ChartedScene(load_scene("cornell"), resolution) {}
};

}  // namespace illum::test
