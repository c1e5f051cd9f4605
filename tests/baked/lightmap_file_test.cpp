// The light-map folder (lightmap.json, atlas.bin, layer EXRs): a written set reads back, and
// every way a folder can be wrong is one illum::Error naming the file: the manifest's JSON,
// types and values, the atlas, and the layers (size, channels, NaN, truncation).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "illum/baked/lightmap_file.h"
#include "illum/core/error.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"

namespace illum::baked {
namespace {

namespace fs = std::filesystem;

class LightmapFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / fmt::format("illum_lmfile_{}_{}", info->name(), ::getpid());
    fs::remove_all(root_);
    fs::create_directories(root_);
    LightmapSet set;
    set.atlas.width = 8;
    set.atlas.height = 4;
    set.atlas.texel_size = 0.25f;
    set.basis = "plain";
    set.scene = "nothing";
    set.scene_triangles = 0;
    Image layer(8, 4, 3);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x) layer.set_rgb(x, y, Color(0.125f * x, 0.25f * y, 1.0f));
    set.layers = {layer};
    save_lightmap_set(folder(), set);
    manifest_ = nlohmann::json::parse(std::ifstream(folder() / "lightmap.json"));
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  fs::path folder() const { return root_ / "lm"; }
  void write_manifest(const nlohmann::json& j) const {
    std::ofstream(folder() / "lightmap.json") << j.dump();
  }
  void write_manifest_text(const std::string& text) const {
    std::ofstream(folder() / "lightmap.json") << text;
  }
  // load_lightmap_set's Error message ("" and a failure if it loads).
  std::string error() const {
    try {
      load_lightmap_set(folder());
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      return m;
    }
    ADD_FAILURE() << "the folder loaded";
    return "";
  }
  fs::path root_;
  nlohmann::json manifest_;
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST_F(LightmapFolder, WrittenSetReadsBack) {
  const LightmapSet back = load_lightmap_set(folder());
  EXPECT_EQ(back.atlas.width, 8);
  ASSERT_EQ(back.layers.size(), 1u);
  EXPECT_EQ(back.layers[0].rgb(3, 2), Color(0.375f, 0.5f, 1.0f));  // exact in half
}

TEST_F(LightmapFolder, ManifestTypesAndValuesAreChecked) {
  const std::string manifest = (folder() / "lightmap.json").string();
  const struct {
    const char* key;
    nlohmann::json value;
    const char* expected;
  } cases[] = {
      {"version", "1", "'version' must be an integer"},
      {"version", 1.5, "'version' must be an integer"},
      {"version", 2, "'version' is 2, but this illum reads illum-lightmap version 1"},
      {"format", 7, "'format' must be a string"},
      {"basis", "rgb", "'basis' must be one of plain, rnm, sh, dominant, none, not \"rgb\""},
      {"content", nullptr, "'content' must be a string"},
      {"scene_triangles", -1, "'scene_triangles' must be an integer"},
      {"scene_triangles", 1e300, "'scene_triangles' must be an integer"},
      {"scene_hash", 7, "'scene_hash' must be a string"},
      {"scene_hash", "0123456789ABCDEF", "'scene_hash' must be 16 lowercase hex digits"},
      {"scene_hash", "0123456789abcde", "'scene_hash' must be 16 lowercase hex digits"},
      {"layers", "layer0.exr", "'layers' must be a list"},
      {"layers", {"layer0.exr", "layer0.exr"}, "'layers' lists 2, but basis 'plain' needs 1"},
      {"layers", {"../lm/layer0.exr"}, "must be a file in the folder"},
      {"layers", {42}, "'layers' must be a file name"},
      {"atlas", "/etc/passwd", "must be a file in the folder"},
      {"atlas", "..", "must be a file in the folder"},
      {"width", 16, "'width' is 16, but the atlas says 8"},
      {"charts", 1u << 31, "'charts' must be an integer"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(fmt::format("{} = {}", c.key, c.value.dump()));
    nlohmann::json j = manifest_;
    j[c.key] = c.value;
    write_manifest(j);
    const std::string m = error();
    EXPECT_TRUE(contains(m, manifest)) << m;
    EXPECT_TRUE(contains(m, c.expected)) << m;
  }
  nlohmann::json without = manifest_;
  without.erase("scene_triangles");
  write_manifest(without);
  EXPECT_TRUE(contains(error(), "'scene_triangles' is missing"));
  write_manifest_text("[1, 2, 3]");
  EXPECT_TRUE(contains(error(), "must be a JSON object"));
  write_manifest_text(R"({"format": "illum-lightmap", "version": )");
  EXPECT_TRUE(contains(error(), "malformed JSON"));
  // Deep nesting is refused before parsing, like any JSON a user hands in: the manifest's
  // "bake" object is copied into the set, and nlohmann copies recursively.
  write_manifest_text(std::string(200000, '[') + std::string(200000, ']'));
  EXPECT_TRUE(contains(error(), "nested deeper than 128 levels"));
  std::string deep_bake = manifest_.dump();
  deep_bake.insert(deep_bake.size() - 1, R"(, "bake": {"x": )" + std::string(100000, '[') +
                                             std::string(100000, ']') + "}");
  write_manifest_text(deep_bake);
  EXPECT_TRUE(contains(error(), "nested deeper than 128 levels"));
}

TEST_F(LightmapFolder, LayersAreChecked) {
  const std::string layer = (folder() / "layer0.exr").string();
  write_image(layer, Image(4, 4, 3, 0.5f));
  EXPECT_TRUE(contains(error(), "4x4, but the atlas is 8x4"));
  write_image(layer, Image(8, 4, 1, 0.5f));
  EXPECT_TRUE(contains(error(), "1 channels, but light-map layers are RGB"));
  Image nan(8, 4, 3, 0.5f);
  nan.pixel(5, 3)[2] = std::numeric_limits<float>::quiet_NaN();
  write_image(layer, nan);
  const std::string m = error();
  EXPECT_TRUE(contains(m, layer) && contains(m, "texel (5, 3) channel 2 is NaN")) << m;
  write_image(layer, Image(8, 4, 3, 0.5f));
  fs::resize_file(layer, fs::file_size(layer) - 10);
  EXPECT_TRUE(contains(error(), layer));
  fs::remove(layer);
  EXPECT_TRUE(contains(error(), layer));
}

TEST_F(LightmapFolder, AtlasFileIsChecked) {
  // A vertex count of 2^31 in a file of a few bytes: refused before anything is allocated.
  std::ofstream(folder() / "atlas.bin", std::ios::binary | std::ios::trunc)
      << std::string("ILLUMATL\x01\0\0\0\x08\0\0\0\x04\0\0\0\0\0\x80\x3e\0\0\0\0\x01\0\0\0", 32)
      << std::string("\x00\0\0\0\x00\0\0\x80\0\0\0\0\0\0\0\0", 16);
  const std::string m = error();
  EXPECT_TRUE(contains(m, (folder() / "atlas.bin").string()) && contains(m, "truncated")) << m;
}

// apply_lightmap_set checks the recorded scene hash against the scene with the atlas
// applied; a refused set (no hash, another hash) leaves the scene exactly as it was.
TEST(LightmapSetApply, RefusedSetsLeaveTheSceneUnchanged) {
  const Scene loaded = load_scene(ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json");
  Scene baked = loaded;
  atlas::make_meshes_unique(baked);
  atlas::AtlasOptions options;
  options.resolution = 64;
  LightmapSet set;
  set.atlas = atlas::build_atlas(baked, options);
  atlas::apply_atlas(baked, set.atlas);
  set.scene = "cornell";
  set.scene_triangles = baked.triangle_count();
  set.folder = "lm";
  const auto same_geometry = [&](const Scene& s) {
    ASSERT_EQ(s.meshes.size(), loaded.meshes.size());
    ASSERT_EQ(s.instances.size(), loaded.instances.size());
    for (size_t i = 0; i < s.meshes.size(); ++i) {
      EXPECT_EQ(s.meshes[i].positions, loaded.meshes[i].positions) << i;
      EXPECT_EQ(s.meshes[i].uv1, loaded.meshes[i].uv1) << i;
    }
    for (size_t i = 0; i < s.instances.size(); ++i)
      EXPECT_EQ(s.instances[i].mesh, loaded.instances[i].mesh) << i;
  };
  for (const std::string& hash : {std::string(), std::string("0123456789abcdef")}) {
    SCOPED_TRACE("hash '" + hash + "'");
    set.scene_hash = hash;
    Scene shown = loaded;
    try {
      apply_lightmap_set(shown, set);
      ADD_FAILURE() << "applied";
    } catch (const Error& e) {
      EXPECT_TRUE(contains(e.what(), "lm: ")) << e.what();
      EXPECT_TRUE(contains(e.what(), "bake it again")) << e.what();
    }
    same_geometry(shown);
  }
  set.scene_hash = geometry_hash_hex(baked);
  Scene shown = loaded;
  apply_lightmap_set(shown, set);
  EXPECT_EQ(geometry_hash(shown), geometry_hash(baked));
}

}  // namespace
}  // namespace illum::baked
