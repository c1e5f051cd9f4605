// Which light-map texels a scene's triangles cover, and the surface point each covered
// texel stands for (ALGORITHMS.md items 5 and 8). Coverage is conservative: every texel a
// triangle touches in uv1 space is covered, including texels the triangle only grazes
// (S000 §2.7.1: seam edges rasterized as lines offset by half a texel and extended one
// texel at both ends), so no texel that bilinear filtering reads inside a chart is left
// unset. A texel's sample point is its centre when that lies inside a covering triangle,
// else the nearest point of the covering triangle that overlaps the texel most.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum::atlas {

struct TexelSample {
  int x = 0, y = 0;             // texel (same convention as atlas.h)
  int instance = 0;             // Scene::instances index
  int triangle = 0;             // triangle of that instance's mesh
  vec2 barycentric{0.0f};       // (b1, b2) of the sample point on that triangle
  vec3 position{0.0f};          // world space
  vec3 normal{0.0f};            // world-space interpolated vertex normal, unit (the front side)
  vec3 geometric_normal{0.0f};  // world-space face normal (winding), unit
  // World-space tangent frame for directional maps: tangent ⟂ normal, unit; bitangent =
  // cross(normal, tangent) · tangent_sign. From Mesh::tangents when present (as the shaders
  // build it), otherwise any frame around the normal.
  vec3 tangent{1.0f, 0.0f, 0.0f};
  float tangent_sign = 1.0f;
  bool centre_inside = true;  // false: the centre lay outside and was moved onto the triangle
};

struct TexelRaster {
  int width = 0;
  int height = 0;
  std::vector<TexelSample> samples;  // one per covered texel, row-major order
  std::vector<int32_t> sample_of;    // width·height entries: index into samples, or −1

  int32_t at(int x, int y) const { return sample_of[size_t(y) * size_t(width) + size_t(x)]; }
  size_t covered() const { return samples.size(); }
};

// Rasterizes every triangle of every instance whose mesh has uv1 (meshes without uv1 are
// skipped). Throws Error for a non-positive size or uv1 outside [0,1] (beyond rounding),
// and also for a size over 16384, a malformed light-mapped mesh (uv1 count, indices), a
// singular transform, or one light-mapped mesh used by two instances (their texels would
// coincide: atlas::make_meshes_unique first). Triangles of zero world area (which rays
// never hit) cover nothing. Runs in parallel (TBB); the result does not depend on it.
TexelRaster rasterize_texels(const Scene& scene, int width, int height);

// Throws Error, prefixed with `who` (the caller's name for itself: "light-map bake"), unless
// `raster` is well formed for `scene`: both sizes ≥ 1, one sample_of entry per texel, every
// sample inside the raster and on a triangle of an instance of the scene (a raster made from
// another scene is refused). The bakers' common input check.
void check_texel_raster(const Scene& scene, const TexelRaster& raster, const char* who);

// Area of the part of `triangle` (texel units, either winding) inside the texel square
// [x, x+1] × [y, y+1]: Sutherland–Hodgman against the square's four sides, then the
// shoelace formula. The raster's largest-overlap rule and the bakers' texel areas use it.
double texel_overlap_area(const glm::dvec2 triangle[3], int x, int y);

// Border post-processing (S002 §3.3.6): `iterations` times, every uncovered texel with
// covered or already-filled 8-neighbours takes their mean, so bilinear filtering at chart
// borders reads no black. `image` has the raster's size. "Already filled" means filled by
// an earlier pass, so the result does not depend on the visiting order. Throws Error for a
// size mismatch or negative iterations.
void dilate(Image& image, const TexelRaster& raster, int iterations);

}  // namespace illum::atlas
