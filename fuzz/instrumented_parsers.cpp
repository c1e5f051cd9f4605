// The parsers' own code, compiled into the fuzz targets so libFuzzer sees their branches and
// ASan checks their memory accesses. illum links Debian's prebuilt libstb, libtinyobjloader
// and libtinygltf, which carry no coverage or ASan instrumentation; these are the same
// Debian headers (same package versions) built as their READMEs describe (one translation
// unit defining *_IMPLEMENTATION). Object files take precedence over shared libraries at link
// time, so every call, including tinygltf's calls into stb_image, reaches these copies.
// Writers (stb_image_write) still come from libstb: the harnesses only read.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_INCLUDE_STB_IMAGE  // already defined above
#include <tiny_gltf.h>
