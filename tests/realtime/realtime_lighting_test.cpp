// The real-time forward path's lighting (and the visibility buffer's), pixel by pixel, against a
// CPU reference that shares no code with the shaders: the offline renderers' own pieces
// (illum::RayTracer for the visible point, its normal-mapped shading normal and uv, illum::Bsdf for
// Lambert / Phong / Blinn, LightSampler::sample_li for point, spot and sun radiometry,
// surface_emission for textured emission, texture_color's bilinear lookups) plus, written here from
// scene.h's definition, the real-time-only range window max(1 − (d/r)², 0).
//
// The scene is one large floor filling the frame (no geometry edges, nothing to cast
// shadows: the reference asserts that no shadow ray is blocked), seen from above at 64×64.
// Every pixel is compared; the tolerance of each is derived below from the formats and the
// device's texture-filter precision, and every pixel must be inside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "illum/core/color.h"
#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"
#include "illum/trace/ray_tracer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;  // the floor spans [−2, 2]² m at y = 0
// The HDR target is fp16 (relative rounding 2⁻¹¹) and both sides shade in float32 from
// positions that differ by the rasteriser's interpolation (≈ 1e-6 relative): 2⁻¹⁰ covers
// both with a factor-2 margin. Where a window or a cone's edge takes the radiance toward 0,
// relative error is meaningless; there the same 2⁻¹⁰ applies to the image's brightest pixel.
constexpr float kShadingRel = 1.0f / 1024.0f;

class RealtimeLighting : public test::ValidatedVulkanTest {};

// A 16×16 texture of 8-bit codes (so the GPU's UNORM upload holds exactly these values):
// `base` ± `spread` per channel from a hash, smooth enough that neighbouring texels differ
// by at most `spread`. Linear (not sRGB): UNORM conversion is exact by the Vulkan spec,
// while the precision of sRGB decoding is left to the implementation.
Texture random_texture(Color base, float spread, uint32_t seed) {
  Texture t;
  t.srgb = false;
  t.image = Image(16, 16, 4, 1.0f);
  uint32_t h = seed * 2654435761u + 12345u;
  auto next = [&] {
    h ^= h << 13;
    h ^= h >> 17;
    h ^= h << 5;
    return static_cast<float>(h % 1000u) / 999.0f;  // [0, 1]
  };
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int k = 0; k < 3; ++k) {
        const float v = std::clamp(base[k] + spread * (2.0f * next() - 1.0f), 0.0f, 1.0f);
        t.image.pixel(x, y)[k] = std::round(v * 255.0f) / 255.0f;
      }
  return t;
}

// Tangent-space normals tilted by up to `max_tilt` radians in varying directions, encoded
// as (n + 1)/2 in 8-bit codes.
Texture random_normal_map(float max_tilt, uint32_t seed) {
  Texture t = random_texture(Color(0.5f), 0.5f, seed);  // two uniform numbers per texel
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      float* p = t.image.pixel(x, y);
      const float tilt = max_tilt * p[0], phi = 2.0f * kPi * p[1];
      const vec3 n(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
      for (int k = 0; k < 3; ++k) p[k] = std::round((0.5f * n[k] + 0.5f) * 255.0f) / 255.0f;
    }
  return t;
}

// Bound on the error of a bilinear lookup from the GPU's sub-texel precision (weights on a
// grid of 2^-bits): at most 2^-bits × (largest step between neighbouring texels along x
// plus along y), relative to the smallest texel value.
float filter_error(const Texture& t, bool relative) {
  const int bits = static_cast<int>(context().limits().subTexelPrecisionBits);
  float step_x = 0.0f, step_y = 0.0f, smallest = 1.0f;
  const Image& im = t.image;
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x)
      for (int k = 0; k < 3; ++k) {
        const float v = im.pixel(x, y)[k];
        smallest = std::min(smallest, v);
        step_x = std::max(step_x, std::abs(v - im.pixel((x + 1) % im.width(), y)[k]));
        step_y = std::max(step_y, std::abs(v - im.pixel(x, (y + 1) % im.height())[k]));
      }
  const float absolute = std::ldexp(step_x + step_y, -bits);
  return relative ? absolute / smallest : absolute;
}

