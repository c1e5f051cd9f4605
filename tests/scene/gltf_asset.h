// A small glTF asset for the scene tests, built in memory: a textured quad under a scaled
// parent, a two-primitive mesh (plus a points primitive that is skipped), punctual lights, a
// camera and materials using the extensions illum reads. write_gltf embeds the buffer as a
// base64 data URI; write_glb packs the same asset into a binary container.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace illum::test {

inline std::string base64(const std::vector<uint8_t>& data) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    const uint32_t b0 = data[i], b1 = i + 1 < data.size() ? data[i + 1] : 0,
                   b2 = i + 2 < data.size() ? data[i + 2] : 0;
    const uint32_t n = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

template <typename T>
inline void put(std::vector<uint8_t>& buf, std::initializer_list<T> values) {
  for (T v : values) {
    const size_t at = buf.size();
    buf.resize(at + sizeof(T));
    std::memcpy(buf.data() + at, &v, sizeof(T));
  }
}

struct Asset {
  nlohmann::json json;
  std::vector<uint8_t> bin;
};

inline Asset make_asset() {
  Asset a;
  auto& b = a.bin;
  put<float>(b, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});  // 0: quad positions
  put<float>(b, {0, 0, 1, 0, 1, 1, 0, 1});              // 48: quad uvs
  put<uint8_t>(b, {0, 1, 2, 0, 2, 3, 0, 0});            // 80: quad indices (+2 pad)
  put<float>(b, {0, 0, 0, 1, 0, 0, 0, 1, 0});           // 88: triangle positions
  put<uint16_t>(b, {0, 1, 2, 0});                       // 124: ushort indices (+pad)
  put<uint16_t>(b, {0, 0, 65535, 0, 0, 65535});         // 132: normalized ushort uvs
  put<uint32_t>(b, {0, 1, 2});                          // 144: uint indices
  using nlohmann::json;
  json& j = a.json;
  j["asset"] = {{"version", "2.0"}};
  j["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                         "KHR_materials_ior", "KHR_materials_transmission"};
  j["buffers"] = json::array({{{"byteLength", b.size()}}});
  j["bufferViews"] = json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", b.size()}}});
  auto acc = [](int offset, int type, const char* kind, int count, bool normalized = false) {
    json x = {{"bufferView", 0},
              {"byteOffset", offset},
              {"componentType", type},
              {"type", kind},
              {"count", count}};
    if (normalized) x["normalized"] = true;
    return x;
  };
  j["accessors"] =
      json::array({acc(0, 5126, "VEC3", 4), acc(48, 5126, "VEC2", 4), acc(80, 5121, "SCALAR", 6),
                   acc(88, 5126, "VEC3", 3), acc(124, 5123, "SCALAR", 3),
                   acc(132, 5123, "VEC2", 3, true), acc(144, 5125, "SCALAR", 3)});
  j["accessors"][0]["min"] = {0, 0, 0};
  j["accessors"][0]["max"] = {1, 1, 0};
  j["accessors"][3]["min"] = {0, 0, 0};
  j["accessors"][3]["max"] = {1, 1, 0};
  j["meshes"] = json::array(
      {{{"name", "quad"},
        {"primitives",
         {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}},
           {"indices", 2},
           {"material", 0}}}}},
       {{"name", "pair"},
        {"primitives",
         {{{"attributes", {{"POSITION", 3}, {"TEXCOORD_0", 5}}}, {"indices", 4}, {"material", 1}},
          {{"attributes", {{"POSITION", 3}}}, {"indices", 6}, {"material", 2}},
          {{"attributes", {{"POSITION", 3}}}, {"mode", 0}}}}}});
  const float h = std::sqrt(0.5f);
  j["nodes"] = json::array(
      {{{"name", "parent"}, {"translation", {1, 0, 0}}, {"scale", {2, 2, 2}}, {"children", {1}}},
       {{"name", "quad_node"}, {"mesh", 0}, {"rotation", {0, h, 0, h}}},
       {{"name", "cam"}, {"camera", 0}, {"translation", {0, 1, 5}}},
       {{"name", "spot"},
        {"translation", {0, 3, 0}},
        {"rotation", {-h, 0, 0, h}},
        {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
       {{"name", "bulb"},
        {"translation", {2, 2, 2}},
        {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
       {{"name", "pair_node"},
        {"mesh", 1},
        {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -3, 1}}}});
  j["scenes"] = json::array({{{"nodes", {0, 2, 3, 4, 5}}}});
  j["scene"] = 0;
  j["cameras"] =
      json::array({{{"type", "perspective"},
                    {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"aspectRatio", 1.5}}}}});
  j["extensions"]["KHR_lights_punctual"]["lights"] =
      json::array({{{"type", "spot"},
                    {"intensity", 10},
                    {"color", {1, 1, 1}},
                    {"range", 7},
                    {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.5}}}},
                   {{"type", "point"}, {"intensity", 3}, {"color", {1, 0, 0}}}});
  auto pbr = [](std::vector<double> base, double metallic, double roughness) {
    return json{
        {"baseColorFactor", base}, {"metallicFactor", metallic}, {"roughnessFactor", roughness}};
  };
  j["materials"] = json::array(
      {{{"name", "emitter"},
        {"pbrMetallicRoughness", pbr({0.5, 0.5, 0.5, 1}, 0, 1)},
        {"emissiveFactor", {1, 0.5, 0.25}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
       {{"name", "glass"},
        {"pbrMetallicRoughness", pbr({0.9, 1, 0.9, 1}, 0, 0)},
        {"extensions",
         {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
          {"KHR_materials_ior", {{"ior", 1.33}}}}}},
       {{"name", "gold"}, {"pbrMetallicRoughness", pbr({1.0, 0.766, 0.336, 1}, 1, 0.2)}},
       {{"name", "plastic"}, {"pbrMetallicRoughness", pbr({0.2, 0.3, 0.8, 1}, 0, 0.3)}}});
  return a;
}

// The asset as .gltf text, its buffer embedded as a base64 data URI.
inline std::string gltf_text(Asset a) {
  a.json["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(a.bin);
  return a.json.dump(2);
}

inline std::string write_gltf(const TempDir& dir, Asset a, const std::string& name = "asset.gltf") {
  return dir.write(name, gltf_text(std::move(a)));
}

inline std::string write_glb(const TempDir& dir, const Asset& a,
                             const std::string& name = "asset.glb") {
  std::string json = a.json.dump();
  while (json.size() % 4) json += ' ';
  std::vector<uint8_t> bin = a.bin;
  while (bin.size() % 4) bin.push_back(0);
  std::vector<uint8_t> out;
  const uint32_t total =
      12 + 8 + static_cast<uint32_t>(json.size()) + 8 + static_cast<uint32_t>(bin.size());
  put<uint32_t>(out, {0x46546C67u, 2u, total});
  put<uint32_t>(out, {static_cast<uint32_t>(json.size()), 0x4E4F534Au});
  out.insert(out.end(), json.begin(), json.end());
  put<uint32_t>(out, {static_cast<uint32_t>(bin.size()), 0x004E4942u});
  out.insert(out.end(), bin.begin(), bin.end());
  return dir.write(name, std::string(out.begin(), out.end()));
}

}  // namespace illum::test
