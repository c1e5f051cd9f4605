#include "illum/export/lightmap_export.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/hdr_encoding.h"
#include "illum/core/histogram_tone.h"
#include "illum/core/sh.h"

namespace illum::exporter {

namespace fs = std::filesystem;

namespace {

// A hidden name beside `path` for writing it (same folder: the rename cannot cross devices).
fs::path temporary_beside(const fs::path& path, const std::string& suffix) {
  return path.parent_path() /
         fmt::format(".{}.tmp-{}{}", path.filename().string(), ::getpid(), suffix);
}

void write_bytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  // Checked to the last byte (core/file_write.h): a full disk is one line with the reason.
  write_file_atomically(path.string(), bytes);
}

}  // namespace

fs::path lightmap_exr_path(const fs::path& glb) {
  fs::path exr = glb;
  exr.replace_extension(".lightmap.exr");
  return exr;
}

void check_export_output(const fs::path& glb) {
  std::string extension = glb.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".glb")
    throw Error(
        fmt::format("{}: the export is a binary glTF: give a .glb file name", glb.string()));
  const fs::path parent = glb.parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw Error(
        fmt::format("{}: output folder '{}' does not exist", glb.string(), parent.string()));
  if (fs::is_directory(glb)) throw Error(fmt::format("{}: is a folder", glb.string()));
  if (fs::is_directory(lightmap_exr_path(glb)))
    throw Error(fmt::format("{}: is a folder", lightmap_exr_path(glb).string()));
}

void check_export_options(const LightmapExportOptions& options) {
  if (options.tone != "none" && options.tone != "lrp97")
    throw Error(fmt::format("--tone '{}' is not one of none, lrp97", options.tone));
  if (!(options.rgbm_range >= 0.0f && std::isfinite(options.rgbm_range)))
    throw Error(
        fmt::format("--rgbm-range {} must be ≥ 0 and finite (0: automatic)", options.rgbm_range));
}

Image lightmap_irradiance(const baked::LightmapSet& set, std::string* description) {
  ILLUM_CHECK(!set.layers.empty(), "light-map set without layers");
  const Image& first = set.layers[0];
  Image out(first.width(), first.height(), 3);
  std::string what;
  if (set.basis == "plain") {
    what = "layer0 (plain: E/π)";
    out = first;
  } else if (set.basis == "rnm") {
    // At the unperturbed normal (0, 0, 1) every RNM basis vector has n·b = 1/√3, so the
    // renderer's normalised squared weights are 1/3 each.
    what = "mean of the 3 RNM layers (E/π at the normal)";
    if (set.layers.size() != 3)
      throw Error(
          fmt::format("light-map set: basis rnm needs 3 layers, not {}", set.layers.size()));
    for (size_t k = 0; k < out.data().size(); ++k)
      out.data()[k] =
          (set.layers[0].data()[k] + set.layers[1].data()[k] + set.layers[2].data()[k]) / 3.0f;
  } else if (set.basis == "dominant") {
    // Layers: ambient A, directional colour C, dominant direction d (tangent space); the
    // renderer shows E/π(n) = A + C·max(0, n·d), at the unperturbed normal n = z.
    what = "dominant: A + C·max(0, d_z) (E/π at the normal)";
    if (set.layers.size() != 3)
      throw Error(
          fmt::format("light-map set: basis dominant needs 3 layers, not {}", set.layers.size()));
    const Image &ambient = set.layers[0], &colour = set.layers[1], &direction = set.layers[2];
    for (int y = 0; y < out.height(); ++y)
      for (int x = 0; x < out.width(); ++x)
        out.set_rgb(x, y,
                    ambient.rgb(x, y) + colour.rgb(x, y) * std::max(0.0f, direction.rgb(x, y).b));
  } else if (set.basis == "sh") {
    // E(n)/π = Σ (Λ_l/π) c_lm Y_lm(n) with the clamped-cosine factors Λ_0 = π, Λ_1 = 2π/3;
    // at n = z only Y00 and Y10 = kY1 are non-zero (layers: Y00, Y1−1, Y10, Y11).
    what = "SH-L1 irradiance at the normal (c0·Y00 + 2/3·c_z·Y1, E/π, clamped at 0)";
    if (set.layers.size() != 4)
      throw Error(fmt::format("light-map set: basis sh needs 4 layers, not {}", set.layers.size()));
    const std::vector<double> factors = sh::clamped_cosine_factors(2);
    const float w0 = static_cast<float>(factors[0] / kPi * sh::kY00);
    const float w1 = static_cast<float>(factors[1] / kPi * sh::kY1);
    for (size_t k = 0; k < out.data().size(); ++k)
      out.data()[k] = std::max(0.0f, w0 * set.layers[0].data()[k] + w1 * set.layers[2].data()[k]);
  } else {
    throw Error(
        fmt::format("light-map set: basis '{}' cannot be exported (plain, rnm, sh, "
                    "dominant)",
                    set.basis));
  }
  if (description != nullptr) *description = what;
  return out;
}

