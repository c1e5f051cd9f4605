// Float images (linear values, interleaved channels, row 0 at the top) and their files:
// PNG/JPEG (8-bit sRGB, via stb), Radiance HDR (via stb), OpenEXR (half or float).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "illum/core/color.h"
#include "illum/core/error.h"

namespace illum {

class Image {
 public:
  Image() = default;
  Image(int width, int height, int channels, float fill = 0.0f);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  bool empty() const { return data_.empty(); }
  size_t pixel_count() const { return static_cast<size_t>(width_) * height_; }

  float* pixel(int x, int y) { return &data_[index(x, y)]; }
  const float* pixel(int x, int y) const { return &data_[index(x, y)]; }
  // RGB of a pixel (grey images replicate channel 0). Alpha, if any, is ignored.
  Color rgb(int x, int y) const;
  void set_rgb(int x, int y, const Color& c);  // alpha, if any, set to 1

  // Bilinear lookup with wrap-around (textures) at uv in [0,1)^2, v = 0 at the top row.
  Color sample_bilinear(float u, float v) const;

  std::vector<float>& data() { return data_; }
  const std::vector<float>& data() const { return data_; }

 private:
  size_t index(int x, int y) const { return (static_cast<size_t>(y) * width_ + x) * channels_; }
  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> data_;
};

// Alpha is the last channel of 2- and 4-channel images; it is never sRGB-encoded.
inline bool is_alpha_channel(int c, int channels) {
  return (channels == 2 || channels == 4) && c == channels - 1;
}

enum class ImageFormat { kPng, kJpeg, kHdr, kExr };

// The format implied by a file name's extension (.png .jpg .jpeg .hdr .exr, any case);
// throws Error naming the path for anything else.
ImageFormat image_format_from_path(const std::string& path);

struct ImageWriteOptions {
  bool srgb = true;       // 8-bit formats: encode linear values to sRGB
  float exposure = 1.0f;  // multiply before encoding (8-bit formats only)
  bool exr_half = true;   // EXR: half floats (false: 32-bit floats)
  int jpeg_quality = 95;
};

// What an image file may declare before illum refuses it (the reader checks these, and each
// format's declared size against the bytes that hold it, before any decoder allocates; rules
// and reasons in src/illum/core/README.md). 2^28 pixels is a 16384² image (4 GiB as float
// RGBA), twice a 16k × 8k environment map.
inline constexpr int64_t kMaxDecodedImageSide = int64_t{1} << 16;
inline constexpr int64_t kMaxDecodedImagePixels = int64_t{1} << 28;

// Reads any supported format. 8-bit files are decoded to linear when `srgb` is true
// (colour textures), kept as value/255 otherwise (normal, roughness maps). The format is
// taken from the file's first bytes (the extension must still be one of the four). Throws
// Error naming the path on a missing, truncated, malformed or oversized file, and on a NaN or
// infinite value in a float (HDR/EXR) image (naming the texel).
Image read_image(const std::string& path, bool srgb = true);

// The same decoder over bytes in memory (images embedded in a glTF/GLB); `name` is what
// messages call the image ("scene.glb: images[2]"). Same checks and errors as read_image.
Image decode_image(std::span<const uint8_t> bytes, const std::string& name, bool srgb = true);

// Writes to `path` through a temporary file in the same folder and renames on success,
// so a failed write leaves no partial file. Throws Error naming the path (e.g. missing
// folder) on failure.
void write_image(const std::string& path, const Image& image,
                 const ImageWriteOptions& options = {});

}  // namespace illum
