// The atlas file: exact round trip, atomic writes, and a clear Error for every kind of bad
// file (missing, truncated at every length, wrong magic or version, out-of-range values).
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "atlas_check.h"
#include "illum/atlas/atlas.h"
#include "illum/core/error.h"

namespace illum::atlas {
namespace {

namespace fs = std::filesystem;

class AtlasFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ =
        fs::temp_directory_path() / fmt::format("illum_atlas_{}_{}", info->name(), ::getpid());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(folder_, ec);
  }
  fs::path file(const std::string& name) const { return folder_ / name; }
  std::string read(const fs::path& path) const {
    std::string bytes(fs::file_size(path), '\0');
    std::ifstream(path, std::ios::binary).read(bytes.data(), std::streamsize(bytes.size()));
    return bytes;
  }
  fs::path write(const std::string& name, const std::string& bytes) const {
    std::ofstream(file(name), std::ios::binary) << bytes;
    return file(name);
  }
  std::string error_loading(const std::string& bytes) const {
    const fs::path path = write("bad.atlas", bytes);
    try {
      load_atlas(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }

  fs::path folder_;
};

// A small atlas with every feature: several charts, a degenerate triangle's point chart,
// and a mesh without instance (kNoChart). `grid` quads per side in the first mesh.
Atlas sample_atlas(int grid_size = 2) {
  Mesh grid = test::split_grid(grid_size);
  grid.indices.insert(grid.indices.end(), {0, 0, 1});
  Mesh tilted = test::split_grid(1);
  Scene scene = test::make_scene(
      {grid, tilted, test::split_grid(1)},
      {mat4(1.0f), glm::rotate(mat4(1.0f), radians(90.0f), vec3(0.0f, 0.0f, 1.0f))});
  scene.instances.pop_back();
  AtlasOptions options;
  options.resolution = 64;
  return build_atlas(scene, options);
}

void expect_equal(const Atlas& a, const Atlas& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(std::memcmp(&a.texel_size, &b.texel_size, sizeof(float)), 0);
  EXPECT_EQ(a.chart_count, b.chart_count);
  ASSERT_EQ(a.charts.size(), b.charts.size());
  for (size_t c = 0; c < a.charts.size(); ++c) {
    EXPECT_EQ(a.charts[c].mesh, b.charts[c].mesh);
    EXPECT_EQ(a.charts[c].x, b.charts[c].x);
    EXPECT_EQ(a.charts[c].y, b.charts[c].y);
    EXPECT_EQ(a.charts[c].width, b.charts[c].width);
    EXPECT_EQ(a.charts[c].height, b.charts[c].height);
  }
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t m = 0; m < a.meshes.size(); ++m) {
    EXPECT_EQ(a.meshes[m].source_vertex_count, b.meshes[m].source_vertex_count);
    EXPECT_EQ(a.meshes[m].source_vertex, b.meshes[m].source_vertex);
    ASSERT_EQ(a.meshes[m].uv1.size(), b.meshes[m].uv1.size());
    // Bit for bit.
    EXPECT_EQ(std::memcmp(a.meshes[m].uv1.data(), b.meshes[m].uv1.data(),
                          a.meshes[m].uv1.size() * sizeof(vec2)),
              0);
    EXPECT_EQ(a.meshes[m].indices, b.meshes[m].indices);
    EXPECT_EQ(a.meshes[m].triangle_chart, b.meshes[m].triangle_chart);
  }
}

TEST_F(AtlasFile, RoundTripIsExact) {
  const Atlas atlas = sample_atlas();
  ASSERT_GE(atlas.chart_count, 3);
  const fs::path path = file("scene.atlas");
  save_atlas(atlas, path);
  expect_equal(atlas, load_atlas(path));
  // Written through a temporary name: nothing else is left in the folder.
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder_)) ++files;
  EXPECT_EQ(files, 1u);
  // The header is what the format says.
  const std::string bytes = read(path);
  EXPECT_EQ(bytes.substr(0, 8), "ILLUMATL");
  EXPECT_EQ(bytes[8], 1);  // version 1, little-endian
  EXPECT_EQ(bytes[9], 0);
  // Saving again replaces the file.
  Atlas changed = atlas;
  changed.texel_size *= 2.0f;
  save_atlas(changed, path);
  EXPECT_EQ(load_atlas(path).texel_size, changed.texel_size);

  // A hand-made atlas without chart rectangles or triangle charts round-trips too.
  Atlas plain;
  plain.width = plain.height = 32;
  plain.texel_size = 0.5f;
  plain.meshes.resize(1);
  plain.meshes[0] = {{0, 1, 2}, {vec2(0.1f), vec2(0.2f, 0.1f), vec2(0.1f, 0.2f)}, {0, 1, 2}, 3, {}};
  save_atlas(plain, file("plain.atlas"));
  expect_equal(plain, load_atlas(file("plain.atlas")));
}

