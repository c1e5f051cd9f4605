// Relighting baked PRT transfer (prt_baker.h) on the CPU: distant light as world-space RGB SH
// radiance coefficients, and an image of the scene from a camera where each visible surface
// point shows albedo × Σ_i T_i L_i (ALGORITHMS.md item 14, S002 §5.5).
#pragma once

#include <vector>

#include "illum/bake/prt_baker.h"
#include "illum/baked/prt_file.h"
#include "illum/core/color.h"
#include "illum/core/image.h"
#include "illum/scene/camera.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

// Distant light: L(ω) = Σ_i c_i Y_i(ω) radiance arriving from direction ω (world frame).
struct ShLight {
  int bands = 0;
  std::vector<Color> coefficients;         // bands²
  Color radiance(const vec3& from) const;  // the band-limited L(ω)
};

// A sun whose light travels along `direction` (as scene files give it) with irradiance E on a
// surface facing it: L = E δ(ω − s), s = −direction/|direction|, so c_i = E Y_i(s). Throws
// Error for a zero or non-finite direction or a negative or non-finite irradiance.
ShLight sun_light(int bands, const vec3& direction, const Color& irradiance);
// Projection of an environment (equirectangular map × scale, rotation_y, or its constant) by
// the exact solid angle of each map pixel (a Riemann sum of the map's bilinear-free pixel
// values: exact for the piecewise-constant map). Throws Error when the result is all zero
// (an unlit environment) or not finite.
ShLight environment_light(int bands, const Environment& env);
// The band-limited light written back into a width × (width/2) lat-long map (environment.h
// mapping, rotation 0): what the path tracer is given to be lit by the same light.
Image sh_environment_map(const ShLight& light, int width);

// kVq: the VQ-compressed SHL-map, averaged over 4 nearest-representative taps at ±¼ texel
// in x and y (S002 §5.8's multi-sampling filter).
enum class PrtLookup { kTexels, kVertices, kVq };

struct RelightOptions {
  int width = 512, height = 512;
  int samples =
      4;  // primary rays per pixel, the first `samples` cells of an n×n grid, n = ⌈√samples⌉
  PrtLookup lookup = PrtLookup::kTexels;
  bool background = true;  // misses show the band-limited light (else black)
  int threads = 0;
};

// Where relight's sample s of `samples` lies inside its pixel: the centre of cell s of an
// n × n grid, n = ⌈√samples⌉ (in pixel units, [0, 1)²).
vec2 relight_sample_offset(int s, int samples);

// The four texels relight's bilinear lookup reads at atlas coordinate `uv1` on a width ×
// height map (texel (x, y) covers [x, x+1] in uv1 × size; taps clamped to the map), tap k at
// x0 + (k & 1), y0 + (k >> 1), with their weights.
struct TexelTaps {
  int x[4], y[4];
  float weight[4];
};
TexelTaps bilinear_texel_taps(vec2 uv1, int width, int height);

// `scene` must have the set applied (apply_prt_set) and `tracer` be built from it. Uses
// bilinear lookup in the (dilated) texel transfer at uv1, or barycentric interpolation of the
// vertex transfer. Throws Error if the set lacks the chosen lookup's data or the light's
// band count differs from the set's.
Image relight(const Scene& scene, const RayTracer& tracer, const baked::PrtSet& set,
              const ShLight& light, const Camera& camera, const RelightOptions& options);

// What each pixel of a width × height image from `camera` sees over its whole footprint, by
// rays on a 9×9 grid spanning the pixel, edges included: kMiss (a ray missed), kSurface (all
// hit), kFlat (all hit one instance with one geometric normal). Per-pixel comparisons of
// `relight` with the path tracer use the flat pixels: where an edge crosses a pixel, the
// relight's fixed ray grid and the path tracer's jittered samples weigh its sides
// differently, which is no error of the transfer.
enum class PixelFootprint : uint8_t { kMiss, kSurface, kFlat };
std::vector<PixelFootprint> pixel_footprints(const RayTracer& tracer, const Camera& camera,
                                             int width, int height);

}  // namespace illum::bake
