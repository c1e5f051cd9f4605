// Reading images: a file's bytes are checked first (image_checks.h: structure, declared size
// against the bytes that hold it), then decoded from memory by stb (PNG, JPEG, Radiance HDR)
// or OpenEXR, so the decoder sees exactly the bytes that were checked. Float images must hold
// finite values.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include <OpenEXR/IexBaseExc.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <stb_image.h>

#include "illum/core/image.h"
#include "illum/core/image_checks.h"

namespace illum {

namespace fs = std::filesystem;

namespace {

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

const char* stb_reason() {
  const char* reason = stbi_failure_reason();
  return reason ? reason : "unknown error";
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// The decoder must agree with the checked header; if it does not, the checks did not see
// what the decoder read, and the image is refused rather than trusted.
void expect_size(const std::string& name, int w, int h, int checked_w, int checked_h) {
  if (w != checked_w || h != checked_h)
    throw Error(fmt::format("{}: the decoder read a {}×{} image where the header says {}×{}", name,
                            w, h, checked_w, checked_h));
}

Image decode_stb_ldr(std::span<const uint8_t> bytes, const std::string& name, bool srgb,
                     int checked_w, int checked_h) {
  const auto* data = bytes.data();
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, n = 0;
  const bool sixteen = stbi_is_16_bit_from_memory(data, size) != 0;
  std::unique_ptr<void, StbFree> pixels(
      sixteen ? static_cast<void*>(stbi_load_16_from_memory(data, size, &w, &h, &n, 0))
              : static_cast<void*>(stbi_load_from_memory(data, size, &w, &h, &n, 0)));
  if (!pixels) throw Error(fmt::format("{}: cannot read image ({})", name, stb_reason()));
  expect_size(name, w, h, checked_w, checked_h);
  Image image(w, h, n);
  const float scale = sixteen ? 1.0f / 65535.0f : 1.0f / 255.0f;
  auto value = [&](float stored, bool colour) {
    const float v = stored * scale;
    return srgb && colour ? srgb_decode(v) : v;
  };
  auto& out = image.data();
  for (size_t i = 0; i < out.size(); ++i) {
    const float stored = static_cast<float>(sixteen ? static_cast<const uint16_t*>(pixels.get())[i]
                                                    : static_cast<const uint8_t*>(pixels.get())[i]);
    out[i] = value(stored, !is_alpha_channel(static_cast<int>(i % static_cast<size_t>(n)), n));
  }
  if (!sixteen) {
    // The bytes too, for texture lookups (Image::keep_bytes): each colour value is
    // byte_values[byte], computed by the same expression as above. One table per encoding,
    // filled once (thread-safe static initialisation) and alive for the program.
    static const std::array<float, 256> srgb_values = [] {
      std::array<float, 256> t{};
      for (int b = 0; b < 256; ++b) t[b] = srgb_decode(static_cast<float>(b) * (1.0f / 255.0f));
      return t;
    }();
    static const std::array<float, 256> linear_values = [] {
      std::array<float, 256> t{};
      for (int b = 0; b < 256; ++b) t[b] = static_cast<float>(b) * (1.0f / 255.0f);
      return t;
    }();
    const auto* first = static_cast<const uint8_t*>(pixels.get());
    image.keep_bytes(std::vector<uint8_t>(first, first + out.size()),
                     srgb ? srgb_values.data() : linear_values.data());
  }
  return image;
}

Image decode_stb_hdr(std::span<const uint8_t> bytes, const std::string& name, int checked_w,
                     int checked_h) {
  int w = 0, h = 0, n = 0;
  std::unique_ptr<float, StbFree> pixels(
      stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n, 0));
  if (!pixels) throw Error(fmt::format("{}: cannot read image ({})", name, stb_reason()));
  expect_size(name, w, h, checked_w, checked_h);
  Image image(w, h, n);
  std::copy_n(pixels.get(), image.data().size(), image.data().begin());
  return image;
}

// OpenEXR reads through this from the bytes already in memory; reading past the end is an
// exception, as with OpenEXR's own file streams.
class MemoryStream final : public Imf::IStream {
 public:
  MemoryStream(std::span<const uint8_t> bytes, const std::string& name)
      : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || static_cast<uint64_t>(n) > bytes_.size() - pos_)
      throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, bytes_.data() + pos_, static_cast<size_t>(n));
    pos_ += static_cast<size_t>(n);
    return pos_ < bytes_.size();
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override {
    pos_ = static_cast<size_t>(std::min<uint64_t>(pos, bytes_.size()));
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
};

// R, G, B (all three) or Y, or a single other channel read as grey; A when present.
std::vector<std::string> exr_channels_to_read(const image_checks::ExrInfo& info,
                                              const std::string& name) {
  auto has = [&](const char* channel) {
    return std::any_of(info.channels.begin(), info.channels.end(),
                       [&](const image_checks::ExrChannel& c) { return c.name == channel; });
  };
  std::vector<std::string> names;
  if (has("R") || has("G") || has("B")) {
    for (const char* channel : {"R", "G", "B"})
      if (!has(channel))
        throw Error(fmt::format("{}: the OpenEXR file has some of channels R, G, B but not {}",
                                name, channel));
    names = {"R", "G", "B"};
  } else if (has("Y")) {
    names = {"Y"};
  } else {
    std::vector<std::string> others;
    for (const auto& c : info.channels)
      if (c.name != "A") others.push_back(c.name);
    if (others.size() != 1)
      throw Error(
          fmt::format("{}: the OpenEXR file has no R, G, B or Y channel and {} others (illum "
                      "reads one as grey)",
                      name, others.size()));
    names = others;
  }
  if (has("A")) names.emplace_back("A");
  return names;
}

Image decode_exr(std::span<const uint8_t> bytes, const std::string& name,
                 const image_checks::ExrInfo& info) {
  const std::vector<std::string> names = exr_channels_to_read(info, name);
  MemoryStream stream(bytes, name);
  Imf::InputFile file(stream);
  const Imath::Box2i dw = file.header().dataWindow();
  expect_size(name, dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1, info.width, info.height);
  const int channels = static_cast<int>(names.size());
  Image image(info.width, info.height, channels);
  Imf::FrameBuffer fb;
  const size_t x_stride = sizeof(float) * static_cast<size_t>(channels);
  for (int c = 0; c < channels; ++c)
    fb.insert(names[static_cast<size_t>(c)],
              Imf::Slice::Make(Imf::FLOAT, image.data().data() + c, dw, x_stride,
                               x_stride * static_cast<size_t>(info.width)));
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return image;
}

// NaN or infinity in a texture or an environment map poisons every estimate that samples it
// (and the environment's importance-sampling distribution): refused where it is read.
void check_finite(const Image& image, const std::string& name) {
  const auto& data = image.data();
  const auto bad =
      std::find_if(data.begin(), data.end(), [](float v) { return !std::isfinite(v); });
  if (bad == data.end()) return;
  const size_t i = static_cast<size_t>(bad - data.begin());
  const size_t texel = i / static_cast<size_t>(image.channels());
  throw Error(fmt::format(
      "{}: texel ({}, {}) channel {} is {} (float images must be finite)", name,
      texel % static_cast<size_t>(image.width()), texel / static_cast<size_t>(image.width()),
      i % static_cast<size_t>(image.channels()), std::isnan(*bad) ? "NaN" : "infinite"));
}

}  // namespace

