// The scene model every loader fills and every renderer, baker and GPU pass reads.
// Units: metres (loaders apply a scene's declared scale), right-handed, +y up.
// Radiometry in SI, linear RGB per channel.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "illum/core/color.h"
#include "illum/core/image.h"
#include "illum/core/math.h"
#include "illum/scene/camera.h"

namespace illum {

inline constexpr int kNoTexture = -1;

struct Texture {
  std::string path;  // where it was loaded from (for messages)
  Image image;       // linear values; colour textures decoded from sRGB at load
  bool srgb = true;  // how the source was encoded
};

enum class MaterialType {
  kLambert,  // f = albedo / π
  kPhong,  // energy-normalized: albedo/π + specular·(n+2)/(2π)·cos^n(α) (α to the mirror direction)
  kBlinn,       // energy-normalized: albedo/π + specular·(n+8)/(8π)·cos^n(θh)
  kMirror,      // perfect specular reflection scaled by `specular`
  kDielectric,  // glass, index `ior`: smooth (Fresnel + Snell) or, with `alpha`, GGX (Walter 2007)
  kConductor,   // metal, complex index eta + i·k: smooth or, with `alpha`, GGX microfacets
};

// Below this GGX α a conductor or dielectric is smooth (delta lobes): the microfacet
// lobe would be narrower than float directions resolve and its pdf would overflow.
inline constexpr float kMinMicrofacetAlpha = 1e-3f;

const char* to_string(MaterialType type);

struct Material {
  std::string name;
  MaterialType type = MaterialType::kLambert;
  Color albedo{0.8f};                  // diffuse reflectance ρ
  int albedo_texture = kNoTexture;     // multiplies albedo (RGB)
  Color specular{0.0f};                // Phong/Blinn ks; mirror reflectance
  float exponent = 32.0f;              // Phong/Blinn shininess n
  float roughness = 1.0f;              // glTF roughness (kept for real-time shading and export)
  int roughness_texture = kNoTexture;  // glTF metallic-roughness: G = roughness
  float ior = 1.5f;                    // dielectric index of refraction (outside is 1)
  Color transmittance{1.0f};           // dielectric tint per crossing
  Color eta{0.2f, 0.92f, 1.1f};        // conductor complex index, real part (default gold)
  Color k{3.9f, 2.45f, 2.14f};         // conductor complex index, imaginary part
  Color emission{0.0f};                // emitted radiance L_e, W/(sr·m²)
  int emission_texture = kNoTexture;   // multiplies emission
  int normal_texture = kNoTexture;     // tangent-space normal map (linear, [0,1] → [-1,1])
  float normal_scale = 1.0f;
  float opacity = 1.0f;  // 1 = opaque (kept for real-time; offline treats as opaque)
  // GGX α of conductors and dielectrics (offline); below kMinMicrofacetAlpha they are smooth.
  float alpha = 0.0f;

  bool is_emissive() const { return !is_black(emission); }
  bool is_specular() const {  // delta BSDF: no next-event estimation possible
    return type == MaterialType::kMirror ||
           ((type == MaterialType::kDielectric || type == MaterialType::kConductor) &&
            alpha < kMinMicrofacetAlpha);
  }
};

// Triangle mesh in object space. Attributes are per vertex; `indices` holds 3 per triangle.
struct Mesh {
  std::string name;
  std::vector<vec3> positions;
  std::vector<vec3> normals;   // unit; same size as positions (loaders compute them if absent)
  std::vector<vec4> tangents;  // xyz unit tangent, w = ±1 bitangent sign; empty if no uv0
  std::vector<vec2> uv0;       // texture coordinates, may be empty
  std::vector<vec2> uv1;       // light-map coordinates, may be empty (the atlas fills them)
  std::vector<uint32_t> indices;
  int material = 0;

