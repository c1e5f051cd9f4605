// Every field of every bake manifest (lightmap.json, prt.json, probes.json) is checked for
// presence, type and range: for each field, several bad values (wrong type, negative, 0,
// 1e12, "NaN" as a string, missing, disagreeing with the atlas or data file) are each one
// illum::Error line that names the manifest and the field, and the good manifest still loads.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "illum/baked/lightmap_file.h"
#include "illum/baked/probe_file.h"
#include "illum/baked/prt_file.h"
#include "illum/core/error.h"
#include "illum/core/sh.h"

namespace illum::baked {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A value to put at a field, or "remove the field".
struct Bad {
  json value;
  bool missing = false;
};
const Bad kMissing{nullptr, true};

struct Field {
  std::vector<std::string> path;  // {"grid", "spacing"}
  std::vector<Bad> bad;
};

std::string dotted(const std::vector<std::string>& path) {
  std::string s;
  for (const std::string& k : path) s += (s.empty() ? "" : ".") + k;
  return s;
}

class ManifestFieldsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            fmt::format("illum_manifest_{}_{}",
                        ::testing::UnitTest::GetInstance()->current_test_info()->name(), getpid());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  static atlas::Atlas small_atlas() {
    atlas::Atlas a;
    a.width = 8;
    a.height = 4;
    a.texel_size = 0.25f;
    return a;
  }

  // For each field and bad value: the manifest with that change makes `load` throw one
  // Error line naming the manifest file and the field; the good manifest loads afterwards.
  void check_fields(const fs::path& folder, const std::string& manifest_name,
                    const std::vector<Field>& fields, const std::function<void()>& load) {
    const fs::path manifest_path = folder / manifest_name;
    const json good = json::parse(std::ifstream(manifest_path));
    ASSERT_NO_THROW(load()) << "the good manifest must load";
    int cases = 0;
    for (const Field& field : fields) {
      for (const Bad& bad : field.bad) {
        const std::string what =
            dotted(field.path) + " = " + (bad.missing ? "(missing)" : bad.value.dump());
        SCOPED_TRACE(manifest_name + ": " + what);
        json changed = good;
        json* parent = &changed;
        for (size_t i = 0; i + 1 < field.path.size(); ++i) parent = &(*parent)[field.path[i]];
        if (bad.missing)
          parent->erase(field.path.back());
        else
          (*parent)[field.path.back()] = bad.value;
        std::ofstream(manifest_path) << changed.dump();
        std::string message;
        try {
          load();
          ADD_FAILURE() << "loaded with " << what;
        } catch (const Error& e) {
          message = e.what();
        }
        ++cases;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(manifest_path.string()), std::string::npos) << message;
        EXPECT_NE(message.find("'" + dotted(field.path) + "'"), std::string::npos) << message;
      }
    }
    EXPECT_GT(cases, 0);
    std::ofstream(manifest_path) << good.dump();
    EXPECT_NO_THROW(load()) << "the good manifest, written back, must load";
  }

  fs::path root_;
};

