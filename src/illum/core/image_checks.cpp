#include "illum/core/image_checks.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include <fmt/format.h>

#include "illum/core/error.h"

namespace illum::image_checks {

namespace {

// Bounds-checked reading over a file's bytes; every failure names the file.
class Cursor {
 public:
  Cursor(std::span<const uint8_t> data, const std::string& name) : data_(data), name_(name) {}

  size_t size() const { return data_.size(); }
  size_t pos() const { return pos_; }
  size_t left() const { return data_.size() - pos_; }
  bool has(uint64_t n) const { return n <= left(); }
  void seek(size_t pos) { pos_ = std::min(pos, data_.size()); }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fmt::format("{}: {}", name_, what));
  }
  void need(uint64_t n, std::string_view what) const {
    if (!has(n))
      fail(fmt::format("truncated: {} needs {} bytes at offset {}, the file has {}", what, n, pos_,
                       data_.size()));
  }
  void skip(uint64_t n, std::string_view what) {
    need(n, what);
    pos_ += static_cast<size_t>(n);
  }
  uint8_t u8(std::string_view what) {
    need(1, what);
    return data_[pos_++];
  }
  uint8_t peek() const { return data_[pos_]; }  // the caller checked has(1)
  uint16_t u16be(std::string_view what) {
    need(2, what);
    const uint16_t v = static_cast<uint16_t>((data_[pos_] << 8) | data_[pos_ + 1]);
    pos_ += 2;
    return v;
  }
  uint32_t u32be(std::string_view what) {
    need(4, what);
    const uint32_t v = (uint32_t{data_[pos_]} << 24) | (uint32_t{data_[pos_ + 1]} << 16) |
                       (uint32_t{data_[pos_ + 2]} << 8) | uint32_t{data_[pos_ + 3]};
    pos_ += 4;
    return v;
  }
  uint32_t u32le(std::string_view what) {
    need(4, what);
    const uint32_t v = uint32_t{data_[pos_]} | (uint32_t{data_[pos_ + 1]} << 8) |
                       (uint32_t{data_[pos_ + 2]} << 16) | (uint32_t{data_[pos_ + 3]} << 24);
    pos_ += 4;
    return v;
  }
  int32_t i32le(std::string_view what) { return static_cast<int32_t>(u32le(what)); }
  uint64_t u64le(std::string_view what) {
    const uint64_t lo = u32le(what);
    return lo | (uint64_t{u32le(what)} << 32);
  }

 private:
  std::span<const uint8_t> data_;
  const std::string& name_;
  size_t pos_ = 0;
};

void check_dimensions(const Cursor& c, int64_t w, int64_t h) {
  if (w < 1 || h < 1)
    c.fail(fmt::format("declares a {}×{} image (an image needs at least one pixel)", w, h));
  if (w > kMaxDecodedImageSide || h > kMaxDecodedImageSide || w * h > kMaxDecodedImagePixels)
    c.fail(
        fmt::format("declares a {}×{} image, larger than illum reads (at most {} pixels a side "
                    "and {} in all)",
                    w, h, kMaxDecodedImageSide, kMaxDecodedImagePixels));
}

uint64_t ceil_div(uint64_t a, uint64_t b) {
  return (a + b - 1) / b;
}

bool starts_with(std::span<const uint8_t> bytes, std::string_view prefix) {
  return bytes.size() >= prefix.size() &&
         std::memcmp(bytes.data(), prefix.data(), prefix.size()) == 0;
}

// ---------------------------------------------------------------------------------------
// PNG: the IHDR chunk, then every chunk's length against the bytes left, up to IEND.

// Deflate's largest expansion: one 258-byte match per 2 bits of a block's Huffman codes,
// 258 × 4 = 1032 bytes out per byte in (zlib's technical notes). No valid zlib stream
// inflates to more than 1032 × its own length.
constexpr uint64_t kDeflateMaxRatio = 1032;

int png_channels(const Cursor& c, int colour_type, int depth) {
  auto depth_in = [&](std::initializer_list<int> allowed) {
    if (std::find(allowed.begin(), allowed.end(), depth) == allowed.end())
      c.fail(fmt::format("malformed PNG: bit depth {} is not allowed for colour type {}", depth,
                         colour_type));
  };
  switch (colour_type) {
    case 0:
      depth_in({1, 2, 4, 8, 16});
      return 1;
    case 2:
      depth_in({8, 16});
      return 3;
    case 3:
      depth_in({1, 2, 4, 8});
      return 1;
    case 4:
      depth_in({8, 16});
      return 2;
    case 6:
      depth_in({8, 16});
      return 4;
    default:
      c.fail(fmt::format("malformed PNG: unknown colour type {}", colour_type));
  }
}

}  // namespace

