// Extra maps in the light-map folder (lightmap.json "extras", ao.exr, obscurance.exr,
// obscurance_color.exr, bent_normal.exr): a written set reads back with its parameters, and
// a wrong entry or a map out of its range is one illum::Error naming the file.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "illum/baked/lightmap_file.h"
#include "illum/core/error.h"

namespace illum::baked {
namespace {

namespace fs = std::filesystem;

LightmapSet set_with_extras() {
  LightmapSet set;
  set.atlas.width = 4;
  set.atlas.height = 2;
  set.atlas.texel_size = 0.25f;
  set.scene = "nothing";
  set.layers = {Image(4, 2, 3, 0.5f)};
  Image grey(4, 2, 3, 0.75f), colour(4, 2, 3), bent(4, 2, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      colour.set_rgb(x, y, Color(0.25f, 0.5f, 1.0f));
      bent.set_rgb(x, y, x == 3 ? Color(0.0f) : Color(0.6f, 0.0f, 0.8f));  // 0: no chart
    }
  set.extras = {{"ao", grey, {{"distance", 0.5}, {"rays", 180}, {"seed", 3}}},
                {"obscurance", grey, {{"d_max", 0.3}}},
                {"obscurance_color", colour, {{"d_max", 0.3}}},
                {"bent_normal", bent, {{"distance", 0.5}}}};
  return set;
}

class LightmapExtrasFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ =
        fs::temp_directory_path() / fmt::format("illum_lmextras_{}_{}", info->name(), ::getpid());
    fs::remove_all(root_);
    fs::create_directories(root_);
    save_lightmap_set(folder(), set_with_extras());
    manifest_ = nlohmann::json::parse(std::ifstream(folder() / "lightmap.json"));
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  fs::path folder() const { return root_ / "lm"; }
  std::string error() const {
    try {
      load_lightmap_set(folder());
    } catch (const Error& e) {
      return e.what();
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

TEST_F(LightmapExtrasFolder, ExtrasReadBackWithTheirParameters) {
  const LightmapSet back = load_lightmap_set(folder());
  ASSERT_EQ(back.extras.size(), 4u);
  ASSERT_NE(back.extra("ao"), nullptr);
  EXPECT_EQ(back.extra("ao")->image.rgb(1, 1), Color(0.75f));
  EXPECT_EQ(back.extra("ao")->params.at("rays"), 180);
  EXPECT_EQ(back.extra("ao")->params.count("file"), 0u);
  EXPECT_EQ(back.extra("obscurance_color")->image.rgb(0, 0), Color(0.25f, 0.5f, 1.0f));
  EXPECT_EQ(back.extra("bent_normal")->image.rgb(3, 0), Color(0.0f));
  EXPECT_EQ(manifest_.at("extras").at("bent_normal").at("file"), "bent_normal.exr");
  EXPECT_TRUE(fs::exists(folder() / "obscurance.exr"));
}

TEST_F(LightmapExtrasFolder, ManifestEntriesAreChecked) {
  const struct {
    nlohmann::json extras;
    const char* expected;
  } cases[] = {
      {"ao.exr", "'extras' must be an object"},
      {{{"fog", {{"file", "ao.exr"}}}}, "unknown extra map 'fog'"},
      {{{"ao", "ao.exr"}}, "extra map 'ao' must be an object with a \"file\""},
      {{{"ao", {{"rays", 3}}}}, "extra map 'ao' must be an object with a \"file\""},
      {{{"ao", {{"file", "../lm/ao.exr"}}}}, "must be a file in the folder"},
      {{{"ao", {{"file", "missing.exr"}}}}, "missing.exr"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.extras.dump());
    nlohmann::json j = manifest_;
    j["extras"] = c.extras;
    std::ofstream(folder() / "lightmap.json") << j.dump();
    const std::string m = error();
    EXPECT_TRUE(contains(m, c.expected)) << m;
    EXPECT_TRUE(contains(m, folder().string())) << m;
  }
}

TEST_F(LightmapExtrasFolder, MapsOutOfTheirRangeAreRefused) {
  ImageWriteOptions exr;
  exr.exr_half = true;
  const struct {
    const char* file;
    Image image;
    const char* expected;
  } cases[] = {
      {"ao.exr", Image(4, 2, 3, 1.5f), "outside [0, 1]"},
      {"obscurance.exr", Image(4, 2, 3, -0.25f), "outside [0, 1]"},
      {"obscurance_color.exr", Image(4, 2, 3, 2.0f), "outside [0, 1]"},
      {"bent_normal.exr", Image(4, 2, 3, 0.5f), "has length"},
      {"ao.exr", Image(4, 2, 1, 0.5f), "channels"},
      {"ao.exr", Image(2, 2, 3, 0.5f), "but the atlas is 4x2"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.expected);
    save_lightmap_set(folder(), set_with_extras());
    write_image((folder() / c.file).string(), c.image, exr);
    const std::string m = error();
    EXPECT_TRUE(contains(m, c.expected)) << m;
    EXPECT_TRUE(contains(m, c.file)) << m;
  }
  // A grey map that is not grey.
  save_lightmap_set(folder(), set_with_extras());
  Image tinted(4, 2, 3, 0.5f);
  tinted.set_rgb(2, 1, Color(0.5f, 0.5f, 0.25f));
  write_image((folder() / "ao.exr").string(), tinted, exr);
  EXPECT_TRUE(contains(error(), "is not grey"));
}

TEST_F(LightmapExtrasFolder, BadExtrasAreNotSaved) {
  const fs::path other = root_ / "other";
  LightmapSet set = set_with_extras();
  set.extras.push_back(set.extras[0]);
  EXPECT_THROW(save_lightmap_set(other, set), Error);
  set = set_with_extras();
  set.extras[0].name = "fog";
  EXPECT_THROW(save_lightmap_set(other, set), Error);
  set = set_with_extras();
  set.extras[1].image = Image(4, 2, 3, 1.25f);
  EXPECT_THROW(save_lightmap_set(other, set), Error);
  EXPECT_FALSE(fs::exists(other));
}

}  // namespace
}  // namespace illum::baked
