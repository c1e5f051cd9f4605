// Images through illum::read_image. read_image picks the decoder from the file name, so the
// harness names the file after the input's magic bytes (PNG, JPEG, Radiance HDR, OpenEXR);
// an input with none of them goes to the decoder its first byte selects, so every decoder
// also sees arbitrary bytes. 8-bit files are read as colour (sRGB-decoded) when the input's
// length is even and as linear data when it is odd: both paths of read_image.
#include <cstring>
#include <string_view>

#include "fuzz_support.h"
#include "illum/core/image.h"

using namespace illum;

namespace {

const char* extension_for(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.starts_with("\x89PNG")) return ".png";
  if (bytes.starts_with("\xFF\xD8")) return ".jpg";
  if (bytes.starts_with("#?")) return ".hdr";
  if (bytes.starts_with("v/1\x01")) return ".exr";
  static const char* const kAll[4] = {".png", ".jpg", ".hdr", ".exr"};
  return kAll[size ? data[0] % 4 : 0];
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = fuzz::scratch_dir() / (std::string("image") + extension_for(data, size));
  fuzz::write_file(file, {reinterpret_cast<const char*>(data), size});
  fuzz::expect_only_illum_errors([&] { read_image(file.string(), size % 2 == 0); });
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
  return 0;
}
