// `illum export`: a scene and its baked light-map folder handed to other tools as one glTF
// binary (gltf_writer.h) plus the linear EXR beside it.
//
//   OUT.glb            the scene with the folder's atlas applied exactly as the real-time
//                      renderer applies it (baked::apply_lightmap_set: the same make_meshes_
//                      unique + apply_atlas, refused for a folder baked for another scene), so
//                      TEXCOORD_1 is the baked uv1; every material references the light-map
//                      through MSFT_lightmap (texCoord 1) as an RGBM PNG embedded in the GLB
//   OUT.lightmap.exr   the same map, linear 32-bit float RGB, for engines that take HDR
//
// The map is the irradiance layer E/π (albedo × map = a Lambertian surface's outgoing
// radiance): a plain folder's layer 0 as it is; RNM and SH-L1 folders are reduced to it at
// the surface normal, as the real-time renderer shows them for an unperturbed normal (RNM:
// the mean of the three basis maps, each weighing (1/√3)² normalised; SH-L1: c0·Y00 +
// (2/3)·c_z·Y1(z), clamped at 0). Directional detail is not exported.
//
// RGBM (core/hdr_encoding.h): c = rgb · a · M per texel, bytes stored linear (no sRGB curve),
// M in the extension's extras ("range"). M defaults to the map's largest channel, so nothing
// clamps and each texel's error is at most rgbm_error_bound(its largest channel, M). With
// tone "lrp97" the PNG holds LRP97 histogram tone reproduction (core/histogram_tone.h) of the
// map, display values in [0, 1] at M = 1; the EXR stays linear either way.
//
// Both files are written beside their final names under hidden temporary names and renamed
// at the end; on any failure neither is left (nor a temporary file). An existing pair is
// replaced.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "illum/baked/lightmap_file.h"
#include "illum/core/image.h"
#include "illum/export/gltf_writer.h"
#include "illum/scene/scene.h"

namespace illum::exporter {

struct LightmapExportOptions {
  std::string tone = "none";  // none | lrp97 (the PNG only)
  float rgbm_range = 0.0f;    // M; 0: the map's largest channel (tone none) or 1 (lrp97)
};

struct LightmapExportResult {
  std::filesystem::path glb, exr;
  std::string layer;  // what the map holds (gltf extras "layer")
  float rgbm_range = 1.0f;
  int width = 0, height = 0;
  size_t glb_bytes = 0, png_bytes = 0;
  GltfWriteSummary gltf;
};

// OUT.glb → OUT.lightmap.exr.
std::filesystem::path lightmap_exr_path(const std::filesystem::path& glb);
// Throws Error naming the path unless it ends in .glb, its folder exists and it is not a
// folder. export_gltf_with_lightmap checks it again; callers run it before loading anything.
void check_export_output(const std::filesystem::path& glb);
// Throws Error for a tone name other than none and lrp97, or a negative or non-finite range.
void check_export_options(const LightmapExportOptions& options);

// The irradiance map E/π of a set (see the top of this file); `description` receives what it
// was made of.
Image lightmap_irradiance(const baked::LightmapSet& set, std::string* description = nullptr);
// RGBA bytes of `image` (RGB) in RGBM with range `range`, negative values taken as 0.
std::vector<uint8_t> encode_rgbm_image(const Image& image, float range);

// Applies `set` to `scene` (Error, scene unchanged, when it was baked for another scene),
// then writes OUT.glb and OUT.lightmap.exr as described above.
LightmapExportResult export_gltf_with_lightmap(Scene& scene, const baked::LightmapSet& set,
                                               const std::filesystem::path& glb,
                                               const LightmapExportOptions& options = {});

}  // namespace illum::exporter
