// Image files: round trips through every format and channel count with tolerances derived
// from each format's precision, and the failure paths (missing folder, missing or corrupt
// file) that must throw illum::Error naming the path and leave no file behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "illum/core/image.h"
#include "illum/core/rng.h"

namespace illum {
namespace {

namespace fs = std::filesystem;

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("illum_core_image_{}_{}_{}", getpid(),
                                                   info->test_suite_name(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  size_t files_in_dir() const {
    return static_cast<size_t>(
        std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

// A smooth test pattern (JPEG-friendly) in [lo, hi] with alpha in [0, 1].
Image pattern(int w, int h, int channels, float lo = 0.0f, float hi = 1.0f) {
  Image img(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        const float t = 0.5f + 0.5f * std::sin(0.11f * x + 0.07f * y + 1.3f * c);
        const bool alpha = (channels == 2 || channels == 4) && c == channels - 1;
        img.pixel(x, y)[c] = alpha ? t : lo + (hi - lo) * t;
      }
  return img;
}

// A pattern spanning six decades (for HDR and EXR).
Image hdr_pattern(int w, int h, int channels) {
  Image img(w, h, channels);
  Rng rng(99);
  for (float& v : img.data()) v = std::pow(10.0f, -3.0f + 6.0f * rng.next_float());
  return img;
}

void expect_same_shape(const Image& a, const Image& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.channels(), b.channels());
}

bool is_alpha(int c, int channels) {
  return (channels == 2 || channels == 4) && c == channels - 1;
}

TEST_F(ImageFiles, PngRoundTripAllChannelCounts) {
  // 8-bit quantization rounds to the nearest code: error ≤ ½ / 255 in the encoded
  // domain (sRGB for colour, linear for alpha), plus float rounding.
  const float tol = 0.5f / 255.0f + 1e-6f;
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const Image img = pattern(37, 21, channels);
    const std::string file = path(fmt::format("c{}.png", channels));
    write_image(file, img);
    const Image back = read_image(file);
    expect_same_shape(img, back);
    for (size_t i = 0; i < img.data().size(); ++i) {
      const int c = static_cast<int>(i % static_cast<size_t>(channels));
      const float a = img.data()[i], b = back.data()[i];
      if (is_alpha(c, channels))
        ASSERT_NEAR(a, b, tol) << i;
      else
        ASSERT_NEAR(srgb_encode(a), srgb_encode(b), tol) << i;
    }
  }
}

TEST_F(ImageFiles, EightBitFilesKeepTheirBytesForLookups) {
  // 8-bit files keep their bytes beside the floats (Image::keep_bytes), so texture lookups
  // read a quarter of the memory; a lookup must return exactly the value the float texels
  // give (the path tracer's images stay the same bytes), for every channel count and both
  // encodings, at any uv (wrap-around included).
  Rng rng(7);
  for (const bool srgb : {true, false}) {
    for (int channels = 1; channels <= 4; ++channels) {
      SCOPED_TRACE(fmt::format("srgb {} channels {}", srgb, channels));
      const std::string file = path(fmt::format("b{}.png", channels));
      write_image(file, pattern(37, 21, channels));
      const Image packed = read_image(file, srgb);
      ASSERT_TRUE(packed.has_bytes());
      Image floats = packed;
      floats.data();  // any non-const access drops the copy
      ASSERT_FALSE(floats.has_bytes());
      for (int i = 0; i < 2000; ++i) {
        const float u = 3.0f * rng.next_float() - 1.0f, v = 3.0f * rng.next_float() - 1.0f;
        const Color a = packed.sample_bilinear(u, v), b = floats.sample_bilinear(u, v);
        ASSERT_TRUE(a.r == b.r && a.g == b.g && a.b == b.b)
            << "uv " << u << " " << v << ": " << a.r << " " << a.g << " " << a.b << " vs " << b.r
            << " " << b.g << " " << b.b;
      }
    }
  }
  // A JPEG (the shared scenes' textures are JPEGs) keeps its bytes too, and a write through a
  // non-const accessor is what a lookup then returns, not the stale byte.
  write_image(path("t.jpg"), pattern(16, 16, 3));
  Image jpeg = read_image(path("t.jpg"));
  ASSERT_TRUE(jpeg.has_bytes());
  jpeg.pixel(3, 4)[0] = 7.0f;
  EXPECT_EQ(jpeg.sample_bilinear(3.5f / 16.0f, 4.5f / 16.0f).r, 7.0f);
  // Float formats have no bytes to keep.
  write_image(path("f.hdr"), hdr_pattern(8, 8, 3));
  EXPECT_FALSE(read_image(path("f.hdr")).has_bytes());
}

TEST_F(ImageFiles, PngLinearDataAndExposure) {
  // srgb = false keeps values as v/255 (normal maps); exposure scales before encoding.
  const Image img = pattern(16, 16, 3, 0.0f, 0.5f);
  ImageWriteOptions options;
  options.srgb = false;
  options.exposure = 2.0f;
  write_image(path("linear.png"), img, options);
  const Image back = read_image(path("linear.png"), /*srgb=*/false);
  expect_same_shape(img, back);
  for (size_t i = 0; i < img.data().size(); ++i)
    ASSERT_NEAR(back.data()[i], 2.0f * img.data()[i], 0.5f / 255.0f + 1e-6f);
}

TEST_F(ImageFiles, JpegRoundTrip) {
  // At quality 95 stb keeps full-resolution chroma and scales the standard quantization
  // tables by 0.1, so no DCT step exceeds 12 codes for luma and 10 for chroma. The DCT is
  // orthonormal, so a channel's pixel RMSE equals its coefficient RMSE, at most step/√12
  // for uniformly distributed rounding. YCbCr→RGB adds at most 1.772 × the chroma error
  // (B = Y + 1.772 Cb); then ½ code of output rounding. Bounds in sRGB-encoded codes:
  auto rmse_bound = [](int channels) {
    const double luma = 12.0 / std::sqrt(12.0), chroma = 10.0 / std::sqrt(12.0);
    const double coded =
        channels == 1 ? luma : std::sqrt(luma * luma + 1.772 * 1.772 * chroma * chroma);
    return (coded + 0.5) / 255.0;
  };
  for (int channels : {1, 3}) {
    SCOPED_TRACE(channels);
    const Image img = pattern(64, 48, channels);
    write_image(path("a.jpg"), img);
    const Image back = read_image(path("a.jpg"));
    // stb writes every JPEG as YCbCr, so a grey image comes back as three equal channels.
    ASSERT_EQ(back.width(), img.width());
    ASSERT_EQ(back.height(), img.height());
    ASSERT_EQ(back.channels(), 3);
    double sq = 0.0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        const Color a = img.rgb(x, y), b = back.rgb(x, y);
        for (int c = 0; c < 3; ++c) {
          const double d = srgb_encode(a[c]) - srgb_encode(b[c]);
          sq += d * d;
        }
      }
    const double rmse = std::sqrt(sq / (3.0 * static_cast<double>(img.pixel_count())));
    EXPECT_LT(rmse, rmse_bound(channels));
    RecordProperty(fmt::format("rmse_codes_{}", channels), fmt::format("{:.3f}", rmse * 255.0));
    std::printf("JPEG q95 %d-channel RMSE: %.3f codes (bound %.3f)\n", channels, rmse * 255.0,
                rmse_bound(channels) * 255.0);
  }
}

TEST_F(ImageFiles, JpegDropsAlpha) {
  write_image(path("rgba.jpeg"), pattern(8, 8, 4));
  EXPECT_EQ(read_image(path("rgba.jpeg")).channels(), 3);
  write_image(path("ga.jpeg"), pattern(8, 8, 2));
  EXPECT_EQ(read_image(path("ga.jpeg")).channels(), 3);
}

TEST_F(ImageFiles, HdrRoundTrip) {
  // RGBE: an 8-bit mantissa shared by the three channels, truncated when encoded, so
  // each channel is off by less than one mantissa step, 2^(e−8) ≤ max(r,g,b) / 128.
  const Image img = hdr_pattern(19, 13, 3);
  write_image(path("a.hdr"), img);
  const Image back = read_image(path("a.hdr"));
  expect_same_shape(img, back);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const float step = max_component(img.rgb(x, y)) / 128.0f;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(back.pixel(x, y)[c], img.pixel(x, y)[c], step) << x << "," << y;
    }
}

TEST_F(ImageFiles, HdrGreyBecomesRgb) {
  // Radiance files are always RGB: a grey image comes back with three equal channels.
  const Image img = hdr_pattern(7, 5, 1);
  write_image(path("grey.hdr"), img);
  const Image back = read_image(path("grey.hdr"));
  ASSERT_EQ(back.channels(), 3);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const float v = img.pixel(x, y)[0];
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(back.pixel(x, y)[c], v, v / 128.0f);
    }
}

TEST_F(ImageFiles, ExrFloatIsExact) {
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    Image img = hdr_pattern(23, 11, channels);
    img.data()[0] = -1.5f;  // EXR keeps negative values
    ImageWriteOptions options;
    options.exr_half = false;
    write_image(path("f.exr"), img, options);
    const Image back = read_image(path("f.exr"));
    expect_same_shape(img, back);
    for (size_t i = 0; i < img.data().size(); ++i) ASSERT_EQ(back.data()[i], img.data()[i]) << i;
  }
}

