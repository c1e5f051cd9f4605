// Internal to core: structural checks of image files before a decoder (stb, OpenEXR) sees
// them. Each walks the file's own structure (PNG chunks, JPEG markers and scans, Radiance
// scanlines, EXR header and chunk table) over the bytes in memory, and throws Error naming
// the file when a count, length or offset points past the bytes that exist, when the
// declared size could not be held by the bytes given (each format's own maximum
// compression ratio), or when the size is outside kMaxDecodedImageSide/Pixels. The rules and
// the reasons for each bound are in src/illum/core/README.md.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "illum/core/image.h"

namespace illum::image_checks {

// The format a file's first bytes announce; nullopt for anything else.
std::optional<ImageFormat> sniff_format(std::span<const uint8_t> bytes);

struct PngInfo {
  int width = 0, height = 0;
};
PngInfo check_png(std::span<const uint8_t> bytes, const std::string& name);

struct JpegInfo {
  int width = 0, height = 0;
  int scans = 0;
};
// Refuses more scans than this: stb decodes each scan over all of its blocks, so scans ×
// blocks is the decoding time; libjpeg's own progressive files have 6 (grey) or 10 (colour).
inline constexpr int kMaxJpegScans = 256;
JpegInfo check_jpeg(std::span<const uint8_t> bytes, const std::string& name);

struct HdrInfo {
  int width = 0, height = 0;
};
HdrInfo check_hdr(std::span<const uint8_t> bytes, const std::string& name);

struct ExrChannel {
  std::string name;
  int pixel_type = 0;  // 0 uint, 1 half, 2 float (OpenEXR's PixelType)
};
struct ExrInfo {
  int min_x = 0, min_y = 0;  // data window origin
  int width = 0, height = 0;
  std::vector<ExrChannel> channels;  // as listed in the file (sorted by name)
};
ExrInfo check_exr(std::span<const uint8_t> bytes, const std::string& name);

}  // namespace illum::image_checks