// Bad values of each kind of field. Counts: a string, negative, fractional, 1e12 as a
// float, "NaN" as a string, missing.
std::vector<Bad> bad_count() {
  return {{"1"}, {-1}, {1.5}, {1e12}, {"NaN"}, {nullptr}, kMissing};
}
std::vector<Bad> bad_string() {
  return {{7}, {nullptr}, {json::array()}, kMissing};
}
std::vector<Bad> bad_size() {
  return {{"0.25"}, {-1}, {0}, {1e12}, {"NaN"}, {nullptr}, kMissing};
}
std::vector<Bad> bad_file() {
  return {{7}, {""}, {".."}, {"../x.bin"}, {"/etc/passwd"}, kMissing};
}
std::vector<Bad> plus(std::vector<Bad> a, const std::vector<Bad>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
// Fields every manifest kind has, with their bad values.
std::vector<Field> common_fields(const std::string& format, bool scene_hash_required) {
  std::vector<Field> f = {
      {{"format"}, plus(bad_string(), {{"illum-other"}, {"NaN"}, {format + " "}})},
      {{"version"}, plus(bad_count(), {{0}, {2}, {1000000000000}})},
      {{"scene"}, bad_string()},
      {{"scene_triangles"}, plus(bad_count(), {{int64_t{1000000000000000}}})},
      {{"scene_hash"}, {{7}, {"NaN"}, {"0123456789ABCDEF"}, {"0123456789abcde"}}},
      {{"bake"}, {{7}, {"x"}, {json::array({1})}}},
  };
  if (scene_hash_required) f[4].bad.push_back(kMissing);
  return f;
}
std::vector<Field> atlas_fields() {
  return {
      {{"atlas"}, bad_file()},
      {{"width"}, plus(bad_count(), {{0}, {16}, {1000000000000}})},
      {{"height"}, plus(bad_count(), {{0}, {8}, {1000000000000}})},
      {{"charts"}, plus(bad_count(), {{5}, {1000000000000}})},
      {{"texel_size"}, plus(bad_size(), {{0.5}})},
  };
}

TEST_F(ManifestFieldsTest, LightmapManifestFields) {
  LightmapSet set;
  set.atlas = small_atlas();
  set.basis = "plain";
  set.scene = "nothing";
  set.scene_hash = "0123456789abcdef";
  set.layers = {Image(8, 4, 3, 0.5f)};
  const fs::path folder = root_ / "lm";
  save_lightmap_set(folder, set);
  std::vector<Field> fields = common_fields("illum-lightmap", false);
  for (Field& f : atlas_fields()) fields.push_back(f);
  fields.push_back({{"basis"}, plus(bad_string(), {{"rgb"}, {"NaN"}})});
  fields.push_back({{"content"}, plus(bad_string(), {{"direct"}, {"NaN"}})});
  fields.push_back({{"layers"},
                    {{"layer0.exr"},
                     {7},
                     {json::array()},
                     {json::array({7})},
                     {json::array({"../layer0.exr"})},
                     {json::array({"layer0.exr", "layer0.exr"})},
                     kMissing}});
  fields.push_back({{"extras"}, {{7}, {"ao"}}});
  check_fields(folder, "lightmap.json", fields, [&] { load_lightmap_set(folder); });
}

TEST_F(ManifestFieldsTest, PrtManifestFields) {
  PrtSet set;
  set.atlas = small_atlas();
  set.bands = 2;
  const int channels = 3 * sh::coefficient_count(2);
  set.texel_transfer = TransferMap(8, 4, channels);
  for (size_t i = 0; i < set.texel_transfer.data.size(); ++i)
    set.texel_transfer.data[i] = float(i % 7) * 0.125f;
  set.vertex_transfer = {std::vector<float>(size_t(3 * channels), 0.25f)};
  set.vq.dimension = channels;
  set.vq.representatives.assign(size_t(2 * channels), 0.5f);
  set.vq.indices.assign(32, 1);
  set.vq.iterations = 4;
  set.vq.max_distance = 0.5;
  set.vq.rms_distance = 0.25;
  set.scene = "nothing";
  set.scene_hash = "0123456789abcdef";
  const fs::path folder = root_ / "prt";
  save_prt_set(folder, set);
  std::vector<Field> fields = common_fields("illum-prt", true);
  for (Field& f : atlas_fields()) fields.push_back(f);
  fields.push_back({{"bands"}, plus(bad_count(), {{0}, {1}, {9}, {1000000000000}})});
  fields.push_back({{"coefficients"}, plus(bad_count(), {{0}, {1}, {9}, {1000000000000}})});
  fields.push_back({{"mode"}, plus(bad_string(), {{"NaN"}, {"sometimes"}})});
  fields.push_back({{"texels"}, {{7}, {""}, {"../texels.bin"}, {"/etc/passwd"}}});
  fields.push_back({{"vertices"}, {{7}, {"vertices.bin"}, {json::array()}}});
  fields.push_back({{"vertices", "file"}, bad_file()});
  fields.push_back({{"vertices", "vertex_counts"},
                    {{"3"},
                     {3},
                     {json::array({-1})},
                     {json::array({1.5})},
                     {json::array({1e12})},
                     {json::array({int64_t{1000000000000}})},
                     {json::array({4})},
                     {json::array({"NaN"})},
                     kMissing}});
  fields.push_back({{"vq"}, {{7}, {"vq"}}});
  fields.push_back({{"vq", "representatives"}, plus(bad_count(), {{0}, {3}, {1000000000000}})});
  fields.push_back({{"vq", "file"}, bad_file()});
  fields.push_back({{"vq", "indices"}, bad_file()});
  fields.push_back({{"vq", "iterations"}, plus(bad_count(), {{1000000000000}})});
  fields.push_back({{"vq", "max_distance"}, {{"0.5"}, {-1}, {1e300}, {"NaN"}, kMissing}});
  fields.push_back({{"vq", "rms_distance"}, {{"0.5"}, {-1}, {1e300}, {"NaN"}, kMissing}});
  check_fields(folder, "prt.json", fields, [&] { load_prt_set(folder); });
}

TEST_F(ManifestFieldsTest, ProbeManifestFields) {
  ProbeSet set;
  set.grid.size = {2, 2, 2};
  set.grid.origin = vec3(-1.0f, 0.0f, 2.0f);
  set.grid.spacing = 0.5f;
  set.probes.resize(8);
  for (size_t i = 0; i < set.probes.size(); ++i) {
    set.probes[i] = ProbeRecord{};
    set.probes[i].weight = i % 3 == 0 ? 0.0f : 1.0f;  // 5 of 8 valid
  }
  set.scene = "nothing";
  set.scene_hash = "0123456789abcdef";
  const fs::path folder = root_ / "probes";
  save_probe_set(folder, set);
  std::vector<Field> fields = common_fields("illum-probes", true);
  fields.push_back({{"sh_bands"}, plus(bad_count(), {{0}, {2}, {1000000000000}})});
  fields.push_back({{"backface_threshold"}, {{"0.25"}, {-1}, {2}, {1e12}, {"NaN"}, kMissing}});
  fields.push_back({{"layout"}, bad_string()});
  fields.push_back({{"grid"}, {{7}, {"grid"}, {json::array()}, kMissing}});
  fields.push_back({{"grid", "size"},
                    {{"2"},
                     {2},
                     {json::array({2, 2})},
                     {json::array({0, 2, 2})},
                     {json::array({2, 2, -1})},
                     {json::array({2, 2, 1.5})},
                     {json::array({2, 2, 1e12})},
                     {json::array({100000, 100000, 100000})},
                     {json::array({2, 2, "NaN"})},
                     {json::array({2, 2, 4})},  // 16 probes: 'probes' disagrees
                     kMissing}});
  fields.push_back({{"grid", "origin"},
                    {{"0"},
                     {json::array({0, 0})},
                     {json::array({"NaN", 0, 0})},
                     {json::array({1e12, 0, 0})},
                     kMissing}});
  fields.push_back({{"grid", "spacing"}, bad_size()});
  fields.push_back({{"probes"}, plus(bad_count(), {{0}, {7}, {9}, {1000000000000}})});
  fields.push_back({{"valid"}, plus(bad_count(), {{4}, {6}, {9}, {1000000000000}})});
  fields.push_back({{"data"}, plus(bad_file(), {{"other.bin"}})});
  check_fields(folder, "probes.json", fields, [&] { load_probe_set(folder); });
}

}  // namespace
}  // namespace illum::baked