TEST_F(ImageFiles, ExrHalfPrecision) {
  // Half floats round to nearest with a 10-bit mantissa: relative error ≤ 2^-11 for
  // normal values (the pattern stays within [1e-3, 1e3], inside half's normal range).
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const Image img = hdr_pattern(23, 11, channels);
    write_image(path("h.exr"), img);
    const Image back = read_image(path("h.exr"));
    expect_same_shape(img, back);
    for (size_t i = 0; i < img.data().size(); ++i)
      ASSERT_NEAR(back.data()[i], img.data()[i], std::abs(img.data()[i]) * 0x1p-11f) << i;
  }
}

TEST_F(ImageFiles, WriteIntoMissingFolderThrowsAndLeavesNothing) {
  const std::string file = path("missing/sub/out.png");
  try {
    write_image(file, pattern(4, 4, 3));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(file));
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ImageFiles, FailedRenameLeavesNoTemporaryFile) {
  // The target is a non-empty folder, so encoding succeeds but the final rename fails;
  // the temporary file must be cleaned up and the error must name the path.
  for (const char* name : {"taken.png", "taken.exr", "taken.hdr"}) {
    const std::string file = path(name);
    fs::create_directories(fs::path(file) / "x");
    EXPECT_THROW(
        try { write_image(file, pattern(4, 4, 3)); } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
          throw;
        },
        Error);
  }
  EXPECT_EQ(files_in_dir(), 3u);  // only the three folders
}

