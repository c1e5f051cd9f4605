// Baked lighting the renderer shows (the `baked` add-on): light-maps, ambient-cube probes,
// PRT transfer vectors. The renderer keeps them (Renderer::set_lightmap, ...) so the
// add-on can be switched off and on again without giving them anew.
#pragma once

#include <vector>

#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

// Baked light-map data for display (uv1 coordinates). Layers: kPlain 1 (irradiance/π, RGB),
// kRnm 3 (the Source basis maps, tangent space), kShL1 4 (radiance SH coefficients Y00,
// Y1−1 (y), Y10 (z), Y11 (x), tangent space). All layers share one size. Its intensity is
// the parameter baked.intensity.
enum class LightmapKind : int { kNone = 0, kPlain = 1, kRnm = 2, kShL1 = 3 };
struct Lightmap {
  LightmapKind kind = LightmapKind::kNone;
  std::vector<Image> layers;
};

// A regular grid of ambient cubes (probes) lighting dynamic objects: each listed instance
// takes the cube trilinearly interpolated at its world-bounds centre (clamped to the grid)
// instead of the light-map / constant ambient. cubes[((z·ny + y)·nx + x)·6 + face], faces
// +x, −x, +y, −y, +z, −z; radiance-like values multiplied by albedo.
struct AmbientCubeGrid {
  glm::ivec3 size{0};
  vec3 origin{0.0f}, spacing{1.0f};
  std::vector<Color> cubes;
  std::vector<int> instances;
};

struct BakedData {
  Lightmap lightmap;
  std::vector<vec4> cubes;         // 6 values per probed draw's interpolated cube
  std::vector<int> draw_cube;      // per draw item: its cube + 1, 0 for none (empty: no probes)
  std::vector<vec4> prt_transfer;  // per vertex, empty: no PRT
};

// Fills data->cubes and data->draw_cube from `grid` for the draws of `scene` (draw_instances:
// the instance of each draw item); throws Error for a grid whose size does not match its
// values or an instance that does not exist.
void interpolate_ambient_cubes(const AmbientCubeGrid& grid, const Scene& scene,
                               const std::vector<int>& draw_instances, BakedData* data);

}  // namespace illum::realtime