std::optional<ImageFormat> sniff_format(std::span<const uint8_t> bytes) {
  if (starts_with(bytes, "\x89PNG\r\n\x1a\n")) return ImageFormat::kPng;
  if (starts_with(bytes, "\xff\xd8\xff")) return ImageFormat::kJpeg;
  // The two first lines stb's Radiance reader accepts.
  if (starts_with(bytes, "#?RADIANCE\n") || starts_with(bytes, "#?RGBE\n"))
    return ImageFormat::kHdr;
  if (starts_with(bytes, std::string_view("\x76\x2f\x31\x01", 4))) return ImageFormat::kExr;
  return std::nullopt;
}

PngInfo check_png(std::span<const uint8_t> bytes, const std::string& name) {
  Cursor c(bytes, name);
  c.skip(8, "the PNG signature");
  const uint32_t ihdr_length = c.u32be("the IHDR chunk");
  if (c.u32be("the IHDR chunk") != 0x49484452u || ihdr_length != 13)
    c.fail("malformed PNG: the first chunk is not a 13-byte IHDR");
  const uint32_t w = c.u32be("the IHDR chunk"), h = c.u32be("the IHDR chunk");
  const int depth = c.u8("the IHDR chunk"), colour_type = c.u8("the IHDR chunk");
  c.skip(3 + 4, "the IHDR chunk");  // compression, filter, interlace; CRC
  const int channels = png_channels(c, colour_type, depth);
  check_dimensions(c, w, h);

  uint64_t idat_bytes = 0;
  for (;;) {
    if (!c.has(8))
      c.fail(fmt::format("truncated PNG: no IEND chunk before the end ({} bytes)", c.size()));
    const size_t at = c.pos();
    const uint32_t length = c.u32be("a chunk header");
    const uint32_t type = c.u32be("a chunk header");
    if (length > 0x7fffffffu)
      c.fail(fmt::format("malformed PNG: chunk at offset {} declares {} bytes (over 2^31 − 1)", at,
                         length));
    if (!c.has(uint64_t{length} + 4))
      c.fail(fmt::format("truncated PNG: the chunk at offset {} declares {} bytes, the file has {}",
                         at, length, c.size()));
    c.skip(uint64_t{length} + 4, "a chunk");
    if (type == 0x49444154u) idat_bytes += length;  // IDAT
    if (type == 0x49454e44u) break;                 // IEND
  }
  if (idat_bytes == 0) c.fail("malformed PNG: no image data (IDAT chunk)");
  // Every pixel's bits are in the inflated stream (plus filter bytes), so the stream is at
  // least this long; its compressed form is at most the IDAT bytes.
  const uint64_t raw_bytes = ceil_div(uint64_t{w} * h * static_cast<uint64_t>(channels * depth), 8);
  if (raw_bytes > kDeflateMaxRatio * idat_bytes)
    c.fail(
        fmt::format("declares {}×{} pixels ({} bytes inflated), more than its {} bytes of "
                    "compressed data can hold (deflate inflates at most {}:1)",
                    w, h, raw_bytes, idat_bytes, kDeflateMaxRatio));
  return {static_cast<int>(w), static_cast<int>(h)};
}

// ---------------------------------------------------------------------------------------
// JPEG: markers from SOI to EOI, the frame header, and the entropy-coded bytes of each scan.

// A DHT segment holds tables of 1 + 16 + n bytes, n the sum of the 16 code-length counts.
// Debian's stb copies the n symbols into a 256-entry array and fills a 257-entry code-size
// list without checking n (stb_image.h stbi__build_huffman), so n > 256 writes past both.
// `defined` gains bit (class·4 + id) for each table.
void check_jpeg_huffman_tables(Cursor& c, size_t segment_end, unsigned& defined) {
  while (c.pos() < segment_end) {
    const size_t at = c.pos();
    if (segment_end - at < 17)
      c.fail(fmt::format("malformed JPEG: Huffman table at offset {} is cut short", at));
    const uint8_t cls_id = c.u8("a Huffman table");
    if ((cls_id >> 4) > 1 || (cls_id & 15) > 3)
      c.fail(fmt::format("malformed JPEG: Huffman table at offset {} has class {} and id {}", at,
                         cls_id >> 4, cls_id & 15));
    size_t symbols = 0;
    for (int i = 0; i < 16; ++i) symbols += c.u8("a Huffman table");
    if (symbols > 256)
      c.fail(
          fmt::format("malformed JPEG: Huffman table at offset {} declares {} codes (at most 256)",
                      at, symbols));
    if (symbols > segment_end - c.pos())
      c.fail(fmt::format("malformed JPEG: Huffman table at offset {} runs past its segment", at));
    c.skip(symbols, "a Huffman table");
    defined |= 1u << ((cls_id >> 4) * 4 + (cls_id & 15));
  }
}

