// Hostile glTF: every count, offset, stride and index against the bytes that exist, every
// number against its range (the shared rules of scene/scene_validation.h under glTF's names),
// the GLB container, nesting depth, number overflow, node hierarchies that are not trees,
// and the decode budget. Each bad input must give one Error line naming the file and the
// element; nothing may crash, hang or allocate on the file's word.
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf_asset.h"
#include "illum/core/error.h"
#include "illum/scene/load.h"
#include "test_util.h"

namespace illum {
namespace {

using nlohmann::json;
using test::Asset;
using test::contains;
using test::error_of;
using test::make_asset;
using test::TempDir;

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct BadAsset {
  const char* name;
  std::function<void(Asset&)> mutate;
  std::vector<std::string> expect;  // all must appear in the message
};

// Writes each mutated asset as .gltf and checks the one-line error.
void expect_errors(const std::vector<BadAsset>& cases) {
  TempDir dir;
  for (const BadAsset& c : cases) {
    SCOPED_TRACE(c.name);
    Asset a = make_asset();
    c.mutate(a);
    const std::string path = test::write_gltf(dir, a, std::string(c.name) + ".gltf");
    const std::string message = error_of([&] { load_scene(path); });
    EXPECT_TRUE(contains(message, path)) << message;
    for (const std::string& e : c.expect) EXPECT_TRUE(contains(message, e)) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(GltfErrors, BuffersViewsAndAccessorsAgainstTheBytes) {
  expect_errors({
      {"buffer_length",
       [](Asset& a) { a.json["buffers"][0]["byteLength"] = a.bin.size() + 4; },
       {"buffers[0].byteLength = 160", "data URI holds 156 bytes"}},
      {"view_negative_offset",
       [](Asset& a) { a.json["bufferViews"][0]["byteOffset"] = -4; },
       {"bufferViews[0].byteOffset = -4 must be a non-negative integer"}},
      {"view_past_buffer",
       [](Asset& a) { a.json["bufferViews"][0]["byteLength"] = a.bin.size() + 1; },
       {"bufferViews[0]", "runs past the end of buffers[0] (156 bytes)"}},
      {"view_stride_odd",
       [](Asset& a) { a.json["bufferViews"][0]["byteStride"] = 6; },
       {"bufferViews[0].byteStride = 6 must be a multiple of 4 in [4, 252]"}},
      {"view_stride_long",
       [](Asset& a) { a.json["bufferViews"][0]["byteStride"] = 256; },
       {"bufferViews[0].byteStride = 256"}},
      {"stride_shorter_than_element",
       [](Asset& a) {
         a.json["bufferViews"].push_back(
             {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}, {"byteStride", 8}});
         a.json["accessors"][0]["bufferView"] = 1;
       },
       {"accessors[0] has 12-byte elements, longer than the byteStride 8 of bufferViews[1]"}},
      {"accessor_past_view",
       [](Asset& a) { a.json["accessors"][0]["count"] = 400; },
       {"accessors[0] (400 elements of 12 bytes", "reads past the end of bufferViews[0]"}},
      {"accessor_count_wraps",  // (count − 1)·stride overflows 64 bits
       [](Asset& a) { a.json["accessors"][0]["count"] = uint64_t{1} << 62; },
       {"accessors[0]", "reads past the end of bufferViews[0]"}},
      {"accessor_negative_offset",
       [](Asset& a) { a.json["accessors"][1]["byteOffset"] = -8; },
       {"accessors[1].byteOffset = -8 must be a non-negative integer"}},
      {"accessor_component_type",
       [](Asset& a) { a.json["accessors"][0]["componentType"] = 5130; },
       {"accessors[0].componentType = 5130 is not a glTF component type"}},
      {"accessor_type",
       [](Asset& a) { a.json["accessors"][0]["type"] = "VEC5"; },
       {"accessors[0].type must be one of"}},
      {"accessor_count_zero",
       [](Asset& a) { a.json["accessors"][0]["count"] = 0; },
       {"accessors[0].count must be at least 1"}},
      {"index_past_vertices",
       [](Asset& a) { a.bin[80 + 5] = 9; },
       {"meshes[0] 'quad' primitive 0 indices (accessors[2]) entry 5 is vertex 9, past the 4 "
        "vertices"}},
  });
}

TEST(GltfErrors, IndicesNameElementsThatExist) {
  expect_errors({
      {"mesh_past_int",
       [](Asset& a) { a.json["nodes"][1]["mesh"] = uint64_t{1} << 32; },
       // tinygltf would truncate 2³² to mesh 0 and load the wrong thing
       {"nodes[1].mesh = 4294967296 refers to meshes[4294967296], but the file has 2 meshes"}},
      {"mesh_negative",
       [](Asset& a) { a.json["nodes"][1]["mesh"] = -1; },
       {"nodes[1].mesh = -1 must be an index"}},
      {"child",
       [](Asset& a) { a.json["nodes"][0]["children"] = {42}; },
       {"nodes[0].children[0] = 42 refers to nodes[42]"}},
      {"attribute",
       [](Asset& a) { a.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; },
       {"meshes[0].primitives[0].attributes.POSITION = 99 refers to accessors[99]"}},
      {"primitive_material",
       [](Asset& a) { a.json["meshes"][0]["primitives"][0]["material"] = 4; },
       {"meshes[0].primitives[0].material = 4 refers to materials[4], but the file has 4"}},
      {"primitive_mode",
       [](Asset& a) { a.json["meshes"][0]["primitives"][0]["mode"] = 9; },
       {"meshes[0].primitives[0].mode = 9 is not a glTF primitive mode"}},
      {"light",
       [](Asset& a) { a.json["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 5; },
       {"nodes[3].extensions.KHR_lights_punctual.light = 5 refers to lights[5], but the file has "
        "2"}},
      {"texture_source",
       [](Asset& a) {
         a.json["textures"] = {{{"source", 3}}};
       },
       {"textures[0].source = 3 refers to images[3], but the file has 0 images"}},
      {"texture_sampler",
       [](Asset& a) {
         a.json["samplers"] = {json::object()};
         a.json["textures"] = {{{"sampler", 1}}};
       },
       {"textures[0].sampler = 1 refers to samplers[1]"}},
      {"material_texture",
       [](Asset& a) {
         a.json["materials"][0]["emissiveTexture"] = {{"index", 7}};
       },
       {"materials[0].emissiveTexture.index = 7 refers to textures[7]"}},
      {"image_view",
       [](Asset& a) {
         a.json["images"] = {{{"bufferView", 9}, {"mimeType", "image/png"}}};
       },
       {"images[0].bufferView = 9 refers to bufferViews[9]"}},
      {"default_scene",
       [](Asset& a) { a.json["scene"] = 3; },
       // used to fall back to scene 0 without a word
       {"scene = 3 refers to scenes[3], but the file has 1 scenes"}},
      {"required_extension",
       [](Asset& a) {
         a.json["extensionsRequired"] = {"KHR_lights_punctual", "KHR_draco_mesh_compression"};
       },
       {"requires extension 'KHR_draco_mesh_compression', which illum does not support"}},
  });
}

TEST(GltfErrors, MaterialValuesUnderTheSharedRules) {
  auto pbr = [](Asset& a, int m) -> json& {
    return a.json["materials"][m]["pbrMetallicRoughness"];
  };
  expect_errors({
      {"emissive_negative",
       [](Asset& a) {
         a.json["materials"][0]["emissiveFactor"] = {-1, 0, 0};
       },
       {"materials[0] 'emitter' emissiveFactor = -1 is outside [0, 1]"}},
      {"base_colour_above_one",
       [&](Asset& a) {
         pbr(a, 3)["baseColorFactor"] = {1.5, 0.3, 0.8, 1};
       },
       {"materials[3] 'plastic' baseColorFactor = 1.5 is outside [0, 1]"}},
      {"base_colour_negative",
       [&](Asset& a) {
         pbr(a, 3)["baseColorFactor"] = {0.2, -0.3, 0.8, 1};
       },
       {"materials[3] 'plastic' baseColorFactor = -0.3 is outside [0, 1]"}},
      {"base_colour_length",
       [&](Asset& a) {
         pbr(a, 3)["baseColorFactor"] = {1, 1, 1};
       },
       {"materials[3].pbrMetallicRoughness.baseColorFactor must be an array of 4 numbers"}},
      {"alpha",
       [&](Asset& a) {
         pbr(a, 3)["baseColorFactor"] = {1, 1, 1, 2};
       },
       {"baseColorFactor alpha = 2 is outside [0, 1]"}},
      {"metallic",
       [&](Asset& a) { pbr(a, 2)["metallicFactor"] = -0.1; },
       {"materials[2] 'gold' metallicFactor = -0.1 is outside [0, 1]"}},
      {"roughness",
       [&](Asset& a) { pbr(a, 2)["roughnessFactor"] = 2; },
       {"materials[2] 'gold' roughnessFactor = 2 is outside [0, 1]"}},
      {"transmission",
       [](Asset& a) {
         a.json["materials"][1]["extensions"]["KHR_materials_transmission"]["transmissionFactor"] =
             1.5;
       },
       {"materials[1] 'glass' KHR_materials_transmission.transmissionFactor = 1.5 is outside [0, "
        "1]"}},
      {"ior",
       [](Asset& a) { a.json["materials"][1]["extensions"]["KHR_materials_ior"]["ior"] = 0.5; },
       {"materials[1] 'glass' KHR_materials_ior.ior = 0.5 is outside [1, 10]"}},
      {"emissive_strength_negative",
       [](Asset& a) {
         a.json["materials"][0]["extensions"]["KHR_materials_emissive_strength"]
               ["emissiveStrength"] = -1;
       },
       {"emissiveStrength = -1 must not be negative"}},
      {"emissive_strength_float_overflow",  // a fine double, infinity as a float
       [](Asset& a) {
         a.json["materials"][0]["extensions"]["KHR_materials_emissive_strength"]
               ["emissiveStrength"] = 1e39;
       },
       {"emissiveStrength = 1e+39 is not a finite single-precision number"}},
      {"emissive_strength_text",
       [](Asset& a) {
         a.json["materials"][0]["extensions"]["KHR_materials_emissive_strength"]
               ["emissiveStrength"] = "lots";
       },
       {"KHR_materials_emissive_strength.emissiveStrength must be a number"}},
  });
}

TEST(GltfErrors, LightAndCameraValues) {
  auto light = [](Asset& a, int i) -> json& {
    return a.json["extensions"]["KHR_lights_punctual"]["lights"][i];
  };
  auto camera = [](Asset& a) -> json& { return a.json["cameras"][0]["perspective"]; };
  expect_errors({
      {"intensity_negative",
       [&](Asset& a) { light(a, 1)["intensity"] = -3; },
       {"KHR_lights_punctual lights[1] intensity = -3 must not be negative"}},
      {"intensity_overflow",
       [&](Asset& a) { light(a, 1)["intensity"] = 1e39; },
       {"lights[1] intensity = 1e+39 is not a finite single-precision number"}},
      {"colour_negative",
       [&](Asset& a) {
         light(a, 1)["color"] = {1, -0.5, 0};
       },
       {"lights[1] color = -0.5 is outside [0, 1]"}},
      {"colour_above_one",
       [&](Asset& a) {
         light(a, 1)["color"] = {2, 0, 0};
       },
       {"lights[1] color = 2 is outside [0, 1]"}},
      {"range_zero",
       [&](Asset& a) { light(a, 0)["range"] = 0; },
       {"lights[0] range = 0 must be positive"}},
      {"range_negative",
       [&](Asset& a) { light(a, 0)["range"] = -7; },
       {"lights[0] range = -7 must be positive"}},
      {"inner_past_outer",
       [&](Asset& a) { light(a, 0)["spot"]["innerConeAngle"] = 0.6; },
       {"lights[0] spot.innerConeAngle = 0.6 is outside [0, outerConeAngle]"}},
      {"outer_past_right_angle",
       [&](Asset& a) { light(a, 0)["spot"]["outerConeAngle"] = 2.0; },
       {"lights[0] spot.outerConeAngle = 2 is outside (0, π/2]"}},
      {"outer_zero",
       [&](Asset& a) {
         light(a, 0)["spot"] = {{"innerConeAngle", 0}, {"outerConeAngle", 0}};
       },
       {"spot.outerConeAngle = 0 is outside (0, π/2]"}},
      {"intensity_text",  // tinygltf would keep its default of 1 silently
       [&](Asset& a) { light(a, 1)["intensity"] = "bright"; },
       {"KHR_lights_punctual lights[1].intensity = \"bright\" must be a number"}},
      {"light_type",
       [&](Asset& a) { light(a, 1)["type"] = "laser"; },
       {"lights[1] type 'laser' is not point, spot or directional"}},
      {"yfov_zero",
       [&](Asset& a) { camera(a)["yfov"] = 0; },
       {"cameras[0] yfov = 0 is outside (0, π)"}},
      {"yfov_wide",
       [&](Asset& a) { camera(a)["yfov"] = 4; },
       {"cameras[0] yfov = 4 is outside (0, π)"}},
      {"znear_zero",
       [&](Asset& a) { camera(a)["znear"] = 0; },
       {"cameras[0] znear = 0 must be positive"}},
      {"zfar_before_znear",
       [&](Asset& a) { camera(a)["zfar"] = 0.05; },
       {"cameras[0] zfar = 0.05 must exceed znear = 0.1"}},
      {"aspect_negative",
       [&](Asset& a) { camera(a)["aspectRatio"] = -1.5; },
       {"cameras[0] aspectRatio = -1.5 must be positive"}},
  });
}

TEST(GltfErrors, NodeTransforms) {
  expect_errors({
      {"translation_float_overflow",
       [](Asset& a) {
         a.json["nodes"][2]["translation"] = {0, 1e39, 5};
       },
       {"nodes[2] 'cam' translation = 1e+39 is not a finite single-precision number"}},
      {"zero_scale",
       [](Asset& a) {
         a.json["nodes"][1]["scale"] = {0, 1, 1};
       },
       {"nodes[1] 'quad_node' has a singular transform"}},
      {"collapsed_matrix",
       [](Asset& a) {
         a.json["nodes"][5]["matrix"] = {1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, -3, 1};
       },
       {"nodes[5] 'pair_node' has a singular transform"}},
      {"projective_matrix",
       [](Asset& a) { a.json["nodes"][5]["matrix"][3] = 0.5; },
       {"nodes[5] 'pair_node' has a projective transform"}},
      {"translation_text",  // tinygltf would drop the whole translation silently
       [](Asset& a) {
         a.json["nodes"][2]["translation"] = {0, "one", 5};
       },
       {"nodes[2].translation must be an array of 3 numbers"}},
      {"matrix_length",
       [](Asset& a) { a.json["nodes"][5]["matrix"].erase(15); },
       {"nodes[5].matrix must be an array of 16 numbers"}},
      {"matrix_and_trs",
       [](Asset& a) {
         a.json["nodes"][5]["translation"] = {1, 2, 3};
       },
       {"nodes[5] has both a matrix and translation/rotation/scale"}},
      {"zero_quaternion",
       [](Asset& a) {
         a.json["nodes"][1]["rotation"] = {0, 0, 0, 0};
       },
       {"nodes[1] 'quad_node' rotation is not a usable quaternion"}},
      {"cycle",
       [](Asset& a) { a.json["nodes"][1]["children"] = {0}; },
       {"node 0 is its own ancestor (cycle)"}},
      {"two_parents",
       [](Asset& a) { a.json["scenes"][0]["nodes"].push_back(1); },
       {"node 1 is reached twice"}},
  });
}

TEST(GltfErrors, NormalScaleFloatOverflow) {
  TempDir dir;
  Asset a = make_asset();
  a.json["images"] = {{{"uri", "n.png"}}};
  a.json["textures"] = {{{"source", 0}}};
  a.json["materials"][2]["normalTexture"] = {{"index", 0}, {"scale", 1e39}};
  const std::string path = test::write_gltf(dir, a);
  LoadOptions options;
  options.load_textures = false;  // the (absent) image is not the point here
  const std::string message = error_of([&] { load_scene(path, options); });
  EXPECT_TRUE(contains(message, "materials[2] 'gold' normalTexture.scale = 1e+39")) << message;
}

TEST(GltfErrors, NestingAndNumbersBeforeAnyParser) {
  TempDir dir;
  const std::string text = test::gltf_text(make_asset());
  const size_t brace = text.rfind('}');
  // A million levels: this crashed tinygltf's recursive extras reader (stack exhaustion).
  const int levels = 1000000;
  const std::string deep =
      dir.write("deep.gltf", text.substr(0, brace) + ", \"extras\": " + std::string(levels, '[') +
                                 std::string(levels, ']') + "}");
  const std::string m1 = error_of([&] { load_scene(deep); });
  EXPECT_TRUE(contains(m1, deep) && contains(m1, "JSON nested deeper than 128 levels")) << m1;
  // 128 levels are fine (the asset itself nests 5 deep, so 120 more stay below the limit).
  const std::string ok =
      dir.write("ok.gltf", text.substr(0, brace) + ", \"extras\": " + std::string(120, '[') +
                               std::string(120, ']') + "}");
  EXPECT_EQ(load_scene(ok).triangle_count(), 4u);
  // A number beyond a double: nlohmann's out_of_range used to escape as exit code 1.
  const std::string big =
      dir.write("big.gltf", text.substr(0, brace) + ",\n  \"extras\": {\"x\": 1e400}}");
  const std::string m2 = error_of([&] { load_scene(big); });
  EXPECT_TRUE(contains(m2, big) && contains(m2, "number 1e400 is out of range")) << m2;
  EXPECT_EQ(m2.find('\n'), std::string::npos) << m2;
}

TEST(GltfErrors, GlbContainer) {
  TempDir dir;
  const std::string good = test::write_glb(dir, make_asset(), "good.glb");
  const std::string bytes = file_bytes(good);
  auto with = [&](size_t at, uint32_t value) {
    std::string b = bytes;
    std::memcpy(&b[at], &value, 4);
    return b;
  };
  const uint32_t json_bytes = [&] {
    uint32_t v;
    std::memcpy(&v, &bytes[12], 4);
    return v;
  }();
  struct Case {
    const char* name;
    std::string bytes;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"magic", with(0, 0x12345678u), "no 'glTF' magic"},
      {"version", with(4, 1u), "container version 1"},
      {"length", with(8, static_cast<uint32_t>(bytes.size() + 100)), "the header declares"},
      {"json_chunk", with(12, 1u << 30), "the JSON chunk of 1073741824 bytes runs past"},
      {"bin_chunk", with(20 + json_bytes, 1u << 30), "the BIN chunk of 1073741824 bytes runs past"},
      {"short", bytes.substr(0, 12), "too short"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.write(std::string(c.name) + ".glb", c.bytes);
    const std::string message = error_of([&] { load_scene(path); });
    EXPECT_TRUE(contains(message, path) && contains(message, c.expect)) << message;
  }
  // The JSON chunk declares more buffer than the BIN chunk holds.
  Asset a = make_asset();
  a.json["buffers"][0]["byteLength"] = 4096;
  const std::string past = test::write_glb(dir, a, "past.glb");
  const std::string m1 = error_of([&] { load_scene(past); });
  EXPECT_TRUE(contains(m1, "buffers[0].byteLength = 4096, but the GLB's BIN chunk has 156 bytes"))
      << m1;
}

TEST(GltfErrors, ExternalBufferSize) {
  TempDir dir;
  Asset a = make_asset();
  a.json["buffers"][0]["uri"] = "geo%20metry.bin";  // percent-decoded like tinygltf does
  dir.write("geo metry.bin", std::string(a.bin.begin(), a.bin.end()) + "extra");
  const std::string path = dir.write("ext.gltf", a.json.dump());
  const std::string m1 = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(m1, "buffers[0].byteLength = 156, but 'geo%20metry.bin' has 161 bytes"))
      << m1;
  dir.write("geo metry.bin", std::string(a.bin.begin(), a.bin.end()));
  EXPECT_EQ(load_scene(path).triangle_count(), 4u);
}

// Memory proportional to the input: an accessor without bufferView is all zeros by the spec,
// so a 1 kB file could declare 30 million vertices (480 MB decoded). The budget refuses it
// before allocating.
TEST(GltfErrors, DeclaredCountsBeyondTheDecodeBudget) {
  TempDir dir;
  Asset a = make_asset();
  a.json["accessors"][0].erase("bufferView");
  a.json["accessors"][0]["count"] = 30000000;
  json& prim = a.json["meshes"][0]["primitives"][0];
  prim.erase("indices");
  prim["attributes"].erase("TEXCOORD_0");
  const std::string path = test::write_gltf(dir, a, "zeros.gltf");
  const std::string message = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path) && contains(message, "meshes[0] 'quad' primitive 0") &&
              contains(message, "the file declares far more data than it holds"))
      << message;
  // A count near 2⁶⁴ must not wrap the budget arithmetic into a small number.
  a.json["accessors"][0]["count"] = (uint64_t{1} << 62) + 1;
  const std::string wrap = test::write_gltf(dir, a, "wrap.gltf");
  const std::string m2 = error_of([&] { load_scene(wrap); });
  EXPECT_TRUE(contains(m2, "the file declares far more data than it holds")) << m2;
}

// Primitives sharing one vertex accessor decode only the vertices their indices use.
TEST(GltfErrors, SharedVertexAccessorIsCompacted) {
  TempDir dir;
  Asset a = make_asset();
  const size_t at = a.bin.size();
  test::put<uint8_t>(a.bin, {0, 1, 2, 0, 2, 3, 0, 0});  // two triangles of the quad
  a.json["buffers"][0]["byteLength"] = a.bin.size();
  a.json["bufferViews"][0]["byteLength"] = a.bin.size();
  a.json["accessors"].push_back({{"bufferView", 0},
                                 {"byteOffset", at},
                                 {"componentType", 5121},
                                 {"type", "SCALAR"},
                                 {"count", 3}});
  a.json["accessors"].push_back({{"bufferView", 0},
                                 {"byteOffset", at + 3},
                                 {"componentType", 5121},
                                 {"type", "SCALAR"},
                                 {"count", 3}});
  a.json["meshes"][0]["primitives"] = {
      {{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 7}, {"material", 3}},
      {{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 8}, {"material", 2}}};
  const Scene scene = load_scene(test::write_gltf(dir, a));
  const vec3 corners[2][3] = {{vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 1, 0)},
                              {vec3(0, 0, 0), vec3(1, 1, 0), vec3(0, 1, 0)}};
  int checked = 0;
  for (const Mesh& m : scene.meshes) {
    if (m.name != "quad/0" && m.name != "quad/1") continue;
    const int which = m.name == "quad/0" ? 0 : 1;
    ASSERT_EQ(m.vertex_count(), 3u) << m.name;  // not the accessor's 4
    ASSERT_EQ(m.uv0.size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[m.indices[k]], corners[which][k]) << m.name;
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

// A chain of 100,000 nodes, each one translating by +x: the walk is iterative (the recursive
// one exhausted the stack), and the leaf's world transform is the exact sum.
TEST(GltfErrors, LongNodeChainLoads) {
  TempDir dir;
  Asset a = make_asset();
  const int n = 100000;
  json nodes = json::array();
  for (int i = 0; i < n; ++i) {
    json node = {{"translation", {1, 0, 0}}};
    if (i + 1 < n) node["children"] = {i + 1};
    nodes.push_back(std::move(node));
  }
  nodes[n - 1]["mesh"] = 0;
  nodes[n - 1]["name"] = "leaf";
  a.json["nodes"] = std::move(nodes);
  a.json["scenes"] = {{{"nodes", {0}}}};
  const Scene scene = load_scene(test::write_gltf(dir, a, "chain.gltf"));
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].name, "leaf");
  // Integers up to 2²⁴ add exactly in float.
  EXPECT_EQ(scene.instances[0].transform[3].x, static_cast<float>(n));
}

}  // namespace
}  // namespace illum
