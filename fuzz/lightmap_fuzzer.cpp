// The baked light-map folder through illum::baked::load_lightmap_set, then
// apply_lightmap_set on the built-in Cornell box, as `illum frame --lightmap` does. The input
// is the manifest (lightmap.json), optionally followed by kNextFile and the atlas file
// (atlas.bin); without a second part atlas.bin does not exist. The layers are fixed
// companions: layer0.exr … layer3.exr, 16×16 RGB (the size of the seeds' atlas), plus
// tex.png/tex.hdr for manifests that name other images.

#include "fuzz_support.h"
#include "illum/baked/lightmap_file.h"
#include "illum/core/image.h"
#include "illum/scene/load.h"

using namespace illum;

namespace {

const Scene& cornell() {
  static const Scene scene = [] {
    LoadOptions options;
    options.load_textures = false;
    return load_scene("cornell", options);
  }();
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  const auto& dir = fuzz::scratch_dir();
  fuzz::write_texture_companions(dir);
  Image layer(16, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      layer.set_rgb(x, y, Color(float(x) / 15.0f, float(y) / 15.0f, 0.5f));
  for (int i = 0; i < 4; ++i)
    write_image((dir / ("layer" + std::to_string(i) + ".exr")).string(), layer);
  cornell();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& dir = fuzz::scratch_dir();
  const auto parts = fuzz::split_files(data, size, 2);
  fuzz::write_file(dir / "lightmap.json", parts[0]);
  fuzz::write_or_remove(dir / "atlas.bin", parts.size() > 1 ? &parts[1] : nullptr);
  fuzz::expect_only_illum_errors([&] {
    const baked::LightmapSet set = baked::load_lightmap_set(dir);
    Scene scene = cornell();
    baked::apply_lightmap_set(scene, set);
  });
  return 0;
}