// A DQT segment holds tables of 1 + 64 or 1 + 128 bytes (8- or 16-bit entries); `defined`
// gains bit id for each.
void check_jpeg_quantization_tables(Cursor& c, size_t segment_end, unsigned& defined) {
  while (c.pos() < segment_end) {
    const size_t at = c.pos();
    const uint8_t precision_id = c.u8("a quantization table");
    if ((precision_id >> 4) > 1 || (precision_id & 15) > 3)
      c.fail(
          fmt::format("malformed JPEG: quantization table at offset {} has precision {} and id {}",
                      at, precision_id >> 4, precision_id & 15));
    const size_t entries = (precision_id >> 4) ? 128 : 64;
    if (entries > segment_end - c.pos())
      c.fail(
          fmt::format("malformed JPEG: quantization table at offset {} runs past its segment", at));
    c.skip(entries, "a quantization table");
    defined |= 1u << (precision_id & 15);
  }
}

// Debian's stb keeps its quantization and Huffman tables in an uninitialised allocation and
// decodes with whichever a component names, defined or not: a file that never defines them
// decodes heap garbage (found by the fuzzer: a UBSan overflow that depended on the inputs
// before it). So every table a scan uses must have been defined before the scan.
void check_jpeg_scan_tables(Cursor& c, size_t segment_end, bool progressive,
                            const std::array<int, 256>& frame_table_of, unsigned quantization,
                            unsigned huffman) {
  const size_t at = c.pos() - 4;
  if (segment_end - c.pos() < 1)
    c.fail(fmt::format("malformed JPEG: scan header at offset {} is empty", at));
  const int count = c.u8("a scan header");
  if (count < 1 || count > 4 || segment_end - c.pos() != 2u * count + 3)
    c.fail(fmt::format("malformed JPEG: scan header at offset {} has {} components in {} bytes", at,
                       count, segment_end - at - 4));
  std::array<uint8_t, 4> ids{}, tables{};
  for (int i = 0; i < count; ++i) {
    ids[i] = c.u8("a scan header");
    tables[i] = c.u8("a scan header");
  }
  const int spectral_start = c.u8("a scan header");
  c.skip(1, "");
  const int approximation_high = c.u8("a scan header") >> 4;
  for (int i = 0; i < count; ++i) {
    const int quant = frame_table_of[ids[i]];
    if (quant < 0)
      c.fail(
          fmt::format("malformed JPEG: the scan at offset {} names component {}, which the "
                      "frame does not have",
                      at, ids[i]));
    if (!(quantization & (1u << quant)))
      c.fail(
          fmt::format("malformed JPEG: component {} uses quantization table {}, which no DQT "
                      "segment before the scan at offset {} defines",
                      ids[i], quant, at));
    const bool uses_dc = !progressive || (spectral_start == 0 && approximation_high == 0);
    const bool uses_ac = !progressive || spectral_start > 0;
    const int dc = tables[i] >> 4, ac = tables[i] & 15;
    if (uses_dc && (dc > 3 || !(huffman & (1u << dc))))
      c.fail(
          fmt::format("malformed JPEG: the scan at offset {} uses DC Huffman table {}, which no "
                      "DHT segment before it defines",
                      at, dc));
    if (uses_ac && (ac > 3 || !(huffman & (1u << (4 + ac)))))
      c.fail(
          fmt::format("malformed JPEG: the scan at offset {} uses AC Huffman table {}, which no "
                      "DHT segment before it defines",
                      at, ac));
  }
}

