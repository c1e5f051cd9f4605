// Missing, unreadable and hostile side files of a scene (textures, .mtl files, environment
// maps, glTF images) and hostile OBJ/MTL text: each is one illum::Error naming the file (and
// the material or line), or with LoadOptions::allow_missing_textures one warning. Inputs are
// written per test; decoding that used to hang runs under a time limit.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/scene/load.h"
#include "test_support/error_within.h"
#include "test_util.h"

namespace illum {
namespace {

using test::contains;
using test::TempDir;

using test::error_within;

std::string load_error(const std::string& path, const LoadOptions& options = {}) {
  return error_within(30.0, [&] { load_scene(path, options); });
}

LoadOptions allowing_missing() {
  LoadOptions options;
  options.allow_missing_textures = true;
  return options;
}

#define EXPECT_NAMES(message, ...)                                                   \
  do {                                                                               \
    const std::string m_ = (message);                                                \
    for (const std::string& part_ : std::initializer_list<std::string>{__VA_ARGS__}) \
      EXPECT_TRUE(contains(m_, part_)) << "expected '" << part_ << "': " << m_;      \
    EXPECT_EQ(m_.find('\n'), std::string::npos) << m_;                               \
  } while (0)

const char* kQuadObj =
    "mtllib m.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
    "usemtl wood\nf 1/1 2/2 3/3\n";

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A Radiance file cut inside its run-length data (stb looped forever on it).
std::string truncated_hdr(const TempDir& dir) {
  Image img(64, 4, 3, 0.5f);
  write_image(dir.file("whole.hdr"), img);
  const std::string bytes = read_file(dir.file("whole.hdr"));
  return bytes.substr(0, bytes.size() - 40);
}

// ---------------------------------------------------------------------------------------
// OBJ / MTL textures and material files

TEST(ObjTextureErrors, MissingTextureNamesItAndTheMaterial) {
  TempDir dir;
  dir.write("m.mtl", "newmtl wood\nKd 0.5 0.4 0.3\nmap_Kd textures/missing.png\n");
  const std::string path = dir.write("t.obj", kQuadObj);
  EXPECT_NAMES(load_error(path), path, "textures/missing.png", "'wood'", "not found");
  // Allowed: one warning, and the material renders without it.
  const Scene scene = load_scene(path, allowing_missing());
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].albedo_texture, kNoTexture);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NAMES(scene.warnings[0], "missing.png", "'wood'");
  ASSERT_EQ(scene.meshes[0].tangents.size(), 3u);  // uv0 and tangents are still there
}

TEST(ObjTextureErrors, UnreadableTexturesAreErrorsToo) {
  TempDir dir;
  dir.write("empty.png", "");
  dir.write("cut.hdr", truncated_hdr(dir));
  for (const char* texture : {"empty.png", "cut.hdr"}) {
    SCOPED_TRACE(texture);
    dir.write("m.mtl", std::string("newmtl wood\nmap_Kd ") + texture + "\n");
    const std::string path = dir.write("t.obj", kQuadObj);
    EXPECT_NAMES(load_error(path), path, dir.file(texture), "'wood'");
    const Scene scene = load_scene(path, allowing_missing());
    EXPECT_EQ(scene.warnings.size(), 1u);
    EXPECT_TRUE(scene.textures.empty());
  }
}

TEST(ObjTextureErrors, MissingMtlIsAMissingFile) {
  TempDir dir;
  const std::string path = dir.write("t.obj", kQuadObj);
  EXPECT_NAMES(load_error(path), path, dir.file("m.mtl"), "mtllib", "not found");
  // Allowed: one warning (not one more per usemtl), default material.
  const Scene scene = load_scene(path, allowing_missing());
  ASSERT_EQ(scene.warnings.size(), 1u) << fmt::format("{}", fmt::join(scene.warnings, " | "));
  EXPECT_NAMES(scene.warnings[0], "m.mtl");
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "default");
  // A comment after the file name is not a file.
  dir.write("m.mtl", "newmtl wood\nKd 0.5 0.4 0.3\n");
  const std::string commented = dir.write("c.obj", std::string("mtllib m.mtl # materials\n") +
                                                       (kQuadObj + std::strlen("mtllib m.mtl\n")));
  EXPECT_TRUE(load_scene(commented).warnings.empty());
}

