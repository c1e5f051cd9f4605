// The seam tests' figures (docs/lightmaps.md, Seams and leaks): written only when
// ILLUM_SEAMS_IMAGES names a folder, so a plain test run writes nothing.
#pragma once

#include <cstdlib>
#include <string>

#include "illum/core/image.h"

namespace illum::test {

inline void write_seam_figure(const std::string& name, const Image& image) {
  const char* dir = std::getenv("ILLUM_SEAMS_IMAGES");
  if (!dir) return;
  ImageWriteOptions o;
  o.exposure = 1.0f;
  write_image(std::string(dir) + "/" + name, image, o);
}

}  // namespace illum::test
