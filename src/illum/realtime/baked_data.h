// Baked lighting the renderer shows (the `baked` add-on): light-maps, the irradiance volume
// of probes for dynamic objects, PRT transfer vectors. The renderer keeps them
// (Renderer::set_lightmap, ...) so the add-on can be switched off and on again without giving them
// anew.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/realtime/probe_volume.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

// Baked light-map data for display (uv1 coordinates). Layers: kPlain 1 (irradiance/π, RGB),
// kRnm 3 (the Source basis maps, tangent space), kShL1 4 (radiance SH coefficients Y00,
// Y1−1 (y), Y10 (z), Y11 (x), tangent space), kDominant 3 (ambient A, directional colour
// C, unit dominant direction d in tangent space: E/π(n) = A + C·max(0, n·d),
// bake/lightmap_basis.h). All layers share one size. Its intensity is the parameter
// baked.intensity.
enum class LightmapKind : int { kNone = 0, kPlain = 1, kRnm = 2, kShL1 = 3, kDominant = 4 };
struct Lightmap {
  LightmapKind kind = LightmapKind::kNone;
  std::vector<Image> layers;
};

// Baked PRT transfer (baked/prt_file.h) for display: RGB SH vectors T of bands² coefficients,
// [point][coefficient][rgb], with E/π = Σ_i T_i·L_i under distant light of world-space SH
// radiance L_i (core/sh.h). The `baked` add-on shows albedo × max(Σ T_i L_i, 0) in place of
// the ambient term, L_i its sun projected to SH each frame, through one of the lookups of
// `illum relight --lookup` (baked.prt_lookup): vertices (one point per vertex of every mesh
// in scene order, interpolated barycentrically), texels (the atlas-sized SHL-map at uv1,
// bilinear over texel centres, clamped at the edges) or vq (representatives + one index per
// texel; 4 nearest taps at ±¼ texel averaged, S002 §5.8). Uploaded as half floats and
// decoded on the GPU in every frame pipeline.
enum class PrtLookup : int { kNone = 0, kVertices = 1, kTexels = 2, kVq = 3 };
struct PrtTransfer {
  int bands = 0;              // 0: no PRT; 1..8 (the uniform holds 64 coefficients)
  int width = 0, height = 0;  // the atlas size (texels, vq)
  std::vector<float> vertices, texels, vq_representatives;  // each empty when absent
  std::vector<uint16_t> vq_indices;                         // width·height, or empty
  bool empty() const { return bands == 0; }
  int channels() const { return 3 * bands * bands; }
};

struct BakedData {
  Lightmap lightmap;
  // The probes lighting the dynamic instances (empty: none), read per pixel
  // (shaders/probe_volume.glsl); and, for the per-instance fallback (baked.probe_lookup =
  // instance), one ambient cube per probed draw: 6 values E/π (+x, −x, +y, −y, +z, −z), the
  // per-pixel lookup at the centre of the instance's world bounds along each axis.
  ProbeVolume probes;
  std::vector<vec4> cubes;     // 6 values per probed draw's cube
  std::vector<int> draw_cube;  // per draw item: its cube + 1, 0 for none (empty: no probes)
  PrtTransfer prt;             // lookup kNone: no PRT
};

// Fills data->cubes and data->draw_cube from `volume` for the draws of `scene`
// (draw_instances: the instance of each draw item); throws Error as check_probe_volume.
void probe_instance_cubes(const ProbeVolume& volume, const Scene& scene,
                          const std::vector<int>& draw_instances, BakedData* data);

}  // namespace illum::realtime
