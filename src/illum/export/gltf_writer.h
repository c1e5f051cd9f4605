// A scene written as glTF 2.0 binary (.glb) through tinygltf, optionally with a light-map
// texture that every material references through the MSFT_lightmap vendor extension.
//
// What is written (and what the project's own glTF loader reads back the same):
//   meshes      one glTF mesh of one triangle primitive per Scene::meshes entry, in order:
//               POSITION (with min/max), NORMAL, TANGENT (when the mesh has tangents),
//               TEXCOORD_0 (uv0, when present), TEXCOORD_1 (uv1, when present), 32-bit
//               indices; float bits copied, never recomputed
//   nodes       one root node per Scene::instances entry, in order, with its object-to-world
//               matrix (omitted when it is the identity); then the camera's node, then one
//               node per exported light
//   materials   metallic-roughness: base colour factor (albedo, opacity as alpha) and
//               texture, roughness factor and texture, normal texture and scale, emission
//               (factor ≤ 1, the rest in KHR_materials_emissive_strength); conductors and
//               mirrors metallic with their specular reflectance as base colour; dielectrics
//               KHR_materials_transmission + KHR_materials_ior with their transmittance
//   textures    re-encoded as PNG from the loaded (linear) images: sRGB ones encoded to sRGB
//   camera      perspective (yfov, aspect of the scene's settings), znear 10⁻³ and zfar 10³
//               times the scene's diagonal
//   lights      point, spot and directional as KHR_lights_punctual: colour = value / its
//               largest channel, intensity = that channel × 683 lm/W (glTF's candela and
//               lux; the loader divides it back out); a spot's inner cone angle is the largest
//               float below its outer one (illum's spots have a hard edge)
// Dropped (listed in GltfWriteSummary::dropped): area lights as lights (their emitters keep
// their emissive material), the environment, Phong/Blinn exponents and specular colours
// (glTF has roughness only: Material::roughness is written), conductor complex indices
// (the base colour is the normal-incidence reflectance).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "illum/scene/scene.h"

namespace illum::exporter {

// The light-map as the GLB carries it: an encoded PNG and how to decode it.
struct GltfLightmapTexture {
  std::vector<uint8_t> png;  // RGBA PNG bytes
  // Written as the extension's `extras` (decoding parameters MSFT_lightmap has no field for):
  // {"encoding": "RGBM", "range": M, "tone": ..., "basis": ..., "layer": ...,
  // "bytes": "linear"}; illum's glTF loader reads it back (scene.h: SceneLightmap).
  std::string encoding = "RGBM";
  float range = 1.0f;
  std::string tone = "none";
  std::string basis;  // the folder's basis the map was reduced from (plain, rnm, sh, dominant)
  std::string layer;  // which folder data it holds ("layer0", "mean of the 3 RNM layers", ...)
  // Whether the light-map already holds each scene light's light (Scene::lights order),
  // written to each exported light's extras as "illum_baked".
  std::vector<bool> light_baked;
};

struct GltfWriteSummary {
  size_t meshes = 0, nodes = 0, materials = 0, textures = 0, lights = 0;
  bool camera = false;
  std::vector<std::string> dropped;  // one line per kind of thing not written
};

// The GLB bytes of `scene` (lightmap may be null). Throws Error when tinygltf cannot
// serialise the model or a texture cannot be encoded.
std::vector<uint8_t> scene_to_glb(const Scene& scene, const GltfLightmapTexture* lightmap,
                                  GltfWriteSummary* summary = nullptr);

// An 8-bit PNG of `bytes` (width × height × channels, row 0 at the top) in memory.
std::vector<uint8_t> encode_png(const std::vector<uint8_t>& bytes, int width, int height,
                                int channels);

}  // namespace illum::exporter
