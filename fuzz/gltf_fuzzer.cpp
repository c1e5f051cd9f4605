// glTF 2.0 through illum::load_scene. An input starting with the GLB magic "glTF" is written
// as scene.glb (one self-contained file: JSON chunk + BIN chunk), anything else as scene.gltf
// (JSON; buffers as data: URIs inside it, or the fixed companion buffer.bin; images may name
// the companion textures).
#include <cstring>

#include "fuzz_support.h"
#include "illum/scene/load.h"

using namespace illum;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  fuzz::write_texture_companions(fuzz::scratch_dir());
  fuzz::write_mesh_companions(fuzz::scratch_dir());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& dir = fuzz::scratch_dir();
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto file = dir / (binary ? "scene.glb" : "scene.gltf");
  fuzz::write_file(file, {reinterpret_cast<const char*>(data), size});
  fuzz::expect_only_illum_errors([&] { load_scene(file.string()); });
  return 0;
}