Image decode_image(std::span<const uint8_t> bytes, const std::string& name, bool srgb) {
  if (bytes.empty()) throw Error(fmt::format("{}: empty image file", name));
  if (bytes.size() > static_cast<size_t>(INT_MAX))
    throw Error(fmt::format("{}: {} bytes, larger than illum reads (2 GiB)", name, bytes.size()));
  const auto format = image_checks::sniff_format(bytes);
  if (!format)
    throw Error(
        fmt::format("{}: not a PNG, JPEG, Radiance HDR or OpenEXR image (unknown first "
                    "bytes)",
                    name));
  try {
    switch (*format) {
      case ImageFormat::kPng: {
        const auto info = image_checks::check_png(bytes, name);
        return decode_stb_ldr(bytes, name, srgb, info.width, info.height);
      }
      case ImageFormat::kJpeg: {
        const auto info = image_checks::check_jpeg(bytes, name);
        return decode_stb_ldr(bytes, name, srgb, info.width, info.height);
      }
      case ImageFormat::kHdr: {
        const auto info = image_checks::check_hdr(bytes, name);
        Image image = decode_stb_hdr(bytes, name, info.width, info.height);
        check_finite(image, name);
        return image;
      }
      case ImageFormat::kExr: {
        const auto info = image_checks::check_exr(bytes, name);
        Image image = decode_exr(bytes, name, info);
        check_finite(image, name);
        return image;
      }
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    // OpenEXR's exceptions, std::bad_alloc: still one line naming the image.
    throw Error(fmt::format("{}: cannot read image ({})", name, one_line(e.what())));
  }
  throw Error(fmt::format("{}: cannot read image", name));
}

Image read_image(const std::string& path, bool srgb) {
  image_format_from_path(path);  // the extension must name a known format
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error(fmt::format("{}: no such image file", path));
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(fmt::format("{}: cannot read image ({})", path, ec.message()));
  if (size > static_cast<uintmax_t>(INT_MAX))
    throw Error(fmt::format("{}: {} bytes, larger than illum reads (2 GiB)", path, size));
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!in || in.gcount() != static_cast<std::streamsize>(bytes.size()))
    throw Error(fmt::format("{}: cannot read image (read error)", path));
  return decode_image(bytes, path, srgb);
}

}  // namespace illum
