// OBJ/MTL through illum::load_scene. The input is the OBJ text, optionally followed by
// kNextFile and the MTL text: the OBJ is written as scene.obj and the MTL as scene.mtl (so
// "mtllib scene.mtl" finds it; without a second part scene.mtl does not exist). Textures and
// a second material library come from the fixed companions (fuzz_support.h).
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
  const auto parts = fuzz::split_files(data, size, 2);
  fuzz::write_file(dir / "scene.obj", parts[0]);
  fuzz::write_or_remove(dir / "scene.mtl", parts.size() > 1 ? &parts[1] : nullptr);
  fuzz::expect_only_illum_errors([&] { load_scene((dir / "scene.obj").string()); });
  return 0;
}