JpegInfo check_jpeg(std::span<const uint8_t> bytes, const std::string& name) {
  Cursor c(bytes, name);
  c.skip(2, "the start-of-image marker");
  JpegInfo info;
  bool have_frame = false, progressive = false;
  unsigned quantization_tables = 0, huffman_tables = 0;  // bit sets of the defined ids
  std::array<int, 256> table_of_component;               // the frame's Tq per component id
  table_of_component.fill(-1);
  uint64_t entropy_bytes = 0;
  for (;;) {
    // Like stb, skip anything between segments up to the next 0xFF, then fill bytes.
    while (c.has(1) && c.peek() != 0xff) c.skip(1, "");
    while (c.has(2) && c.peek() == 0xff && bytes[c.pos() + 1] == 0xff) c.skip(1, "");
    if (!c.has(2)) c.fail("truncated JPEG: no end-of-image marker");
    c.skip(1, "");
    const uint8_t marker = c.u8("a marker");
    if (marker == 0xd9) break;                                           // EOI
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) continue;  // no length
    const size_t at = c.pos() - 2;
    const uint16_t length = c.u16be("a marker segment");
    if (length < 2)
      c.fail(fmt::format("malformed JPEG: segment at offset {} has length {}", at, length));
    c.need(length - 2u, "a marker segment");
    const size_t segment_end = c.pos() + length - 2u;
    const bool sof =
        marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (sof) {
      if (marker > 0xc2)
        c.fail(
            fmt::format("unsupported JPEG coding (SOF{}); illum reads baseline and progressive "
                        "Huffman-coded JPEGs",
                        marker - 0xc0));
      if (have_frame) c.fail("malformed JPEG: two frame headers");
      if (length < 8) c.fail("malformed JPEG: frame header too short");
      c.skip(1, "the frame header");  // sample precision
      info.height = c.u16be("the frame header");
      info.width = c.u16be("the frame header");
      check_dimensions(c, info.width, info.height);
      const int components = c.u8("the frame header");
      if (components < 1 || length != 8 + 3 * components)
        c.fail(fmt::format("malformed JPEG: frame header of {} bytes for {} components", length,
                           components));
      for (int i = 0; i < components; ++i) {
        const uint8_t id = c.u8("the frame header");
        c.skip(1, "");  // sampling factors
        const uint8_t table = c.u8("the frame header");
        if (table > 3)
          c.fail(
              fmt::format("malformed JPEG: component {} names quantization table {}", id, table));
        table_of_component[id] = table;
      }
      have_frame = true;
      progressive = marker == 0xc2;
    }
    if (marker == 0xc4) check_jpeg_huffman_tables(c, segment_end, huffman_tables);
    if (marker == 0xdb) check_jpeg_quantization_tables(c, segment_end, quantization_tables);
    if (marker == 0xda) {
      if (!have_frame) c.fail("malformed JPEG: a scan before the frame header");
      check_jpeg_scan_tables(c, segment_end, progressive, table_of_component, quantization_tables,
                             huffman_tables);
    }
    c.seek(segment_end);
    if (marker != 0xda) continue;  // SOS: the entropy-coded data follows its header
    if (++info.scans > kMaxJpegScans)
      c.fail(fmt::format("JPEG has more than {} scans (decoding time grows with scans × pixels)",
                         kMaxJpegScans));
    for (;;) {
      if (!c.has(2)) c.fail("truncated JPEG: the file ends inside a scan");
      if (c.peek() != 0xff) {
        c.skip(1, "");
        ++entropy_bytes;
        continue;
      }
      const uint8_t next = bytes[c.pos() + 1];
      if (next == 0x00 || (next >= 0xd0 && next <= 0xd7)) {  // stuffed 0xFF, restart marker
        c.skip(2, "");
        entropy_bytes += next == 0x00;
        continue;
      }
      break;  // a marker ends the scan
    }
  }
  if (!have_frame) c.fail("malformed JPEG: no frame header");
  // Every 8×8 block of the full-resolution component is coded in at least one bit (the
  // Huffman code of its DC coefficient in its first scan).
  const uint64_t blocks = ceil_div(static_cast<uint64_t>(info.width), 8) *
                          ceil_div(static_cast<uint64_t>(info.height), 8);
  if (blocks > 8 * entropy_bytes)
    c.fail(
        fmt::format("declares {}×{} pixels ({} blocks of 8×8), more than its {} bytes of coded "
                    "data can hold (at least one bit per block)",
                    info.width, info.height, blocks, entropy_bytes));
  return info;
}

// ---------------------------------------------------------------------------------------
// Radiance HDR: the header exactly as stb_image parses it, then every scanline.