std::vector<uint8_t> encode_rgbm_image(const Image& image, float range) {
  ILLUM_CHECK(image.channels() == 3, "RGBM of a {}-channel image", image.channels());
  std::vector<uint8_t> bytes(image.pixel_count() * 4);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const std::array<uint8_t, 4> rgbm = encode_rgbm(image.rgb(x, y), range);  // clamps < 0
      std::copy(rgbm.begin(), rgbm.end(),
                bytes.begin() + 4 * (static_cast<size_t>(y) * image.width() + x));
    }
  return bytes;
}

LightmapExportResult export_gltf_with_lightmap(Scene& scene, const baked::LightmapSet& set,
                                               const fs::path& glb,
                                               const LightmapExportOptions& options) {
  check_export_output(glb);
  check_export_options(options);
  baked::apply_lightmap_set(scene, set);  // refuses another scene's set, scene unchanged

  LightmapExportResult result;
  result.glb = glb;
  result.exr = lightmap_exr_path(glb);
  const Image irradiance = lightmap_irradiance(set, &result.layer);
  result.width = irradiance.width();
  result.height = irradiance.height();

  const bool tone = options.tone == "lrp97";
  const Image encoded = tone ? histogram_tone_mapped(irradiance) : irradiance;
  float range = options.rgbm_range;
  if (range == 0.0f) {
    range = 1.0f;  // a black map (or tone-mapped values, in [0, 1])
    if (!tone) {
      float largest = 0.0f;
      for (float v : encoded.data()) largest = std::max(largest, v);
      if (largest > 0.0f) range = largest;
    }
  }
  result.rgbm_range = range;

  GltfLightmapTexture texture;
  texture.range = range;
  texture.tone = options.tone;
  texture.basis = set.basis;
  texture.layer = result.layer;
  texture.png = encode_png(encode_rgbm_image(encoded, range), encoded.width(), encoded.height(), 4);
  result.png_bytes = texture.png.size();
  // Which lights the map holds: the rule prepare_lightmap_display applies when showing it.
  for (const Light& light : scene.lights)
    texture.light_baked.push_back(set.content == "all" || light.type == LightType::kArea ||
                                  light.type == LightType::kEnvironment);
  const std::vector<uint8_t> bytes = scene_to_glb(scene, &texture, &result.gltf);
  result.glb_bytes = bytes.size();

  const fs::path glb_tmp = temporary_beside(glb, ".glb");
  const fs::path exr_tmp = temporary_beside(result.exr, ".exr");
  try {
    write_bytes(glb_tmp, bytes);
    ImageWriteOptions exr;
    exr.exr_half = false;  // the folder's values exactly (its halves are floats too)
    write_image(exr_tmp.string(), irradiance, exr);
    fs::rename(exr_tmp, result.exr);
    try {
      fs::rename(glb_tmp, glb);
    } catch (...) {
      std::error_code ignored;
      fs::remove(result.exr, ignored);
      throw;
    }
  } catch (const fs::filesystem_error& e) {
    std::error_code ignored;
    fs::remove(glb_tmp, ignored);
    fs::remove(exr_tmp, ignored);
    throw Error(fmt::format("{}: {}", glb.string(), e.code().message()));
  } catch (...) {
    std::error_code ignored;
    fs::remove(glb_tmp, ignored);
    fs::remove(exr_tmp, ignored);
    throw;
  }
  return result;
}

}  // namespace illum::exporter
