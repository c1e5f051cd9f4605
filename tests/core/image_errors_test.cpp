// Hostile image files: every one is refused with an illum::Error naming the file, before a
// decoder allocates for a size the bytes cannot hold and without hanging (truncated Radiance
// run-length data made stb loop forever). The messages are pinned so that each test fails
// when the check it covers is removed (the mutation list in the issue's closing note). Valid
// files at the edge of each bound (constant images, every OpenEXR compression and tile
// layout) must still read. All files are generated here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPreviewImage.h>
#include <OpenEXR/ImfStringVectorAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include "illum/core/image.h"
#include "illum/core/rng.h"
#include "test_support/error_within.h"

namespace illum {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<uint8_t>;

class ImageErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / fmt::format("illum_image_errors_{}_{}", getpid(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

Bytes bytes_of(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

Bytes text(std::string_view s) {
  return Bytes(s.begin(), s.end());
}

void append(Bytes& b, const Bytes& more) {
  b.insert(b.end(), more.begin(), more.end());
}

size_t find(const Bytes& b, std::string_view needle, size_t from = 0) {
  const auto it =
      std::search(b.begin() + static_cast<std::ptrdiff_t>(from), b.end(), needle.begin(),
                  needle.end(), [](uint8_t x, char y) { return x == static_cast<uint8_t>(y); });
  EXPECT_NE(it, b.end()) << "pattern not found";
  return static_cast<size_t>(it - b.begin());
}

void put_u32le(Bytes& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_u32be(Bytes& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<uint8_t>(v >> (8 * (3 - i)));
}
void put_u16be(Bytes& b, size_t at, uint16_t v) {
  b[at] = static_cast<uint8_t>(v >> 8);
  b[at + 1] = static_cast<uint8_t>(v);
}

using test::error_within;

std::string decode_error(const Bytes& bytes, const std::string& name) {
  return error_within(20.0, [&] { decode_image(bytes, name); });
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

#define EXPECT_MESSAGE(message, name, part)                                      \
  do {                                                                           \
    const std::string m_ = (message);                                            \
    EXPECT_TRUE(contains(m_, name)) << "does not name " << (name) << ": " << m_; \
    EXPECT_TRUE(contains(m_, part)) << "expected '" << (part) << "': " << m_;    \
    EXPECT_EQ(m_.find('\n'), std::string::npos) << m_;                           \
  } while (0)

// ---------------------------------------------------------------------------------------
// Radiance HDR

constexpr std::string_view kHdrHeader = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";

// Cut anywhere, a run-length encoded file is an error; before the pre-check, stb read zeros
// past the end and a zero run count never advanced (full CPU, forever).
TEST_F(ImageErrors, TruncatedHdrIsAnErrorNotAHang) {
  Image img(64, 8, 3);
  Rng rng(5);
  for (float& v : img.data()) v = rng.next_float() * 4.0f;
  write_image(path("a.hdr"), img);
  const Bytes whole = bytes_of(path("a.hdr"));
  const size_t data = find(whole, "+X 64\n") + 6;
  ASSERT_EQ(whole[data], 2);  // stb writes run-length scanlines at this width
  ASSERT_EQ(whole[data + 1], 2);
  for (size_t cut = data; cut < whole.size(); ++cut) {
    SCOPED_TRACE(cut);
    const Bytes part(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_MESSAGE(decode_error(part, "cut.hdr"), "cut.hdr", "truncated");
  }
  EXPECT_EQ(decode_image(whole, "whole.hdr").width(), 64);
}

TEST_F(ImageErrors, HdrZeroRunCountIsAnError) {
  // A scanline of width 16 whose first run count is 0: malformed (no writer makes one). stb
  // skips such counts without advancing, which at the end of the data, where it reads zero
  // counts, never ends.
  Bytes b = text(kHdrHeader);
  append(b, text("-Y 1 +X 16\n"));
  append(b, {2, 2, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_MESSAGE(decode_error(b, "zero.hdr"), "zero.hdr", "run of 0");
}

TEST_F(ImageErrors, HdrDeclaredSizeNeedsItsBytes) {
  // 7 pixels wide is stored flat (4 bytes a pixel): 60000 rows need 1.68 MB, not 40 bytes.
  Bytes flat = text(kHdrHeader);
  append(flat, text("-Y 60000 +X 7\n"));
  flat.resize(flat.size() + 40, 128);
  EXPECT_MESSAGE(decode_error(flat, "flat.hdr"), "flat.hdr", "truncated");
  Bytes empty = text(kHdrHeader);
  append(empty, text("-Y 0 +X 16\n"));
  EXPECT_MESSAGE(decode_error(empty, "empty.hdr"), "empty.hdr", "at least one pixel");
  Bytes huge = text(kHdrHeader);
  append(huge, text("-Y 60000 +X 60000\n"));
  EXPECT_MESSAGE(decode_error(huge, "huge.hdr"), "huge.hdr", "larger than illum reads");
}

TEST_F(ImageErrors, HdrFlatScanlineAfterRunLengthOnesIsAnError) {
  // stb would start over flat at pixel (1, 0) here and return a scrambled image.
  Bytes b = text(kHdrHeader);
  append(b, text("-Y 2 +X 8\n"));
  append(b, {2, 2, 0, 8});
  for (int channel = 0; channel < 4; ++channel) append(b, {128 + 8, 100});
  for (int i = 0; i < 16; ++i) append(b, {200, 200, 200, 128});
  EXPECT_MESSAGE(decode_error(b, "mixed.hdr"), "mixed.hdr", "not run-length encoded");
}

// ---------------------------------------------------------------------------------------
// PNG

Bytes png_with(uint32_t w, uint32_t h, const Bytes& idat, bool iend = true) {
  Bytes b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  auto chunk = [&](const char* type, const Bytes& data) {
    const size_t at = b.size();
    b.resize(at + 8);
    put_u32be(b, at, static_cast<uint32_t>(data.size()));
    std::memcpy(&b[at + 4], type, 4);
    append(b, data);
    append(b, {0, 0, 0, 0});  // CRC (neither stb nor illum's check reads it)
  };
  Bytes ihdr(13, 0);
  put_u32be(ihdr, 0, w);
  put_u32be(ihdr, 4, h);
  ihdr[8] = 8;  // 8-bit grey
  chunk("IHDR", ihdr);
  chunk("IDAT", idat);
  if (iend) chunk("IEND", {});
  return b;
}

TEST_F(ImageErrors, PngDeclaredSizeBeyondWhatItsDataCanInflateTo) {
  // 16000² grey pixels need 256 MB inflated; 100 bytes of deflate inflate to at most
  // 103 200. stb allocates the inflated size before it reads the stream.
  EXPECT_MESSAGE(decode_error(png_with(16000, 16000, Bytes(100, 0x78)), "bomb.png"), "bomb.png",
                 "deflate inflates at most 1032:1");
  EXPECT_MESSAGE(decode_error(png_with(60000, 60000, Bytes(100, 0x78)), "huge.png"), "huge.png",
                 "larger than illum reads");
  EXPECT_MESSAGE(decode_error(png_with(0, 5, Bytes(100, 0x78)), "empty.png"), "empty.png",
                 "at least one pixel");
}

TEST_F(ImageErrors, PngStructureIsChecked) {
  write_image(path("a.png"), Image(32, 32, 3, 0.5f));
  const Bytes whole = bytes_of(path("a.png"));
  const Bytes no_iend(whole.begin(), whole.end() - 12);
  EXPECT_MESSAGE(decode_error(no_iend, "cut.png"), "cut.png", "no IEND");
  Bytes long_chunk = whole;
  put_u32be(long_chunk, find(whole, "IDAT") - 4, 0x7fff0000u);
  EXPECT_MESSAGE(decode_error(long_chunk, "long.png"), "long.png", "declares");
}

// A constant image is the most compressible: stb's own PNG of one still reads.
TEST_F(ImageErrors, ConstantPngStillReads) {
  write_image(path("flat.png"), Image(2048, 2048, 1, 0.0f));
  const Image back = read_image(path("flat.png"));
  EXPECT_EQ(back.width(), 2048);
  std::printf("2048² constant PNG: %zu bytes\n",
              static_cast<size_t>(fs::file_size(path("flat.png"))));
}

// ---------------------------------------------------------------------------------------
// JPEG

Bytes small_jpeg(const std::string& file) {
  Image img(16, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) img.set_rgb(x, y, Color(x / 16.0f, y / 16.0f, 0.5f));
  write_image(file, img);
  return bytes_of(file);
}

TEST_F(ImageErrors, JpegDeclaredSizeBeyondItsCodedData) {
  Bytes b = small_jpeg(path("a.jpg"));
  const size_t sof = find(b, "\xff\xc0\x00\x11\x08");
  put_u16be(b, sof + 5, 4000);  // height
  put_u16be(b, sof + 7, 4000);  // width: 250 000 blocks from about 200 coded bytes
  EXPECT_MESSAGE(decode_error(b, "bomb.jpg"), "bomb.jpg", "at least one bit per block");
}

TEST_F(ImageErrors, JpegWithoutEndMarkerIsTruncated) {
  // Cut anywhere in its scan, a JPEG is an error (stb decodes the missing data as grey).
  const Bytes whole = small_jpeg(path("a.jpg"));
  const size_t scan = find(whole, "\xff\xda\x00\x0c\x03") + 14;
  for (size_t cut = scan; cut < whole.size(); ++cut) {
    SCOPED_TRACE(cut);
    const Bytes part(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_MESSAGE(decode_error(part, "cut.jpg"), "cut.jpg", "truncated JPEG");
  }
  EXPECT_EQ(decode_image(whole, "whole.jpg").width(), 16);
}

TEST_F(ImageErrors, JpegScanCountIsBounded) {
  // The one scan of a baseline file, repeated: each scan costs a pass over every block.
  const Bytes whole = small_jpeg(path("a.jpg"));
  const size_t sos = find(whole, "\xff\xda\x00\x0c\x03");
  const Bytes scan(whole.begin() + static_cast<std::ptrdiff_t>(sos), whole.end() - 2);
  Bytes many(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(sos));
  for (int i = 0; i < 300; ++i) append(many, scan);
  append(many, {0xff, 0xd9});
  EXPECT_MESSAGE(decode_error(many, "scans.jpg"), "scans.jpg", "more than 256 scans");
}

TEST_F(ImageErrors, JpegHuffmanTablesAreChecked) {
  // Debian's stb writes the symbols of a Huffman table into 256 entries without counting
  // them (fuzz/regressions/image/jpeg-dht-*): a table declaring more is refused first.
  Bytes b = small_jpeg(path("a.jpg"));
  const size_t dht = find(b, "\xff\xc4");
  ASSERT_EQ(b[dht + 4], 0x00);                            // the first table: DC, id 0
  for (size_t i = 0; i < 16; ++i) b[dht + 5 + i] = 0x40;  // 16 × 64 = 1024 codes
  EXPECT_MESSAGE(decode_error(b, "dht.jpg"), "dht.jpg", "declares 1024 codes");
  Bytes bad_class = small_jpeg(path("a.jpg"));
  bad_class[dht + 4] = 0x24;  // class 2
  EXPECT_MESSAGE(decode_error(bad_class, "class.jpg"), "class.jpg", "class 2 and id 4");
}

TEST_F(ImageErrors, JpegTablesAreDefinedBeforeTheScanThatUsesThem) {
  // Debian's stb decodes with whatever table a component names, defined or not, from an
  // uninitialised allocation: a file without its DQT decoded heap garbage (the fuzzer's
  // UBSan overflow that only showed after other inputs; fuzz/regressions/image/jpeg-no-dqt-*).
  const Bytes whole = small_jpeg(path("a.jpg"));
  const size_t dqt = find(whole, "\xff\xdb\x00\x84");
  ASSERT_EQ(whole[dqt + 4], 0x00);
  ASSERT_EQ(whole[dqt + 4 + 65], 0x01);  // stb writes tables 0 and 1 in one segment
  Bytes quant = whole;
  quant[dqt + 4 + 65] = 0x02;  // table 1 becomes table 2: the chroma components lack theirs
  EXPECT_MESSAGE(decode_error(quant, "dqt.jpg"), "dqt.jpg",
                 "component 2 uses quantization table 1, which no DQT segment");
  Bytes no_dqt = whole;
  no_dqt.erase(no_dqt.begin() + static_cast<std::ptrdiff_t>(dqt),
               no_dqt.begin() + static_cast<std::ptrdiff_t>(dqt + 2 + 0x84));
  EXPECT_MESSAGE(decode_error(no_dqt, "nodqt.jpg"), "nodqt.jpg", "quantization table 0");

  const size_t sos = find(whole, "\xff\xda\x00\x0c\x03");
  ASSERT_EQ(whole[sos + 7], 0x02);
  ASSERT_EQ(whole[sos + 8], 0x11);  // component 2: DC table 1, AC table 1
  Bytes dc = whole;
  dc[sos + 8] = 0x21;
  EXPECT_MESSAGE(decode_error(dc, "dc.jpg"), "dc.jpg", "uses DC Huffman table 2");
  Bytes ac = whole;
  ac[sos + 8] = 0x12;
  EXPECT_MESSAGE(decode_error(ac, "ac.jpg"), "ac.jpg", "uses AC Huffman table 2");
  Bytes component = whole;
  component[sos + 7] = 0x09;
  EXPECT_MESSAGE(decode_error(component, "comp.jpg"), "comp.jpg",
                 "names component 9, which the frame does not have");
  EXPECT_EQ(decode_image(whole, "whole.jpg").width(), 16);
}

TEST_F(ImageErrors, JpegCodingOtherThanHuffmanIsRefused) {
  Bytes b = small_jpeg(path("a.jpg"));
  b[find(b, "\xff\xc0\x00\x11\x08") + 1] = 0xc9;  // arithmetic coding
  EXPECT_MESSAGE(decode_error(b, "arith.jpg"), "arith.jpg", "unsupported JPEG coding");
}

// ---------------------------------------------------------------------------------------
// OpenEXR

// The ratios image_checks.cpp allows, for the printout.
const char* const kCompressionBounds[] = {"1",    "64", "1032", "1032",   "410",
                                          "1376", "11", "11",   "132096", "132096"};
const char* const kCompressionNames[] = {"none",  "rle", "zips", "zip",  "piz",
                                         "pxr24", "b44", "b44a", "dwaa", "dwab"};

// Pixels of `w` × `h` × 3 channels in the file's own type (OpenEXR does not convert on output).
class ExrPixels {
 public:
  ExrPixels(int w, int h, Imf::PixelType type, const std::function<float(int, int, int)>& value)
      : w_(w), type_(type), size_(type == Imf::HALF ? 2 : 4) {
    bytes_.resize(static_cast<size_t>(w) * h * 3 * size_);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          char* p = bytes_.data() + ((static_cast<size_t>(y) * w + x) * 3 + c) * size_;
          const float v = value(x, y, c);
          if (type == Imf::HALF) {
            const Imath::half hv(v);
            std::memcpy(p, &hv, 2);
          } else {
            std::memcpy(p, &v, 4);
          }
        }
  }
  Imf::Slice slice(int c) {
    return Imf::Slice(type_, bytes_.data() + c * size_, 3 * size_, 3 * size_ * w_);
  }

 private:
  int w_;
  Imf::PixelType type_;
  size_t size_;
  std::vector<char> bytes_;
};

void write_scanline_exr(const std::string& file, int w, int h, Imf::Compression compression,
                        Imf::PixelType type, const std::function<float(int, int, int)>& value,
                        const std::function<void(Imf::Header&)>& edit = {}) {
  Imf::Header header(w, h);
  header.compression() = compression;
  const char* names[] = {"R", "G", "B"};
  for (const char* n : names) header.channels().insert(n, Imf::Channel(type));
  if (edit) edit(header);
  ExrPixels pixels(w, h, type, value);
  Imf::FrameBuffer fb;
  for (int c = 0; c < 3; ++c) fb.insert(names[c], pixels.slice(c));
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(fb);
  out.writePixels(h);
}

void write_tiled_exr(const std::string& file, int w, int h, Imf::LevelMode mode,
                     Imf::LevelRoundingMode rounding, Imf::Compression compression,
                     const std::function<float(int, int, int)>& value, int tile = 0) {
  Imf::Header header(w, h);
  header.compression() = compression;
  header.setTileDescription(
      Imf::TileDescription(tile > 0 ? tile : 16, tile > 0 ? tile : 8, mode, rounding));
  const char* names[] = {"R", "G", "B"};
  for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::HALF));
  Imf::TiledOutputFile out(file.c_str(), header);
  for (int ly = 0; ly < out.numYLevels(); ++ly)
    for (int lx = 0; lx < out.numXLevels(); ++lx) {
      if (mode != Imf::RIPMAP_LEVELS && lx != ly) continue;
      const int lw = out.levelWidth(lx), lh = out.levelHeight(ly);
      ExrPixels pixels(lw, lh, Imf::HALF, [&](int x, int y, int c) {
        return lx == 0 && ly == 0 ? value(x, y, c) : 0.25f;
      });
      Imf::FrameBuffer fb;
      for (int c = 0; c < 3; ++c) fb.insert(names[c], pixels.slice(c));
      out.setFrameBuffer(fb);
      if (mode == Imf::RIPMAP_LEVELS)
        out.writeTiles(0, out.numXTiles(lx) - 1, 0, out.numYTiles(ly) - 1, lx, ly);
      else
        out.writeTiles(0, out.numXTiles(lx) - 1, 0, out.numYTiles(ly) - 1, lx);
    }
}

float pattern_value(int x, int y, int c) {
  return 0.25f * static_cast<float>((x * 7 + y * 3 + c * 5) % 16);  // exact in half
}

void expect_level0(const Image& back, int w, int h, bool exact, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(back.width(), w);
  ASSERT_EQ(back.height(), h);
  ASSERT_EQ(back.channels(), 3);
  if (!exact) return;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(back.pixel(x, y)[c], pattern_value(x, y, c)) << x << "," << y;
}

// Valid files at the edge of the per-compression ratio bounds: constant images (the most
// compressible) and patterned ones, in every compression and tile layout OpenEXR writes.
TEST_F(ImageErrors, EveryExrCompressionAndLayoutStillReads) {
  for (int compression = 0; compression < 10; ++compression) {
    const auto comp = static_cast<Imf::Compression>(compression);
    const bool lossless = compression <= 4;  // none, rle, zips, zip, piz
    for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT}) {
      SCOPED_TRACE(fmt::format("{} {}", kCompressionNames[compression],
                               type == Imf::HALF ? "half" : "float"));
      const std::string file = path("c.exr");
      write_scanline_exr(file, 1024, 256, comp, type, [](int, int, int) { return 0.0f; });
      const Image flat = read_image(file);
      ASSERT_EQ(flat.width(), 1024);
      for (float v : flat.data()) ASSERT_EQ(v, 0.0f);
      const double pixel_bytes = 1024.0 * 256.0 * 3.0 * (type == Imf::HALF ? 2.0 : 4.0);
      std::printf(
          "constant 1024x256 %-5s %-5s: %8zu bytes, pixels/file %6.0f (bound per chunk %s)\n",
          kCompressionNames[compression], type == Imf::HALF ? "half" : "float",
          static_cast<size_t>(fs::file_size(file)),
          pixel_bytes / static_cast<double>(fs::file_size(file)), kCompressionBounds[compression]);
      write_scanline_exr(file, 300, 70, comp, type, pattern_value);
      expect_level0(read_image(file), 300, 70, lossless, "pattern");
    }
  }
  const struct {
    Imf::LevelMode mode;
    Imf::LevelRoundingMode rounding;
    const char* name;
  } layouts[] = {{Imf::ONE_LEVEL, Imf::ROUND_DOWN, "one level"},
                 {Imf::MIPMAP_LEVELS, Imf::ROUND_DOWN, "mipmap, round down"},
                 {Imf::MIPMAP_LEVELS, Imf::ROUND_UP, "mipmap, round up"},
                 {Imf::RIPMAP_LEVELS, Imf::ROUND_DOWN, "ripmap, round down"},
                 {Imf::RIPMAP_LEVELS, Imf::ROUND_UP, "ripmap, round up"}};
  for (const auto& layout : layouts)
    for (Imf::Compression comp :
         {Imf::NO_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION}) {
      const std::string file = path("t.exr");
      write_tiled_exr(file, 37, 21, layout.mode, layout.rounding, comp, pattern_value);
      expect_level0(read_image(file), 37, 21, true, layout.name);
    }
}

// Offsets of the data window's four int32 in a file written by write_scanline_exr.
size_t data_window_at(const Bytes& b) {
  return find(b, std::string_view("dataWindow\0box2i\0", 17)) + 17 + 4;
}

TEST_F(ImageErrors, ExrAbsurdDataWindows) {
  write_scanline_exr(path("a.exr"), 32, 32, Imf::ZIP_COMPRESSION, Imf::HALF, pattern_value);
  const Bytes whole = bytes_of(path("a.exr"));
  const size_t dw = data_window_at(whole);
  auto with_window = [&](int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    Bytes b = whole;
    put_u32le(b, dw, static_cast<uint32_t>(x0));
    put_u32le(b, dw + 4, static_cast<uint32_t>(y0));
    put_u32le(b, dw + 8, static_cast<uint32_t>(x1));
    put_u32le(b, dw + 12, static_cast<uint32_t>(y1));
    return b;
  };
  EXPECT_MESSAGE(decode_error(with_window(0, 0, 59999, 59999), "huge.exr"), "huge.exr",
                 "larger than illum reads");
  EXPECT_MESSAGE(decode_error(with_window(0, 0, 31, -5), "negative.exr"), "negative.exr",
                 "at least one pixel");
  EXPECT_MESSAGE(decode_error(with_window(0, 0, INT32_MAX, 31), "overflow.exr"), "overflow.exr",
                 "larger than illum reads");
  // Within the size limits, but 1000 chunks need an 8000-byte offset table.
  EXPECT_MESSAGE(decode_error(with_window(0, 0, 15999, 15999), "table.exr"), "table.exr",
                 "offset table");
  EXPECT_MESSAGE(decode_error(with_window(-(1 << 30) - 5, 0, -(1 << 30) + 26, 31), "far.exr"),
                 "far.exr", "beyond ±2^30");
}

TEST_F(ImageErrors, TruncatedExrScanlinesAndTiles) {
  write_scanline_exr(path("s.exr"), 40, 40, Imf::ZIP_COMPRESSION, Imf::HALF, pattern_value);
  write_tiled_exr(path("t.exr"), 40, 40, Imf::MIPMAP_LEVELS, Imf::ROUND_DOWN, Imf::ZIP_COMPRESSION,
                  pattern_value);
  for (const char* name : {"s.exr", "t.exr"}) {
    const Bytes whole = bytes_of(path(name));
    for (size_t cut = 8; cut < whole.size(); cut += 7) {
      SCOPED_TRACE(fmt::format("{} cut at {} of {}", name, cut, whole.size()));
      const Bytes part(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut));
      const std::string m = decode_error(part, name);
      EXPECT_MESSAGE(m, name, "");
      EXPECT_TRUE(contains(m, "truncated") || contains(m, "malformed")) << m;
    }
  }
}

// Where the chunk offset table of a single-part file starts: the first offset points just
// past the table of `chunks` entries.
size_t exr_offset_table(const Bytes& b, size_t chunks) {
  for (size_t p = 8; p + 8 <= b.size(); ++p) {
    uint64_t first = 0;
    for (int i = 0; i < 8; ++i) first |= uint64_t{b[p + i]} << (8 * i);
    if (first == p + 8 * chunks) return p;
  }
  ADD_FAILURE() << "no offset table";
  return 0;
}

TEST_F(ImageErrors, ExrChunkSizesAreChecked) {
  // Uncompressed: a chunk declaring fewer bytes than its pixels would be read past its end.
  write_scanline_exr(path("n.exr"), 16, 4, Imf::NO_COMPRESSION, Imf::HALF, pattern_value);
  Bytes b = bytes_of(path("n.exr"));
  const size_t table = exr_offset_table(b, 4);
  uint64_t first = 0;
  for (int i = 0; i < 8; ++i) first |= uint64_t{b[table + i]} << (8 * i);
  Bytes short_chunk = b;
  put_u32le(short_chunk, static_cast<size_t>(first) + 4, 10);  // 96 bytes of pixels in 10
  EXPECT_MESSAGE(decode_error(short_chunk, "short.exr"), "short.exr",
                 "more than its compression can expand");
  Bytes long_chunk = b;
  put_u32le(long_chunk, static_cast<size_t>(first) + 4, 97);  // more bytes than its pixels
  EXPECT_MESSAGE(decode_error(long_chunk, "long.exr"), "long.exr", "97 bytes for 96 bytes");
  Bytes at_zero = b;  // an offset of 0: the writer never finished the table
  put_u32le(at_zero, table, 0);
  put_u32le(at_zero, table + 4, 0);
  EXPECT_MESSAGE(decode_error(at_zero, "zero.exr"), "zero.exr", "outside the data");
  Bytes swapped = b;  // chunk 0's offset names chunk 1's data (scanline 1)
  std::copy_n(b.begin() + static_cast<std::ptrdiff_t>(table + 8), 8,
              swapped.begin() + static_cast<std::ptrdiff_t>(table));
  EXPECT_MESSAGE(decode_error(swapped, "swapped.exr"), "swapped.exr",
                 "holds scanline 1, expected 0");
}

TEST_F(ImageErrors, ExrTileTableMustFitTheFile) {
  // 1×1 tiles over a 16384² window are 2^28 chunks: their offset table alone would be 2 GiB.
  write_tiled_exr(path("t.exr"), 16, 16, Imf::ONE_LEVEL, Imf::ROUND_DOWN, Imf::ZIP_COMPRESSION,
                  pattern_value, 1);
  Bytes b = bytes_of(path("t.exr"));
  const size_t dw = find(b, std::string_view("dataWindow\0box2i\0", 17)) + 17 + 4;
  put_u32le(b, dw + 8, 16383);
  put_u32le(b, dw + 12, 16383);
  EXPECT_MESSAGE(decode_error(b, "tiles.exr"), "tiles.exr", "offset table");
}

TEST_F(ImageErrors, ExrChannelsMustMakeAnImage) {
  write_scanline_exr(path("a.exr"), 8, 8, Imf::ZIP_COMPRESSION, Imf::HALF, pattern_value);
  Bytes b = bytes_of(path("a.exr"));
  Bytes missing = b;
  missing[find(b, std::string_view("B\0\x01\0\0\0", 6))] = 'Z';  // R, G and Z
  EXPECT_MESSAGE(decode_error(missing, "rg.exr"), "rg.exr", "not B");
  Bytes subsampled = b;
  put_u32le(subsampled, find(b, std::string_view("G\0\x01\0\0\0", 6)) + 10, 2);
  EXPECT_MESSAGE(decode_error(subsampled, "sub.exr"), "sub.exr", "subsampled");
  Bytes deep = b;
  deep[5] |= 0x08;  // version flags: non-image (deep) data
  EXPECT_MESSAGE(decode_error(deep, "deep.exr"), "deep.exr", "deep OpenEXR");
}

TEST_F(ImageErrors, ExrHeaderAttributesCannotAskForMemory) {
  // An attribute of a type OpenEXR does not know is read whole into memory: its size must lie
  // inside the file.
  write_scanline_exr(path("v.exr"), 8, 8, Imf::ZIP_COMPRESSION, Imf::HALF, pattern_value,
                     [](Imf::Header& h) {
                       h.insert("views", Imf::StringVectorAttribute({"left", "right"}));
                     });
  const Bytes views = bytes_of(path("v.exr"));
  const size_t at = find(views, std::string_view("views\0stringvector\0", 19));
  Bytes unknown = views;
  unknown[at + 6 + 11] = 'x';  // "stringvectox": an opaque attribute
  put_u32le(unknown, at + 19, 0x7ffffff0u);
  EXPECT_MESSAGE(decode_error(unknown, "attribute.exr"), "attribute.exr",
                 "declares 2147483632 bytes");
  // Counts inside an attribute (a preview's size, a string vector's lengths): OpenEXR 3.1
  // checks these against the attribute itself; still one Error naming the file.
  Bytes strings = views;
  put_u32le(strings, at + 19 + 4, 0x7ffffff0u);
  EXPECT_MESSAGE(decode_error(strings, "strings.exr"), "strings.exr", "cannot read image");
  write_scanline_exr(path("p.exr"), 8, 8, Imf::ZIP_COMPRESSION, Imf::HALF, pattern_value,
                     [](Imf::Header& h) { h.setPreviewImage(Imf::PreviewImage(2, 2)); });
  Bytes preview = bytes_of(path("p.exr"));
  const size_t p = find(preview, std::string_view("preview\0preview\0", 16)) + 16 + 4;
  put_u32le(preview, p, 30000);
  put_u32le(preview, p + 4, 30000);
  EXPECT_MESSAGE(decode_error(preview, "p.exr"), "p.exr", "cannot read image");
}

TEST_F(ImageErrors, NonFiniteTexelsAreNamed) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT}) {
    write_scanline_exr(path("n.exr"), 8, 4, Imf::ZIP_COMPRESSION, type, [&](int x, int y, int c) {
      return x == 3 && y == 2 && c == 1 ? nan : 1.0f;
    });
    EXPECT_MESSAGE(error_within(20, [&] { read_image(path("n.exr")); }), path("n.exr"),
                   "texel (3, 2) channel 1 is NaN");
    write_scanline_exr(path("i.exr"), 8, 4, Imf::ZIP_COMPRESSION, type, [&](int x, int y, int c) {
      return x == 7 && y == 0 && c == 2 ? inf : 1.0f;
    });
    EXPECT_MESSAGE(error_within(20, [&] { read_image(path("i.exr")); }), path("i.exr"),
                   "texel (7, 0) channel 2 is infinite");
  }
}

// ---------------------------------------------------------------------------------------
// Any format

TEST_F(ImageErrors, DecodeFromMemoryIsTheFileReader) {
  Image img(9, 5, 4);
  Rng rng(3);
  for (float& v : img.data()) v = rng.next_float();
  write_image(path("a.png"), img);
  const Image from_file = read_image(path("a.png"), false);
  const Image from_memory = decode_image(bytes_of(path("a.png")), "memory", false);
  EXPECT_EQ(from_file.data(), from_memory.data());
  // The content decides the format: a PNG named .jpg reads as the PNG it is.
  fs::copy_file(path("a.png"), path("really_png.jpg"));
  EXPECT_EQ(read_image(path("really_png.jpg"), false).data(), from_file.data());
  EXPECT_MESSAGE(decode_error({}, "nothing.png"), "nothing.png", "empty image file");
  EXPECT_MESSAGE(decode_error(text("GIF89a......"), "anim.png"), "anim.png",
                 "not a PNG, JPEG, Radiance HDR or OpenEXR image");
}

}  // namespace
}  // namespace illum