Scene floor_scene(const Material& material) {
  Scene s;
  s.name = "lit-floor";
  s.materials = {material};
  Mesh m;
  m.positions = {{-kHalf, 0, -kHalf}, {-kHalf, 0, kHalf}, {kHalf, 0, kHalf}, {kHalf, 0, -kHalf}};
  m.normals.assign(4, vec3(0, 1, 0));
  m.tangents.assign(4, vec4(1, 0, 0, 1));  // u along +x; v (the bitangent, n × t) along −z
  for (const vec3& p : m.positions) m.uv0.push_back({(p.x + kHalf) / 4.0f, (kHalf - p.z) / 4.0f});
  m.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back(m);
  s.instances.push_back({"floor", 0, mat4(1.0f)});
  Camera c;
  c.position = vec3(0.1f, 2.5f, 1.2f);
  c.look_at = vec3(0.0f, 0.0f, -0.1f);
  c.fov_y = radians(40.0f);
  s.camera = c;
  return s;
}

struct Reference {
  Image radiance{kSize, kSize, 3};
  std::vector<float> tolerance;   // per pixel, relative
  std::vector<uint8_t> excluded;  // a hard cone edge runs through the pixel's neighbourhood
  std::vector<uint8_t> lit;       // some light reaches the pixel
  size_t floor_pixels = 0, blocked = 0, below_shading_normal = 0;
  float brightest = 0.0f;
};

// `texture_rel`: the relative error bound of the albedo/emission lookups; `normal_abs`: the
// absolute error bound of a normal-map lookup, which moves cos θ by at most that much.
Reference cpu_reference(const Scene& scene, float texture_rel = 0.0f, float normal_abs = 0.0f) {
  const RayTracer tracer(scene);
  const LightSampler lights(scene);
  Reference ref;
  ref.tolerance.assign(kSize * kSize, kShadingRel);
  ref.excluded.assign(kSize * kSize, 0);
  ref.lit.assign(kSize * kSize, 0);
  std::vector<int> in_cone(kSize * kSize, -1);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = static_cast<size_t>(y) * kSize + x;
      const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, kSize, kSize);
      Hit hit;
      if (!tracer.intersect(ray, &hit)) continue;
      ++ref.floor_pixels;
      const SurfaceInteraction si = tracer.interaction(ray, hit);
      const Bsdf bsdf(scene, si);
      Color L = surface_emission(scene, si);
      float tolerance = kShadingRel + texture_rel;
      for (int li = 0; li < lights.light_count(); ++li) {
        const Light& light = scene.lights[static_cast<size_t>(li)];
        const std::optional<LightSample> s = lights.sample_li(li, si.p, vec2(0.5f));
        if (light.type == LightType::kSpot) in_cone[i] = s.has_value() ? 1 : 0;
        if (!s) continue;
        if (tracer.occluded(shadow_ray(si.p, si.ng, *s))) {
          ++ref.blocked;
          continue;
        }
        const float cos_s = glm::dot(s->wi, si.ns);
        if (cos_s <= 0.0f && glm::dot(s->wi, si.ng) > 0.0f) ++ref.below_shading_normal;
        // The range window of scene.h: max(1 − (d/r)², 0), real time only.
        float window = 1.0f;
        if (light.range > 0.0f)
          window = std::max(1.0f - (s->distance * s->distance) / (light.range * light.range), 0.0f);
        const Color c = bsdf.eval(si.wo, s->wi) * s->li * (std::abs(cos_s) * window / s->pdf);
        if (!is_black(c)) ref.lit[i] = 1;
        L += c;
        if (normal_abs > 0.0f && std::abs(cos_s) > 0.0f)
          tolerance = std::max(tolerance, kShadingRel + texture_rel + normal_abs / std::abs(cos_s));
      }
      ref.radiance.set_rgb(x, y, L);
      ref.tolerance[i] = tolerance;
      ref.brightest = std::max(ref.brightest, std::max(L.r, std::max(L.g, L.b)));
    }
  // A spot's hard edge: a pixel centre on either side of it may shade either way.
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, kSize - 1), yy = std::clamp(y + dy, 0, kSize - 1);
          if (in_cone[static_cast<size_t>(yy) * kSize + xx] !=
              in_cone[static_cast<size_t>(y) * kSize + x])
            ref.excluded[static_cast<size_t>(y) * kSize + x] = 1;
        }
  return ref;
}