  size_t triangle_count() const { return indices.size() / 3; }
  size_t vertex_count() const { return positions.size(); }
};

// The largest per-object light-map texel a scene file may ask for: a texel wider than a
// kilometre is a typo (a unit mix-up), not a light-map.
inline constexpr float kMaxLightmapTexelSize = 1000.0f;

struct Instance {
  std::string name;
  int mesh = 0;
  mat4 transform{1.0f};  // object → world
  // Marked `"dynamic": true` in a scene file: an object that moves at run time, so bakes
  // leave it out of their geometry and the real-time renderer lights it from the probes
  // (realtime/probe_volume.h) instead of a light-map.
  bool dynamic = false;
  // `"lightmap": {"texel_size": s}` in a scene file: this object's light-map texels are s
  // metres, whatever the bake's --texel-size (0: the bake's).
  float lightmap_texel_size = 0.0f;
};

enum class LightType { kPoint, kSpot, kDirectional, kArea, kEnvironment };

const char* to_string(LightType type);

// Lights. Point and spot lights store radiant intensity I (W/sr per channel); a light given
// by flux is converted at load: point I = Φ/(4π), spot I = Φ/Ω with Ω = 2π(1 − cos θc)
// (S004's convention: the flux spread uniformly over the cone). Directional lights store
// the irradiance E (W/m²) on a surface facing them. Area lights are the emissive triangles
// of one instance (radiance comes from its material). The environment light refers to
// Scene::environment.
struct Light {
  std::string name;
  LightType type = LightType::kPoint;
  vec3 position{0.0f};
  vec3 direction{0.0f, -1.0f, 0.0f};       // spot axis / direction the directional light travels
  Color intensity{0.0f};                   // point, spot: W/sr
  float cone_half_angle = radians(45.0f);  // spot: θc, hard edge
  Color irradiance{0.0f};                  // directional: W/m²
  int instance = -1;                       // area: instance whose emissive triangles emit
  float range = 0.0f;  // real-time culling radius r in max(1−(d/r)², 0); 0 = none
  // Spot only, set by the real-time renderer for an area light seen from afar: intensity
  // `intensity`·cos θ at angle θ from the axis (a Lambertian emitter), not constant.
  bool cosine_falloff = false;
  // The scene file's light-map (Scene::lightmap) already holds this light's light: a display
  // of that map leaves the light out, so it is not counted twice (glTF: extras.illum_baked).
  bool in_lightmap = false;

  float cos_cutoff() const { return std::cos(cone_half_angle); }
  // Ω = 2π(1 − cos θc): the spot's cone solid angle.
  float cone_solid_angle() const { return 2.0f * kPi * (1.0f - cos_cutoff()); }
  bool is_delta() const {
    return type == LightType::kPoint || type == LightType::kSpot || type == LightType::kDirectional;
  }
};

// Equirectangular HDR environment: +y is the zenith (top row), u = 0.5 looks down −z.
// The direction → (u, v) mapping lives in scene/environment.h.
struct Environment {
  std::string path;
  Image radiance;           // linear radiance per texel
  float scale = 1.0f;       // multiplies the map
  float rotation_y = 0.0f;  // radians about +y
  Color constant{0.0f};     // used where `radiance` is empty (uniform sky)
};

// Settings a scene file may carry for the jobs that render it (CLI options override them).
struct SceneSettings {
  int width = 512;
  int height = 512;
  int spp = 16;
  int max_bounces = 8;
  // Real-time renderers' constant ambient radiance factor (× albedo) when no light-map is
  // shown: a stand-in for the indirect light a rasterizer does not compute.
  Color ambient{0.0f};
};

// A light-map the scene file carries: illum's glTF export (MSFT_lightmap on TEXCOORD_1 with
// the decoding in the extension's extras, docs/lightmaps.md "Export to glTF"). The loader
// decodes it to linear RGB (RGBM: rgb·a·range); it is read on Mesh::uv1 and holds E/π, as a
// plain light-map folder's layer. Kept apart from Scene::textures, which materials sample
// as 8-bit colour.
struct SceneLightmap {
  Image image;           // RGB; empty when the load skipped textures
  std::string encoding;  // "RGBM"
  float range = 1.0f;    // RGBM's M
  std::string tone;      // "none": the values are E/π; "lrp97": display values in [0, 1]
  std::string basis;     // the folder's basis it was reduced from ("" when the file omits it)
  std::string layer;     // what the exporter says the map holds
};

struct Scene {
  std::string name;         // built-in name or file stem
  std::string source_path;  // file it was loaded from ("" for procedural)
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::optional<Environment> environment;
  std::optional<Camera> camera;
  std::optional<SceneLightmap> lightmap;
  SceneSettings settings;
  std::vector<std::string> warnings;  // non-fatal load findings (dropped triangles, ...)

  size_t triangle_count() const;  // over instances
  Bounds3 bounds() const;         // world space, over instances
};

}  // namespace illum