TEST(ObjTextureErrors, MtlNumbersMustBeFinite) {
  TempDir dir;
  const std::string path = dir.write("t.obj", kQuadObj);
  for (const char* bad : {"Kd 0.5 nan 0.3", "Ns inf", "Ke 1e39 0 0", "d 0x1p3",
                          "map_Kd -bm nan t.png", "illum two"}) {
    SCOPED_TRACE(bad);
    dir.write("m.mtl", std::string("newmtl wood\n# a comment\n") + bad + "\n");
    EXPECT_NAMES(load_error(path), dir.file("m.mtl"), "line 3", "not a finite number");
  }
}

// ---------------------------------------------------------------------------------------
// OBJ text

TEST(ObjTextErrors, NumbersOverflowingAFloatNameTheLine) {
  TempDir dir;
  const std::string digits(400, '9');
  for (const std::string& bad : {std::string("v 1e39 0 0"), "v 0 " + digits + " 0",
                                 std::string("vt 0 1e99999999999"), std::string("vn -inf 0 1")}) {
    SCOPED_TRACE(bad);
    const std::string path =
        dir.write("n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + bad + "\nf 1 2 3\n");
    EXPECT_NAMES(load_error(path), path, "line 4", "not a finite number");
  }
}

TEST(ObjTextErrors, IndicesAreCheckedWithTheirLine) {
  TempDir dir;
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const struct {
    const char* face;
    const char* expected;
  } cases[] = {{"f 1 2 0", "vertex index 0"},
               {"f 1 2 4", "vertex 4 is out of range"},
               {"f 1 2 99999999999999", "vertex 99999999999999 is out of range"},
               {"f 1 2 99999999999999999999", "not a vertex index"},
               {"f -1 -2 -4", "vertex -4 is out of range"},
               {"f 1/1 2/1 3/1", "uv 1 is out of range"},
               {"f 1//2 2//2 3//2", "normal 2 is out of range"},
               {"f 1 2 x", "not a vertex index"},
               {"f 1///1 2 3", "more than three indices"},
               {"l 1 7", "vertex 7 is out of range"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.face);
    const std::string path = dir.write("i.obj", head + c.face + "\n");
    EXPECT_NAMES(load_error(path), path, "line 4", c.expected);
  }
  // Relative indices within range are fine.
  EXPECT_EQ(load_scene(dir.write("r.obj", head + "f -3 -2 -1\n")).triangle_count(), 1u);
}

std::string polygon_obj(size_t n) {
  std::string text;
  for (size_t i = 0; i < n; ++i) {
    const double a = 6.283185307179586 * static_cast<double>(i) / static_cast<double>(n);
    text += fmt::format("v {} {} 0\n", std::cos(a), std::sin(a));
  }
  text += "f";
  for (size_t i = 1; i <= n; ++i) text += fmt::format(" {}", i);
  return text + "\n";
}

TEST(ObjTextErrors, FaceVertexCountIsBounded) {
  // tinyobjloader's ear clipping is quadratic in a face's vertices: 10^6 would take hours.
  TempDir dir;
  const std::string big = dir.write("big.obj", polygon_obj(1025));
  EXPECT_NAMES(load_error(big), big, "line 1026", "a face of 1025 vertices");
  const std::string ok = dir.write("ok.obj", polygon_obj(1024));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(load_scene(ok).triangle_count(), 1022u);
  std::printf("a 1024-gon loads in %.3f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

TEST(ObjTextErrors, BinaryGarbageIsNotAnObj) {
  TempDir dir;
  std::string garbage = "v 0 0 0\n";
  for (int i = 0; i < 256; ++i) garbage += static_cast<char>((i * 37) & 0xff);
  const std::string path = dir.write("g.obj", garbage);
  EXPECT_NAMES(load_error(path), path, "not a text OBJ file");
}

// ---------------------------------------------------------------------------------------
// Scene files: textures and the environment map

TEST(SceneFileTextureErrors, MissingTexturesAndEnvironmentMaps) {
  TempDir dir;
  dir.write("tri.obj", "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string tex = dir.write(
      "t.illum.json",
      R"({"meshes": [{"file": "tri.obj"}], "materials": {"default": {"albedo_texture": "none.png"}}})");
  EXPECT_NAMES(load_error(tex), tex, dir.file("none.png"), "'default'");
  EXPECT_EQ(load_scene(tex, allowing_missing()).warnings.size(), 1u);

  const std::string env = dir.write(
      "e.illum.json", R"({"meshes": [{"file": "tri.obj"}], "environment": {"file": "sky.hdr"}})");
  EXPECT_NAMES(load_error(env), env, dir.file("sky.hdr"), "environment map", "not found");
  const Scene without = load_scene(env, allowing_missing());
  EXPECT_EQ(without.warnings.size(), 1u);
  EXPECT_FALSE(without.environment.has_value());
  EXPECT_TRUE(without.lights.empty());

  // A truncated map: an error (stb used to loop forever on it), within a time limit.
  dir.write("sky.hdr", truncated_hdr(dir));
  EXPECT_NAMES(load_error(env), env, dir.file("sky.hdr"), "truncated");
  // A NaN texel: the reader names it.
  Image nan_map(4, 2, 3, 1.0f);
  nan_map.pixel(2, 1)[0] = std::numeric_limits<float>::quiet_NaN();
  ImageWriteOptions exact;
  exact.exr_half = false;
  write_image(dir.file("nan.exr"), nan_map, exact);
  const std::string nan_env = dir.write(
      "n.illum.json", R"({"meshes": [{"file": "tri.obj"}], "environment": {"file": "nan.exr"}})");
  EXPECT_NAMES(load_error(nan_env), nan_env, dir.file("nan.exr"), "texel (2, 1) channel 0 is NaN");
}

// ---------------------------------------------------------------------------------------
// glTF images

std::string base64(const std::string& data) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    const uint32_t b0 = static_cast<uint8_t>(data[i]);
    const uint32_t b1 = i + 1 < data.size() ? static_cast<uint8_t>(data[i + 1]) : 0;
    const uint32_t b2 = i + 2 < data.size() ? static_cast<uint8_t>(data[i + 2]) : 0;
    const uint32_t n = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

template <typename T>
void put(std::string& buf, std::initializer_list<T> values) {
  for (T v : values) buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// One textured triangle; the image is `image` (a JSON object) and the binary buffer is
// `bin` followed by `extra` bytes (for GLB-embedded images).
nlohmann::json textured_triangle(const nlohmann::json& image) {
  using nlohmann::json;
  json j;
  j["asset"] = {{"version", "2.0"}};
  j["accessors"] = json::array({{{"bufferView", 0},
                                 {"componentType", 5126},
                                 {"type", "VEC3"},
                                 {"count", 3},
                                 {"min", {0, 0, 0}},
                                 {"max", {1, 1, 0}}},
                                {{"bufferView", 0},
                                 {"byteOffset", 36},
                                 {"componentType", 5126},
                                 {"type", "VEC2"},
                                 {"count", 3}}});
  j["meshes"] =
      json::array({{{"primitives",
                     {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"material", 0}}}}}});
  j["materials"] = json::array(
      {{{"name", "painted"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  j["textures"] = json::array({{{"source", 0}}});
  j["images"] = json::array({image});
  j["nodes"] = json::array({{{"mesh", 0}}});
  j["scenes"] = json::array({{{"nodes", {0}}}});
  j["scene"] = 0;
  return j;
}

std::string triangle_bin() {
  std::string b;
  put<float>(b, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  put<float>(b, {0, 0, 1, 0, 0, 1});
  return b;  // 60 bytes
}

std::string write_gltf(const TempDir& dir, nlohmann::json j) {
  j["buffers"] = {{{"byteLength", 60},
                   {"uri", "data:application/octet-stream;base64," + base64(triangle_bin())}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteLength", 60}}};
  return dir.write("t.gltf", j.dump());
}

// A GLB whose binary chunk holds the triangle and then `image_bytes`, with bufferView 1 the
// image's (at `view_offset`, `view_length`: by default exactly the image).
std::string write_glb(const TempDir& dir, nlohmann::json j, const std::string& image_bytes,
                      int64_t view_offset = 60, int64_t view_length = -1) {
  std::string bin = triangle_bin() + image_bytes;
  while (bin.size() % 4) bin += '\0';
  j["buffers"] = {{{"byteLength", bin.size()}}};
  j["bufferViews"] = {
      {{"buffer", 0}, {"byteLength", 60}},
      {{"buffer", 0},
       {"byteOffset", view_offset},
       {"byteLength", view_length < 0 ? static_cast<int64_t>(image_bytes.size()) : view_length}}};
  std::string json = j.dump();
  while (json.size() % 4) json += ' ';
  std::string out;
  put<uint32_t>(out, {0x46546C67u, 2u, static_cast<uint32_t>(28 + json.size() + bin.size())});
  put<uint32_t>(out, {static_cast<uint32_t>(json.size()), 0x4E4F534Au});
  out += json;
  put<uint32_t>(out, {static_cast<uint32_t>(bin.size()), 0x004E4942u});
  out += bin;
  return dir.write("t.glb", out);
}

// An 8-bit grey PNG declaring `w` × `h` pixels over 100 bytes of "compressed" data.
std::string png_declaring(uint32_t w, uint32_t h) {
  auto be = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  std::string png = "\x89PNG\r\n\x1a\n";
  png += be(13) + "IHDR" + be(w) + be(h) + std::string("\x08\x00\x00\x00\x00", 5) + be(0);
  png += be(100) + "IDAT" + std::string(100, 'x') + be(0);
  png += be(0) + "IEND" + be(0);
  return png;
}

TEST(GltfTextureErrors, MissingExternalImageNamesItAndTheMaterial) {
  TempDir dir;
  const std::string path = write_gltf(dir, textured_triangle({{"uri", "gone.png"}}));
  EXPECT_NAMES(load_error(path), path, dir.file("gone.png"), "'painted'", "not found");
  const Scene scene = load_scene(path, allowing_missing());
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NAMES(scene.warnings[0], "gone.png", "'painted'");
  dir.write("gone.png", "");  // present but empty: tinygltf drops it, illum names it
  EXPECT_NAMES(load_error(path), path, "gone.png", "'painted'", "empty");
  EXPECT_EQ(load_scene(path, allowing_missing()).warnings.size(), 1u);
}

TEST(GltfTextureErrors, EmbeddedImagesGoThroughTheCheckedDecoder) {
  TempDir dir;
  // A data: URI image declaring 16000² pixels in 100 bytes.
  const std::string uri = write_gltf(
      dir,
      textured_triangle({{"uri", "data:image/png;base64," + base64(png_declaring(16000, 16000))}}));
  EXPECT_NAMES(load_error(uri), uri, "images[0]", "'painted'", "deflate");
  // The same inside a GLB.
  const std::string glb =
      write_glb(dir, textured_triangle({{"bufferView", 1}, {"mimeType", "image/png"}}),
                png_declaring(16000, 16000));
  EXPECT_NAMES(load_error(glb), glb, "images[0]", "'painted'", "deflate");
  // A bufferView reaching past its buffer is a malformed file (never an allowed warning),
  // refused by the structure check before tinygltf reads the image.
  const std::string past =
      write_glb(dir, textured_triangle({{"bufferView", 1}, {"mimeType", "image/png"}}),
                png_declaring(4, 4), 60, 4096);
  EXPECT_NAMES(load_error(past, allowing_missing()), past, "bufferViews[1]",
               "runs past the end of buffers[0]");
  // A real embedded PNG still decodes.
  Image img(3, 2, 3, 0.25f);
  write_image(dir.file("small.png"), img);
  const std::string png = read_file(dir.file("small.png"));
  const Scene scene = load_scene(
      write_glb(dir, textured_triangle({{"bufferView", 1}, {"mimeType", "image/png"}}), png));
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].image.width(), 3);
  EXPECT_NEAR(scene.textures[0].image.rgb(0, 0).r, 0.25f, 0.01f);
}

}  // namespace
}  // namespace illum