TEST_F(ImageFiles, WriteReplacesExistingFile) {
  write_image(path("a.png"), Image(2, 2, 3, 0.0f));
  write_image(path("a.png"), Image(3, 1, 3, 1.0f));
  const Image back = read_image(path("a.png"));
  EXPECT_EQ(back.width(), 3);
  EXPECT_EQ(back.pixel(0, 0)[0], 1.0f);
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ImageFiles, UnknownExtensionAndEmptyImageThrow) {
  EXPECT_THROW(write_image(path("a.bmp"), pattern(2, 2, 3)), Error);
  EXPECT_THROW(write_image(path("a.png"), Image()), Error);
  EXPECT_THROW(read_image(path("a.tiff")), Error);
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ImageFiles, ReadMissingFileThrowsNamingIt) {
  for (const char* name : {"none.png", "none.jpg", "none.hdr", "none.exr"}) {
    const std::string file = path(name);
    try {
      read_image(file);
      FAIL() << "expected an Error for " << file;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  }
}

TEST_F(ImageFiles, ReadCorruptFileThrowsNamingIt) {
  std::vector<std::string> files;
  // Garbage bytes under every extension.
  for (const char* name : {"junk.png", "junk.jpg", "junk.hdr", "junk.exr"}) {
    std::ofstream(path(name), std::ios::binary) << "this is not an image at all, just some text\n";
    files.push_back(path(name));
  }
  // Valid files cut in half.
  for (const char* name : {"cut.png", "cut.exr"}) {
    write_image(path(name), hdr_pattern(64, 64, 3));
    fs::resize_file(path(name), fs::file_size(path(name)) / 2);
    files.push_back(path(name));
  }
  for (const auto& file : files) {
    try {
      read_image(file);
      ADD_FAILURE() << "expected an Error for " << file;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  }
}

TEST(Image, FormatFromPath) {
  EXPECT_EQ(image_format_from_path("a/b.PNG"), ImageFormat::kPng);
  EXPECT_EQ(image_format_from_path("x.jpeg"), ImageFormat::kJpeg);
  EXPECT_EQ(image_format_from_path("x.JPG"), ImageFormat::kJpeg);
  EXPECT_EQ(image_format_from_path("x.hdr"), ImageFormat::kHdr);
  EXPECT_EQ(image_format_from_path("x.Exr"), ImageFormat::kExr);
  try {
    image_format_from_path("out/picture.webp");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out/picture.webp"), std::string::npos);
  }
}

TEST(Image, PixelAccessAndRgb) {
  Image grey(3, 2, 1, 0.25f);
  EXPECT_EQ(grey.rgb(2, 1), Color(0.25f));
  grey.set_rgb(1, 1, Color(1.0f, 0.0f, 0.0f));
  EXPECT_FLOAT_EQ(grey.pixel(1, 1)[0], luminance(Color(1.0f, 0.0f, 0.0f)));

  Image ga(2, 2, 2, 0.5f);
  ga.set_rgb(0, 0, Color(0.3f));
  EXPECT_FLOAT_EQ(ga.pixel(0, 0)[0], 0.3f);
  EXPECT_EQ(ga.pixel(0, 0)[1], 1.0f);

  Image rgba(2, 2, 4, 0.0f);
  rgba.set_rgb(1, 0, Color(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(rgba.rgb(1, 0), Color(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(rgba.pixel(1, 0)[3], 1.0f);
  EXPECT_EQ(rgba.pixel_count(), 4u);
  EXPECT_THROW(Image(2, 2, 5), InternalError);
}

TEST(Image, BilinearInterpolatesAndWraps) {
  Image img(2, 1, 1);
  img.pixel(0, 0)[0] = 0.0f;
  img.pixel(1, 0)[0] = 1.0f;
  // Texel centres at u = 0.25 and 0.75.
  EXPECT_FLOAT_EQ(img.sample_bilinear(0.25f, 0.5f).r, 0.0f);
  EXPECT_FLOAT_EQ(img.sample_bilinear(0.75f, 0.5f).r, 1.0f);
  EXPECT_FLOAT_EQ(img.sample_bilinear(0.5f, 0.5f).r, 0.5f);
  // Between the last and first texel the lookup wraps around.
  EXPECT_FLOAT_EQ(img.sample_bilinear(0.0f, 0.5f).r, 0.5f);
  EXPECT_FLOAT_EQ(img.sample_bilinear(1.0f, 0.5f).r, 0.5f);
  EXPECT_FLOAT_EQ(img.sample_bilinear(-0.75f, 0.5f).r, 0.0f);
  EXPECT_FLOAT_EQ(img.sample_bilinear(2.75f, 3.0f).r, 1.0f);
}

TEST(Image, BilinearMatchesDirectFormulaAcrossTiles) {
  // A 5×3 RGB image of distinct texels against the textbook formula in double precision
  // (integer modulo for the wrap) at coordinates over several tiles, negative ones included.
  // Tolerance: u is a float with |u| ≤ 4, so its rounding (≤ 2.4e-7) moves the texel
  // coordinate by ≤ 1.2e-6 texels, and texel values differ by ≤ 1: 1e-5 covers that and
  // the float sums.
  const int w = 5, h = 3;
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set_rgb(x, y, Color(0.1f * x, 0.3f * y, 0.05f * (x * h + y)));
  auto reference = [&](double u, double v, int channel) {
    const double x = u * w - 0.5, y = v * h - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    auto wrap = [](double i, int n) { return ((static_cast<int>(i) % n) + n) % n; };
    const int x0 = wrap(fx, w), x1 = (x0 + 1) % w, y0 = wrap(fy, h), y1 = (y0 + 1) % h;
    const double tx = x - fx, ty = y - fy;
    auto at = [&](int xi, int yi) { return static_cast<double>(img.pixel(xi, yi)[channel]); };
    return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) +
           ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
  };
  Rng rng(17);
  for (int i = 0; i < 2000; ++i) {
    const float u = 8.0f * rng.next_float() - 4.0f, v = 8.0f * rng.next_float() - 4.0f;
    const Color c = img.sample_bilinear(u, v);
    for (int ch = 0; ch < 3; ++ch)
      ASSERT_NEAR(c[ch], reference(u, v, ch), 1e-5) << u << " " << v << " channel " << ch;
  }
  // Non-finite coordinates read the lookup at 0 instead of indexing out of the image.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(img.sample_bilinear(nan, 0.5f), img.sample_bilinear(0.0f, 0.5f));
  EXPECT_EQ(img.sample_bilinear(0.5f, inf), img.sample_bilinear(0.5f, 0.0f));
  EXPECT_EQ(img.sample_bilinear(-inf, nan), img.sample_bilinear(0.0f, 0.0f));
}

}  // namespace
}  // namespace illum