namespace {

// stb_image's stbi__hdr_gettoken: a line up to '\n' or the end, at most 1023 characters (the
// rest of a longer line is skipped).
std::string hdr_line(Cursor& c) {
  std::string line;
  while (c.has(1)) {
    const char ch = static_cast<char>(c.u8(""));
    if (ch == '\n') return line;
    line.push_back(ch);
    if (line.size() == 1023) {
      while (c.has(1) && c.u8("") != '\n') {
      }
      return line;
    }
  }
  return line;
}

}  // namespace

HdrInfo check_hdr(std::span<const uint8_t> bytes, const std::string& name) {
  Cursor c(bytes, name);
  const std::string magic = hdr_line(c);
  if (magic != "#?RADIANCE" && magic != "#?RGBE") c.fail("malformed Radiance HDR: bad first line");
  bool rgbe = false;
  for (;;) {
    const std::string line = hdr_line(c);
    if (line.empty()) break;
    if (line == "FORMAT=32-bit_rle_rgbe") rgbe = true;
  }
  if (!rgbe) c.fail("unsupported Radiance HDR: no FORMAT=32-bit_rle_rgbe line");
  // "-Y height +X width", parsed with strtol as stb does, so both read the same numbers.
  const std::string size_line = hdr_line(c);
  const char* p = size_line.c_str();
  if (std::strncmp(p, "-Y ", 3) != 0)
    c.fail(fmt::format("unsupported Radiance HDR layout '{}' (illum reads -Y H +X W)",
                       size_line.substr(0, 40)));
  char* end = nullptr;
  const long h = std::strtol(p + 3, &end, 10);
  p = end;
  while (*p == ' ') ++p;
  if (std::strncmp(p, "+X ", 3) != 0)
    c.fail(fmt::format("unsupported Radiance HDR layout '{}' (illum reads -Y H +X W)",
                       size_line.substr(0, 40)));
  const long w = std::strtol(p + 3, nullptr, 10);
  check_dimensions(c, w, h);
  const uint64_t pixels = static_cast<uint64_t>(w) * static_cast<uint64_t>(h);

  // stb reads scanlines flat (4 bytes a pixel) when the width is outside [8, 32768) or the
  // first scanline does not start with the run-length marker 2 2; at the end of the data it
  // reads zeros without a word, and a zero run count then never advances (an endless loop).
  auto need_flat = [&](uint64_t count) {
    if (!c.has(4 * count))
      c.fail(
          fmt::format("truncated Radiance HDR: {}×{} pixels stored flat need {} more bytes at "
                      "offset {}, the file has {}",
                      w, h, 4 * count, c.pos(), c.size()));
  };
  if (w < 8 || w >= 32768) {
    need_flat(pixels);
    return {static_cast<int>(w), static_cast<int>(h)};
  }
  for (long y = 0; y < h; ++y) {
    const size_t line_start = c.pos();
    c.need(4, fmt::format("scanline {}", y));
    const uint8_t c1 = c.u8(""), c2 = c.u8(""), len_hi = c.u8(""), len_lo = c.u8("");
    if (c1 != 2 || c2 != 2 || (len_hi & 0x80)) {
      // Not run-length encoded. stb then decodes the rest of the file flat, starting over at
      // pixel 1 of row 0, which is right only when this is the first scanline.
      if (y > 0)
        c.fail(
            fmt::format("malformed Radiance HDR: scanline {} (offset {}) is not run-length "
                        "encoded but those before it are",
                        y, line_start));
      need_flat(pixels - 1);
      return {static_cast<int>(w), static_cast<int>(h)};
    }
    if (((len_hi << 8) | len_lo) != w)
      c.fail(fmt::format("malformed Radiance HDR: scanline {} declares width {}, the image {}", y,
                         (len_hi << 8) | len_lo, w));
    for (int channel = 0; channel < 4; ++channel) {
      long x = 0;
      while (x < w) {
        const size_t at = c.pos();
        if (!c.has(1))
          c.fail(fmt::format("truncated Radiance HDR: the file ends in scanline {} of {}", y, h));
        const uint8_t count = c.u8("");
        const long run = count > 128 ? count - 128 : count;
        if (run == 0 || run > w - x)
          c.fail(
              fmt::format("malformed Radiance HDR: run of {} at offset {} (scanline {}, {} "
                          "pixels left in it)",
                          run, at, y, w - x));
        const uint64_t data = count > 128 ? 1 : static_cast<uint64_t>(run);
        if (!c.has(data))
          c.fail(fmt::format("truncated Radiance HDR: the file ends in scanline {} of {}", y, h));
        c.skip(data, "");
        x += run;
      }
    }
  }
  return {static_cast<int>(w), static_cast<int>(h)};
}