Image render_pipeline(const Scene& scene, const std::string& pipeline) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = pipeline;
  o.shadows = "none";  // nothing casts a shadow here (the reference checks it)
  o.disable("luminance");
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  return r.hdr();
}

struct Comparison {
  size_t compared = 0, outside = 0, lit = 0;
  double worst = 0.0;  // largest |gpu − cpu| / allowed over the pixels and channels
};

Comparison compare(const Image& gpu, const Reference& ref) {
  Comparison c;
  const float floor = kShadingRel * ref.brightest;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = static_cast<size_t>(y) * kSize + x;
      if (ref.excluded[i]) continue;
      const Color g = gpu.rgb(x, y), r = ref.radiance.rgb(x, y);
      double worst = 0.0;
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst,
                         std::abs(double(g[k]) - r[k]) / (double(ref.tolerance[i]) * r[k] + floor));
      ++c.compared;
      c.lit += ref.lit[i];
      c.outside += worst > 1.0 ? 1 : 0;
      c.worst = std::max(c.worst, worst);
    }
  return c;
}

// Runs one case: the reference must see the whole frame as floor with nothing blocked, and
// every compared pixel must agree within its tolerance.
Comparison check(const Scene& scene, const char* name, float texture_rel = 0.0f,
                 float normal_abs = 0.0f) {
  const Reference ref = cpu_reference(scene, texture_rel, normal_abs);
  EXPECT_EQ(ref.floor_pixels, static_cast<size_t>(kSize * kSize)) << name;
  EXPECT_EQ(ref.blocked, 0u) << name << ": the scene must not cast shadows";
  EXPECT_EQ(ref.below_shading_normal, 0u)
      << name << ": lights below the shading normal shade differently by design";
  // The visibility buffer shades with the same functions from the triangle it rebuilds, its
  // texture LOD from analytic derivatives (here every texture is magnified: level 0 in both,
  // so the same filter bound holds).
  Comparison c;
  for (const std::string pipeline : {"forward", "visibility"}) {
    c = compare(render_pipeline(scene, pipeline), ref);
    std::printf(
        "%-28s %-10s %zu pixels compared (%zu lit), %zu outside their tolerance, worst %.3f of "
        "it\n",
        name, pipeline.c_str(), c.compared, c.lit, c.outside, c.worst);
    EXPECT_EQ(c.outside, 0u) << name << " (" << pipeline << "): worst error " << c.worst
                             << " × the tolerance";
  }
  return c;
}

Light point_light(vec3 position, Color intensity) {
  Light l;
  l.type = LightType::kPoint;
  l.position = position;
  l.intensity = intensity;
  return l;
}

Material lambert(Color albedo) {
  Material m;
  m.albedo = albedo;
  return m;
}

TEST_F(RealtimeLighting, PointLightWithRangeWindow) {
  Scene scene = floor_scene(lambert(Color(0.7f, 0.6f, 0.5f)));
  Light l = point_light(vec3(0.3f, 0.8f, -0.2f), Color(1.0f, 0.9f, 0.8f));
  l.range = 1.5f;  // reaches the floor within 1.27 m of the light's foot: the window shows
  scene.lights = {l};
  const Comparison c = check(scene, "point, range 1.5 m");
  EXPECT_GT(c.lit, c.compared / 4);
  EXPECT_LT(c.lit, c.compared - c.compared / 8) << "the window's end must be in view";
}