TEST_F(AtlasFile, MissingFileOrFolder) {
  std::string message;
  try {
    load_atlas(file("nope.atlas"));
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("nope.atlas"), std::string::npos) << message;
  message.clear();
  try {
    save_atlas(sample_atlas(), folder_ / "missing" / "x.atlas");
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("x.atlas"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(folder_ / "missing"));
}

TEST_F(AtlasFile, EveryTruncationIsAnError) {
  const Atlas atlas = sample_atlas(1);
  save_atlas(atlas, file("good.atlas"));
  const std::string bytes = read(file("good.atlas"));
  for (size_t length = 0; length < bytes.size(); ++length) {
    const std::string message = error_loading(bytes.substr(0, length));
    EXPECT_FALSE(message.empty()) << "a file cut to " << length << " bytes loaded";
    EXPECT_NE(message.find("bad.atlas"), std::string::npos) << message;
  }
  // And so is anything appended.
  EXPECT_NE(error_loading(bytes + "x").find("unexpected bytes"), std::string::npos);
}

// Offsets in the file of the sample atlas (see atlas_file.cpp for the layout).
struct Layout {
  size_t mesh0;  // first byte of mesh 0's header
  size_t source_vertex0, uv10, indices0, charts0;
};
Layout layout_of(const Atlas& atlas) {
  Layout l;
  l.mesh0 = 8 + 6 * 4 + 20 * atlas.charts.size();
  const size_t v = atlas.meshes[0].source_vertex.size();
  l.source_vertex0 = l.mesh0 + 16;
  l.uv10 = l.source_vertex0 + 4 * v;
  l.indices0 = l.uv10 + 8 * v;
  l.charts0 = l.indices0 + 4 * atlas.meshes[0].indices.size();
  return l;
}

void put_u32(std::string& bytes, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = char((v >> (8 * i)) & 0xff);
}

TEST_F(AtlasFile, MalformedContentsAreErrors) {
  const Atlas atlas = sample_atlas();
  save_atlas(atlas, file("good.atlas"));
  const std::string good = read(file("good.atlas"));
  const Layout l = layout_of(atlas);
  const uint32_t vertices = uint32_t(atlas.meshes[0].source_vertex.size());
  struct Case {
    std::string what;
    size_t at;
    uint32_t value;
    std::string expected;  // in the message
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Case> cases = {
      {"wrong magic", 0, 0x4c4c4958u, "magic"},
      {"wrong version", 8, 2, "version 2"},
      {"zero width", 12, 0, "size"},
      {"negative texel size", 20, std::bit_cast<uint32_t>(-1.0f), "texel size"},
      {"huge chart count", 24, 0xffffffffu, "chart"},
      {"huge mesh count", 28, 0xfffffff0u, "truncated"},
      {"chart outside", 8 + 6 * 4 + 4, 60, "outside"},
      {"chart of missing mesh", 8 + 6 * 4, 7, "mesh 7"},
      {"huge vertex count", l.mesh0 + 4, 0x7fffffffu, "truncated"},
      {"index count not a multiple of 3", l.mesh0 + 8, uint32_t(atlas.meshes[0].indices.size() - 1),
       ""},
      {"source vertex out of range", l.source_vertex0, atlas.meshes[0].source_vertex_count,
       "source vertex"},
      {"uv1 outside [0,1]", l.uv10, std::bit_cast<uint32_t>(1.5f), "outside [0,1]"},
      {"uv1 NaN", l.uv10 + 4, std::bit_cast<uint32_t>(nan), "uv1"},
      {"index out of range", l.indices0, vertices, "uses vertex"},
      {"chart index out of range", l.charts0, 1000, "chart 1000"},
  };
  for (const Case& c : cases) {
    std::string bytes = good;
    put_u32(bytes, c.at, c.value);
    const std::string message = error_loading(bytes);
    EXPECT_FALSE(message.empty()) << c.what << " loaded";
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    EXPECT_NE(message.find("bad.atlas"), std::string::npos) << c.what << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST_F(AtlasFile, InconsistentAtlasIsNotSaved) {
  Atlas atlas = sample_atlas();
  atlas.meshes[0].indices[0] = 100000;
  const fs::path path = file("x.atlas");
  bool threw = false;
  try {
    save_atlas(atlas, path);
  } catch (const Error& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("uses vertex"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(threw);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace illum::atlas
