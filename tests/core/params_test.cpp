// Params: typed getters, range checks, unknown-key detection (nested too) and JSON errors
// that name the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "illum/core/params.h"

namespace illum {
namespace {

namespace fs = std::filesystem;

// Runs `f`, expects an Error, and returns its message.
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an illum::Error";
  return {};
}

Params make(const char* json) {
  return Params(nlohmann::json::parse(json), "scene.json");
}

TEST(Params, TypedGetters) {
  const Params p =
      make(R"({"b": true, "i": 7, "f": 2.5, "s": "hi", "v2": [1, 2], "v3": [1, 2.5, -3],
                            "fl": [0.5, 1], "sl": ["a", "b"]})");
  EXPECT_EQ(p.get<bool>("b"), true);
  EXPECT_EQ(p.get<int>("i"), 7);
  EXPECT_FLOAT_EQ(p.get<float>("f"), 2.5f);
  EXPECT_FLOAT_EQ(p.get<float>("i"), 7.0f);  // integers are numbers too
  EXPECT_EQ(p.get<std::string>("s"), "hi");
  EXPECT_EQ(p.get<vec2>("v2"), vec2(1, 2));
  EXPECT_EQ(p.get<vec3>("v3"), vec3(1, 2.5f, -3));
  EXPECT_EQ(p.get<std::vector<float>>("fl"), (std::vector<float>{0.5f, 1.0f}));
  EXPECT_EQ(p.get<std::vector<std::string>>("sl"), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(p.get<int>("missing", 42), 42);
  EXPECT_TRUE(p.has("b"));
  EXPECT_FALSE(p.has("missing"));
  EXPECT_NO_THROW(p.check_all_used());
}

TEST(Params, TypeMismatchNamesOriginAndKey) {
  const Params p = make(R"({"i": 1.5, "s": 3, "v": [1, 2], "b": "yes"})");
  for (const auto& msg :
       {error_of([&] { p.get<int>("i"); }), error_of([&] { p.get<std::string>("s"); }),
        error_of([&] { p.get<vec3>("v"); }), error_of([&] { p.get<bool>("b"); }),
        error_of([&] { p.get<float>("absent"); })}) {
    EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
  }
  EXPECT_NE(error_of([&] { p.get<int>("i"); }).find("'i'"), std::string::npos);
  EXPECT_NE(error_of([&] { p.get<float>("absent"); }).find("missing"), std::string::npos);
}

TEST(Params, RangeErrors) {
  const Params p = make(R"({"spp": 0, "albedo": 1.5, "ok": 0.5, "big": 3000000000})");
  const std::string msg = error_of([&] { p.get_int_in("spp", 16, 1, 1 << 20); });
  EXPECT_NE(msg.find("'spp'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("outside"), std::string::npos) << msg;
  EXPECT_NE(error_of([&] { p.get_float_in("albedo", 0.5f, 0.0f, 1.0f); }).find("'albedo'"),
            std::string::npos);
  EXPECT_FLOAT_EQ(p.get_float_in("ok", 0.1f, 0.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(p.get_float_in("default", 0.1f, 0.0f, 1.0f), 0.1f);
  EXPECT_NE(error_of([&] { p.get<int>("big"); }).find("out of range"), std::string::npos);
}

TEST(Params, UnknownKeyDetected) {
  const Params p = make(R"({"spp": 4, "spp_typo": 8})");
  p.get<int>("spp");
  const std::string msg = error_of([&] { p.check_all_used(); });
  EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("spp_typo"), std::string::npos) << msg;
  p.mark_used("spp_typo");
  EXPECT_NO_THROW(p.check_all_used());
}

TEST(Params, UnknownKeyInNestedChildren) {
  const Params p = make(R"({"camera": {"fov": 40, "fvo": 1},
                            "lights": [{"type": "point"}, {"type": "spot", "angel": 30}]})");
  const Params camera = p.child("camera");
  camera.get<float>("fov");
  camera.mark_used("fvo");
  for (const Params& light : p.children("lights")) light.get<std::string>("type");
  // Reads through a copy count for the original.
  const std::string msg = error_of([&] { p.check_all_used(); });
  EXPECT_NE(msg.find("lights[1].angel"), std::string::npos) << msg;
  EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;

  const Params q = make(R"({"camera": {"fov": 40, "fvo": 1}})");
  q.child("camera").get<float>("fov");
  EXPECT_NE(error_of([&] { q.check_all_used(); }).find("camera.fvo"), std::string::npos);
}

TEST(Params, ChildOfWrongTypeThrows) {
  const Params p = make(R"({"camera": 3, "lights": [1]})");
  EXPECT_NE(error_of([&] { p.child("camera"); }).find("'camera'"), std::string::npos);
  EXPECT_NE(error_of([&] { p.children("lights"); }).find("lights[0]"), std::string::npos);
}

class ParamsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fmt::format("illum_core_params_{}", getpid());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string file = (dir_ / name).string();
    std::ofstream(file) << text;
    return file;
  }
  fs::path dir_;
};

TEST_F(ParamsFile, ReadsFileWithComments) {
  const std::string file = write("ok.json", "{\n  // comment\n  \"spp\": 16\n}\n");
  const Params p = Params::from_file(file);
  EXPECT_EQ(p.get<int>("spp"), 16);
  EXPECT_EQ(p.origin(), file);
}

TEST_F(ParamsFile, MalformedJsonNamesTheFile) {
  const std::string file = write("bad.json", "{\n  \"spp\": 16,\n  \"oops\" 3\n}\n");
  const std::string msg = error_of([&] { Params::from_file(file); });
  EXPECT_NE(msg.find(file), std::string::npos) << msg;
  EXPECT_NE(msg.find("malformed JSON"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
}

TEST_F(ParamsFile, MissingFileAndNonObjectThrow) {
  const std::string missing = (dir_ / "nope.json").string();
  EXPECT_NE(error_of([&] { Params::from_file(missing); }).find(missing), std::string::npos);
  const std::string array = write("array.json", "[1, 2]");
  EXPECT_NE(error_of([&] { Params::from_file(array); }).find(array), std::string::npos);
}

}  // namespace
}  // namespace illum
