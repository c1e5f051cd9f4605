// illum scene files (.illum.json) through illum::load_scene. The input is written as
// scene.illum.json; the meshes, textures and environment maps it names come from the fixed
// companions (mesh.obj with materials "white" and "light" and objects "floor" and "lamp",
// mesh.gltf, tex.png, env.hdr, env.exr, ...; fuzz_support.h), so the fuzzer spends its time on
// the scene file's own keys and values.
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
  const auto file = fuzz::scratch_dir() / "scene.illum.json";
  fuzz::write_file(file, {reinterpret_cast<const char*>(data), size});
  fuzz::expect_only_illum_errors([&] { load_scene(file.string()); });
  return 0;
}
