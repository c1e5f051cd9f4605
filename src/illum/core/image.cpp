#include "illum/core/image.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <stb_image_write.h>

#include "illum/core/file_write.h"

namespace illum {

namespace fs = std::filesystem;

Image::Image(int width, int height, int channels, float fill)
    : width_(width), height_(height), channels_(channels) {
  ILLUM_CHECK(width >= 0 && height >= 0, "negative image size {}x{}", width, height);
  ILLUM_CHECK(channels >= 1 && channels <= 4, "images have 1 to 4 channels, not {}", channels);
  data_.assign(static_cast<size_t>(width) * height * channels, fill);
}

void Image::keep_bytes(std::vector<uint8_t> bytes, const float* byte_values) {
  ILLUM_CHECK(bytes.size() == data_.size() && byte_values, "{} bytes for {} values", bytes.size(),
              data_.size());
  bytes_ = std::move(bytes);
  byte_values_ = byte_values;
}

Color Image::rgb(int x, int y) const {
  const float* p = pixel(x, y);
  return channels_ >= 3 ? Color(p[0], p[1], p[2]) : Color(p[0]);
}

void Image::set_rgb(int x, int y, const Color& c) {
  float* p = pixel(x, y);
  if (channels_ >= 3) {
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  } else {
    p[0] = luminance(c);  // grey images keep the luminance
  }
  if (channels_ == 2 || channels_ == 4) p[channels_ - 1] = 1.0f;
}

ImageFormat image_format_from_path(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return ImageFormat::kPng;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::kJpeg;
  if (ext == ".hdr") return ImageFormat::kHdr;
  if (ext == ".exr") return ImageFormat::kExr;
  throw Error(
      fmt::format("{}: unsupported image format '{}' (use .png, .jpg, .hdr or .exr)", path, ext));
}

// ---------------------------------------------------------------------------------------
// Writing

namespace {

// The encoders write into memory; write_file_atomically then puts the bytes on disk and
// checks that every one arrived (stb's own fwrite path cannot tell a full disk).
void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* p = static_cast<const uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

// OpenEXR's output stream, in memory.
class MemoryOStream : public Imf::OStream {
 public:
  explicit MemoryOStream(std::vector<uint8_t>* out) : Imf::OStream("memory"), out_(out) {}
  void write(const char c[], int n) override {
    const size_t end = position_ + static_cast<size_t>(n);
    if (end > out_->size()) out_->resize(end);
    std::memcpy(out_->data() + position_, c, static_cast<size_t>(n));
    position_ = end;
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t pos) override { position_ = static_cast<size_t>(pos); }

 private:
  std::vector<uint8_t>* out_;
  size_t position_ = 0;
};

void write_stb_ldr(std::vector<uint8_t>* out, ImageFormat format, const Image& image,
                   const ImageWriteOptions& options, bool* ok) {
  const int n = image.channels();
  std::vector<uint8_t> bytes(image.data().size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    const bool colour = !is_alpha_channel(static_cast<int>(i % static_cast<size_t>(n)), n);
    float v = image.data()[i];
    if (colour) v *= options.exposure;
    if (!(v >= 0.0f)) v = 0.0f;  // also maps NaN to black
    v = std::min(v, 1.0f);
    if (colour && options.srgb) v = srgb_encode(v);
    bytes[i] = static_cast<uint8_t>(v * 255.0f + 0.5f);
  }
  if (format == ImageFormat::kPng)
    *ok = stbi_write_png_to_func(append_bytes, out, image.width(), image.height(), n, bytes.data(),
                                 image.width() * n) != 0;
  else
    *ok = stbi_write_jpg_to_func(append_bytes, out, image.width(), image.height(), n, bytes.data(),
                                 std::clamp(options.jpeg_quality, 1, 100)) != 0;
}

void write_stb_hdr(std::vector<uint8_t>* out, const Image& image, bool* ok) {
  // RGBE cannot store negative or non-finite values.
  std::vector<float> data(image.data());
  for (float& v : data) v = std::isfinite(v) ? std::max(v, 0.0f) : 0.0f;
  *ok = stbi_write_hdr_to_func(append_bytes, out, image.width(), image.height(), image.channels(),
                               data.data()) != 0;
}

void write_exr(std::vector<uint8_t>* out, const Image& image, bool half) {
  const int n = image.channels();
  static const char* const kNames[4][4] = {
      {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  const char* const* names = kNames[n - 1];
  const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
  Imf::Header header(image.width(), image.height());
  for (int c = 0; c < n; ++c) header.channels().insert(names[c], Imf::Channel(type));
  std::vector<Imath::half> halves;
  const char* base = reinterpret_cast<const char*>(image.data().data());
  size_t element = sizeof(float);
  if (half) {
    halves.assign(image.data().begin(), image.data().end());
    base = reinterpret_cast<const char*>(halves.data());
    element = sizeof(Imath::half);
  }
  const size_t x_stride = element * static_cast<size_t>(n);
  Imf::FrameBuffer fb;
  for (int c = 0; c < n; ++c)
    fb.insert(names[c], Imf::Slice(type, const_cast<char*>(base + element * static_cast<size_t>(c)),
                                   x_stride, x_stride * static_cast<size_t>(image.width())));
  MemoryOStream stream(out);
  Imf::OutputFile file(stream, header);
  file.setFrameBuffer(fb);
  file.writePixels(image.height());
}

}  // namespace

void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options) {
  const ImageFormat format = image_format_from_path(path);
  if (image.empty()) throw Error(fmt::format("{}: cannot write an empty image", path));
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(
        fmt::format("{}: cannot write image: folder '{}' does not exist", path, folder.string()));
  std::vector<uint8_t> bytes;
  std::string failure;
  try {
    bool ok = true;
    switch (format) {
      case ImageFormat::kPng:
      case ImageFormat::kJpeg:
        write_stb_ldr(&bytes, format, image, options, &ok);
        break;
      case ImageFormat::kHdr:
        write_stb_hdr(&bytes, image, &ok);
        break;
      case ImageFormat::kExr:
        // OutputFile writes its offset table when it is destroyed: scoped here.
        write_exr(&bytes, image, options.exr_half);
        break;
    }
    if (!ok) failure = "the encoder could not write the file";
  } catch (const std::exception& e) {
    failure = e.what();
  }
  if (!failure.empty()) throw Error(fmt::format("{}: cannot write image ({})", path, failure));
  write_file_atomically(path, bytes);
}

}  // namespace illum