TEST_F(RealtimeLighting, SpotLightInsideItsCone) {
  Scene scene = floor_scene(lambert(Color(0.6f, 0.65f, 0.7f)));
  Light spot = point_light(vec3(-0.4f, 1.2f, 0.3f), Color(3.0f, 2.5f, 2.0f));
  spot.type = LightType::kSpot;
  spot.direction = glm::normalize(vec3(0.4f, -1.0f, -0.3f));
  spot.cone_half_angle = radians(30.0f);
  scene.lights = {spot};
  const Comparison c = check(scene, "spot, 30° cone");
  EXPECT_GT(c.lit, c.compared / 8);
  EXPECT_LT(c.lit, c.compared - c.compared / 8) << "the cone's edge must be in view";
}

TEST_F(RealtimeLighting, SunIrradiance) {
  Scene scene = floor_scene(lambert(Color(0.5f, 0.55f, 0.6f)));
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.5f, -1.0f, 0.7f));
  sun.irradiance = Color(2.0f, 1.8f, 1.5f);
  scene.lights = {sun};
  check(scene, "sun");
}

// Specular lobes are sharp (exponent 40) and the light sits where the highlight is in view.
Scene specular_scene(MaterialType type) {
  Material m = lambert(Color(0.3f, 0.35f, 0.4f));
  m.type = type;
  m.specular = Color(0.5f, 0.45f, 0.4f);
  m.exponent = 40.0f;
  Scene scene = floor_scene(m);
  scene.lights = {point_light(vec3(-0.2f, 1.0f, -0.9f), Color(1.5f))};
  return scene;
}

TEST_F(RealtimeLighting, PhongSpecular) {
  check(specular_scene(MaterialType::kPhong), "Phong, n = 40");
}

TEST_F(RealtimeLighting, BlinnSpecular) {
  check(specular_scene(MaterialType::kBlinn), "Blinn, n = 40");
}

// Albedo and tangent-space normal maps on a Lambert floor. The normal map's lookup error
// moves cos θ by at most its own bound (a unit normal's components), which the reference
// adds per pixel as that bound / cos θ.
TEST_F(RealtimeLighting, AlbedoAndNormalTextures) {
  Material m = lambert(Color(1.0f));
  m.albedo_texture = 0;
  m.normal_texture = 1;
  Scene scene = floor_scene(m);
  scene.textures = {random_texture(Color(0.55f, 0.5f, 0.45f), 0.2f, 1),
                    random_normal_map(radians(30.0f), 2)};
  scene.lights = {point_light(vec3(0.2f, 1.4f, -0.3f), Color(2.0f, 1.9f, 1.8f))};
  // Decoding n = 2c − 1 doubles each component's lookup error, three components make the
  // vector's error up to √3 times that, and normalising a blend of normals at most 60° apart
  // (length ≥ cos 30° = 0.87) divides by at least 0.87: 2·√3/0.87 < 4.
  check(scene, "albedo + normal maps", filter_error(scene.textures[0], true),
        4.0f * filter_error(scene.textures[1], false));
}

// Emission × emission texture, plus a light so the sum is checked too.
TEST_F(RealtimeLighting, TexturedEmission) {
  Material m = lambert(Color(0.4f));
  m.emission = Color(0.8f, 0.6f, 0.4f);
  m.emission_texture = 0;
  Scene scene = floor_scene(m);
  scene.textures = {random_texture(Color(0.5f), 0.3f, 3)};
  scene.lights = {point_light(vec3(0.0f, 1.0f, 0.0f), Color(0.3f))};
  check(scene, "textured emission", filter_error(scene.textures[0], true));
}

}  // namespace
}  // namespace illum::realtime