// ---------------------------------------------------------------------------------------
// OpenEXR: the header's attributes, then the chunk offset table and every chunk's own header,
// before OpenEXR allocates tables sized from the data window.

namespace {

// Lines per scanline chunk, by compression (OpenEXR's file layout).
int exr_lines_per_chunk(int compression) {
  static constexpr int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return kLines[compression];
}

// The largest uncompressed/compressed ratio a chunk of each compression can have, from how
// each codec stores its smallest output:
//   NONE 1; RLE 64 (runs of at most 127 bytes in 2 bytes); ZIPS/ZIP 1032 (deflate);
//   PIZ 410 (Huffman: a code, a run code and 8 bits, each code at least one bit, for 256
//   16-bit values: 4096 bits in 10); PXR24 1376 (24 of a float's 32 bits through deflate);
//   B44/B44A 11 (a flat 4×4 block of halves, 32 bytes, in 3); DWAA/DWAB 132096 (one DC value
//   of 2 bytes per 8×8 block of up to 4-byte samples, through deflate: 256 / 2 × 1032).
uint64_t exr_max_ratio(int compression) {
  static constexpr uint64_t kRatio[] = {1, 64, 1032, 1032, 410, 1376, 11, 11, 132096, 132096};
  return kRatio[compression];
}

int exr_level_size(int size, int level, bool round_up) {
  const int64_t b = int64_t{1} << level;
  int64_t s = size / b;
  if (round_up && s * b < size) ++s;
  return static_cast<int>(std::max<int64_t>(s, 1));
}

int exr_level_count(int size, bool round_up) {
  int levels = 0;
  while ((int64_t{1} << levels) < size) ++levels;             // ceil(log2 size)
  if (!round_up && (int64_t{1} << levels) != size) --levels;  // floor(log2 size)
  return levels + 1;
}

}  // namespace

