// Float images (linear values, interleaved channels, row 0 at the top) and their files:
// PNG/JPEG (8-bit sRGB, via stb), Radiance HDR (via stb), OpenEXR (half or float).
#pragma once

#include <cmath>
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

  float* pixel(int x, int y) {
    drop_bytes();
    return &data_[index(x, y)];
  }
  const float* pixel(int x, int y) const { return &data_[index(x, y)]; }
  // RGB of a pixel (grey images replicate channel 0). Alpha, if any, is ignored.
  Color rgb(int x, int y) const;
  void set_rgb(int x, int y, const Color& c);  // alpha, if any, set to 1

  // Bilinear lookup with wrap-around (textures) at uv in [0,1)^2, v = 0 at the top row.
  // Any finite uv tiles; a non-finite coordinate reads as 0. Inline: it is on the path
  // tracer's hit path (albedo and normal maps at every vertex). Reads the 8-bit copy when
  // the image has one (keep_bytes): the same values, a quarter of the memory to fetch.
  Color sample_bilinear(float u, float v) const {
    ILLUM_CHECK(!empty(), "bilinear lookup in an empty image");
    if (bytes_.empty())
      return filter(
          data_.data(), [](float x) { return x; }, u, v);
    const float* table = byte_values_;
    return filter(
        bytes_.data(), [table](uint8_t b) { return table[b]; }, u, v);
  }

  // Keeps `bytes` (one per value, interleaved like data()) beside the floats, where every
  // colour (non-alpha) value equals byte_values[byte] exactly; byte_values must outlive the
  // image. For 8-bit files the decoder does this, so texture lookups read a quarter of the
  // memory and return the same floats. Any non-const access to the pixels drops the copy.
  void keep_bytes(std::vector<uint8_t> bytes, const float* byte_values);
  bool has_bytes() const { return !bytes_.empty(); }

  std::vector<float>& data() {
    drop_bytes();
    return data_;
  }
  const std::vector<float>& data() const { return data_; }

 private:
  size_t index(int x, int y) const { return (static_cast<size_t>(y) * width_ + x) * channels_; }
  void drop_bytes() {
    if (!bytes_.empty()) bytes_ = {};
  }
  // The bilinear filter over texels stored as T, each value read through value(T).
  template <typename T, typename Value>
  Color filter(const T* d, Value&& value, float u, float v) const {
    int x0, x1, y0, y1;
    float tx, ty;
    wrap_texel(u, width_, &x0, &x1, &tx);
    wrap_texel(v, height_, &y0, &y1, &ty);
    const size_t row0 = static_cast<size_t>(y0) * width_, row1 = static_cast<size_t>(y1) * width_;
    const size_t c = static_cast<size_t>(channels_);
    const T* p00 = d + (row0 + x0) * c;
    const T* p10 = d + (row0 + x1) * c;
    const T* p01 = d + (row1 + x0) * c;
    const T* p11 = d + (row1 + x1) * c;
    const auto texel = [&value, rgb = channels_ >= 3](const T* p) {
      return rgb ? Color(value(p[0]), value(p[1]), value(p[2])) : Color(value(p[0]));
    };
    return (1.0f - ty) * ((1.0f - tx) * texel(p00) + tx * texel(p10)) +
           ty * ((1.0f - tx) * texel(p01) + tx * texel(p11));
  }
  // The two texels around coordinate `t` (texel centres at (i + 0.5) / n) and the weight of
  // the second. `t` is first reduced to [0, 1], where t − floor(t) is exact, so the texel
  // index needs no fmod and cannot overflow an int; index −1 and n wrap to n − 1 and 0.
  static void wrap_texel(float t, int n, int* i0, int* i1, float* frac) {
    float f = t - std::floor(t);
    if (!(f >= 0.0f && f <= 1.0f)) f = 0.0f;  // NaN or infinite coordinate
    const float x = f * static_cast<float>(n) - 0.5f;
    const float fx = std::floor(x);
    *frac = x - fx;
    int i = static_cast<int>(fx);  // −1 … n − 1
    if (i < 0) i += n;
    *i0 = i;
    *i1 = i + 1 == n ? 0 : i + 1;
  }
  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> data_;
  std::vector<uint8_t> bytes_;          // keep_bytes(); empty when the image has no copy
  const float* byte_values_ = nullptr;  // value of each byte (colour channels)
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