ExrInfo check_exr(std::span<const uint8_t> bytes, const std::string& name) {
  Cursor c(bytes, name);
  c.skip(4, "the OpenEXR magic number");
  const uint32_t version = c.u32le("the version field");
  if ((version & 0xff) != 2) c.fail(fmt::format("unsupported OpenEXR version {}", version & 0xff));
  const bool tiled = version & 0x200, long_names = version & 0x400;
  if (version & 0x800) c.fail("deep OpenEXR images are not supported");
  if (version & 0x1000) c.fail("multi-part OpenEXR files are not supported");
  if (version & ~0x1fffu) c.fail(fmt::format("unknown OpenEXR version flags {:#x}", version));

  ExrInfo info;
  bool have_channels = false, have_window = false, have_compression = false, have_tiles = false;
  int compression = 0;
  int64_t max_x = 0, max_y = 0;
  uint32_t tile_w = 0, tile_h = 0;
  int level_mode = 0;
  bool round_up = false;
  const size_t max_name = long_names ? 255 : 31;
  auto read_name = [&](std::string_view what) {
    std::string s;
    for (;;) {
      const char ch = static_cast<char>(c.u8(what));
      if (ch == '\0') return s;
      if (s.size() == max_name)
        c.fail(
            fmt::format("malformed OpenEXR header: {} longer than {} characters", what, max_name));
      s.push_back(ch);
    }
  };
  for (;;) {
    const std::string attribute = read_name("an attribute name");
    if (attribute.empty()) break;  // end of the header
    const std::string type = read_name("an attribute type");
    const int32_t size = c.i32le("an attribute size");
    if (size < 0 || !c.has(static_cast<uint64_t>(size)))
      c.fail(
          fmt::format("malformed OpenEXR header: attribute '{}' declares {} bytes at offset {}, "
                      "the file has {}",
                      attribute, size, c.pos(), c.size()));
    const size_t end = c.pos() + static_cast<size_t>(size);
    auto expect_size = [&](int32_t expected) {
      if (size != expected)
        c.fail(
            fmt::format("malformed OpenEXR header: attribute '{}' of type {} has {} bytes, not "
                        "{}",
                        attribute, type, size, expected));
    };
    if (attribute == "channels" && type == "chlist") {
      for (;;) {
        const std::string channel = read_name("a channel name");
        if (channel.empty()) break;
        const int32_t pixel_type = c.i32le("a channel");
        c.skip(4, "a channel");  // pLinear, reserved
        const int32_t x_sampling = c.i32le("a channel"), y_sampling = c.i32le("a channel");
        if (pixel_type < 0 || pixel_type > 2)
          c.fail(fmt::format("malformed OpenEXR header: channel '{}' has pixel type {}", channel,
                             pixel_type));
        if (x_sampling != 1 || y_sampling != 1)
          c.fail(
              fmt::format("OpenEXR channel '{}' is subsampled ({}×{}); illum reads full-"
                          "resolution channels only",
                          channel, x_sampling, y_sampling));
        info.channels.push_back({channel, pixel_type});
      }
      if (c.pos() != end)
        c.fail("malformed OpenEXR header: the channel list does not fill its attribute");
      have_channels = true;
    } else if (attribute == "compression" && type == "compression") {
      expect_size(1);
      compression = c.u8("the compression");
      if (compression > 9) c.fail(fmt::format("unsupported OpenEXR compression {}", compression));
      have_compression = true;
    } else if (attribute == "dataWindow" && type == "box2i") {
      expect_size(16);
      info.min_x = c.i32le("the data window");
      info.min_y = c.i32le("the data window");
      max_x = c.i32le("the data window");
      max_y = c.i32le("the data window");
      have_window = true;
    } else if (attribute == "tiles" && type == "tiledesc") {
      expect_size(9);
      tile_w = c.u32le("the tile description");
      tile_h = c.u32le("the tile description");
      const uint8_t mode = c.u8("the tile description");
      level_mode = mode & 0xf;
      round_up = (mode >> 4) == 1;
      if (level_mode > 2 || (mode >> 4) > 1)
        c.fail(fmt::format("malformed OpenEXR header: tile mode {:#x}", mode));
      have_tiles = true;
    }
    if (c.pos() > end)
      c.fail(fmt::format("malformed OpenEXR header: attribute '{}' overruns its {} bytes",
                         attribute, size));
    c.seek(end);
  }
  if (!have_channels || !have_window || !have_compression)
    c.fail("malformed OpenEXR header: it needs 'channels', 'compression' and 'dataWindow'");
  if (tiled != have_tiles) c.fail("malformed OpenEXR header: tiled flag and 'tiles' disagree");
  if (info.channels.empty()) c.fail("the OpenEXR file has no channels");
  const int64_t w = max_x - info.min_x + 1, h = max_y - info.min_y + 1;
  check_dimensions(c, w, h);
  // OpenEXR computes coordinates in int: keep the window well inside.
  constexpr int64_t kCoordinateLimit = int64_t{1} << 30;
  if (std::abs(int64_t{info.min_x}) > kCoordinateLimit ||
      std::abs(int64_t{info.min_y}) > kCoordinateLimit)
    c.fail(fmt::format("OpenEXR data window starts at ({}, {}), beyond ±2^30", info.min_x,
                       info.min_y));
  info.width = static_cast<int>(w);
  info.height = static_cast<int>(h);
  uint64_t pixel_bytes = 0;
  for (const ExrChannel& ch : info.channels) pixel_bytes += ch.pixel_type == 1 ? 2 : 4;

  // The chunks: (first pixel, size in pixels) of each, in offset-table order.
  struct Chunk {
    int64_t x, y, w, h;
    int lx, ly;
  };
  std::vector<Chunk> chunks;
  auto reserve_table = [&](uint64_t count) {
    if (count > c.left() / 8)
      c.fail(
          fmt::format("truncated OpenEXR: its {} chunks need an offset table of {} bytes at "
                      "offset {}, the file has {}",
                      count, count * 8, c.pos(), c.size()));
    chunks.reserve(static_cast<size_t>(count));
  };
  if (!tiled) {
    const int lines = exr_lines_per_chunk(compression);
    reserve_table(ceil_div(static_cast<uint64_t>(h), static_cast<uint64_t>(lines)));
    for (int64_t y = 0; y < h; y += lines)
      chunks.push_back({0, y, w, std::min<int64_t>(lines, h - y), 0, 0});
  } else {
    if (tile_w < 1 || tile_h < 1 || tile_w > 0x7fffffffu || tile_h > 0x7fffffffu)
      c.fail(fmt::format("malformed OpenEXR header: {}×{} tiles", tile_w, tile_h));
    // OpenEXR allocates whole tiles; tiles larger than the image are legal but only as big as
    // this, so a tiny file cannot ask for a huge tile buffer.
    constexpr int64_t kMaxTileSideOverImage = 1024;
    if (tile_w > std::max(w, kMaxTileSideOverImage) || tile_h > std::max(h, kMaxTileSideOverImage))
      c.fail(
          fmt::format("OpenEXR tiles of {}×{} for a {}×{} image (tiles larger than the image "
                      "are refused above {} pixels a side)",
                      tile_w, tile_h, w, h, kMaxTileSideOverImage));
    const int x_levels = level_mode == 0 ? 1
                         : level_mode == 1
                             ? exr_level_count(static_cast<int>(std::max(w, h)), round_up)
                             : exr_level_count(static_cast<int>(w), round_up);
    const int y_levels = level_mode == 0   ? 1
                         : level_mode == 1 ? x_levels
                                           : exr_level_count(static_cast<int>(h), round_up);
    auto tiles_of_level = [&](int lx, int ly, int64_t* lw, int64_t* lh) {
      *lw = exr_level_size(static_cast<int>(w), lx, round_up);
      *lh = exr_level_size(static_cast<int>(h), ly, round_up);
      return ceil_div(static_cast<uint64_t>(*lw), tile_w) *
             ceil_div(static_cast<uint64_t>(*lh), tile_h);
    };
    uint64_t count = 0;
    int64_t lw = 0, lh = 0;
    for (int ly = 0; ly < y_levels; ++ly)
      for (int lx = 0; lx < x_levels; ++lx)
        if (level_mode == 2 || lx == ly) count += tiles_of_level(lx, ly, &lw, &lh);
    reserve_table(count);
    for (int ly = 0; ly < y_levels; ++ly)
      for (int lx = 0; lx < x_levels; ++lx) {
        if (level_mode != 2 && lx != ly) continue;
        tiles_of_level(lx, ly, &lw, &lh);
        for (int64_t ty = 0; ty * tile_h < lh; ++ty)
          for (int64_t tx = 0; tx * tile_w < lw; ++tx)
            chunks.push_back({tx, ty, std::min<int64_t>(tile_w, lw - tx * tile_w),
                              std::min<int64_t>(tile_h, lh - ty * tile_h), lx, ly});
      }
  }

  const size_t table_start = c.pos();
  const size_t data_start = table_start + 8 * chunks.size();
  const uint64_t ratio = exr_max_ratio(compression);
  for (size_t i = 0; i < chunks.size(); ++i) {
    c.seek(table_start + 8 * i);
    const uint64_t offset = c.u64le("the offset table");
    const Chunk& k = chunks[i];
    // A zero or out-of-file offset is a file whose writer stopped (the table is written last).
    if (offset < data_start || offset >= c.size())
      c.fail(
          fmt::format("truncated or malformed OpenEXR: chunk {} of {} is at offset {}, outside "
                      "the data ({}..{})",
                      i, chunks.size(), offset, data_start, c.size()));
    c.seek(static_cast<size_t>(offset));
    if (tiled) {
      const int32_t tx = c.i32le("a tile header"), ty = c.i32le("a tile header");
      const int32_t lx = c.i32le("a tile header"), ly = c.i32le("a tile header");
      if (tx != k.x || ty != k.y || lx != k.lx || ly != k.ly)
        c.fail(
            fmt::format("malformed OpenEXR: chunk {} holds tile ({}, {}) of level ({}, {}), "
                        "expected ({}, {}) of ({}, {})",
                        i, tx, ty, lx, ly, k.x, k.y, k.lx, k.ly));
    } else {
      const int32_t y = c.i32le("a scanline chunk header");
      if (int64_t{y} != info.min_y + k.y)
        c.fail(fmt::format("malformed OpenEXR: chunk {} holds scanline {}, expected {}", i, y,
                           info.min_y + k.y));
    }
    const int32_t packed = c.i32le("a chunk header");
    if (packed < 0 || !c.has(static_cast<uint64_t>(packed)))
      c.fail(
          fmt::format("truncated OpenEXR: chunk {} declares {} bytes at offset {}, the file has "
                      "{}",
                      i, packed, c.pos(), c.size()));
    const uint64_t unpacked = static_cast<uint64_t>(k.w * k.h) * pixel_bytes;
    if (static_cast<uint64_t>(packed) > unpacked)
      c.fail(fmt::format("malformed OpenEXR: chunk {} holds {} bytes for {} bytes of pixels", i,
                         packed, unpacked));
    if (unpacked > ratio * static_cast<uint64_t>(packed))
      c.fail(
          fmt::format("malformed OpenEXR: chunk {} declares {} bytes of pixels in {} bytes, "
                      "more than its compression can expand ({}:1)",
                      i, unpacked, packed, ratio));
  }
  return info;
}

}  // namespace illum::image_checks
