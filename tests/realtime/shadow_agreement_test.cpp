// Shadow techniques against a ray-traced shadow mask (illum::RayTracer): stencil shadow
// volumes (front- and back-facing casters), shadow maps (PCF and VSM) must agree on which pixels
// are shadowed for ≥ 99% of the pixels away from geometry and shadow edges.
#include <gtest/gtest.h>

#include <cstdio>

#include "illum/core/color.h"
#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "illum/trace/ray_tracer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 128;

// Ray-traced mask: 1 where the first light is blocked or behind the surface; surface ids per
// pixel for the edge band.
// `blocked` counts the pixels lit but for an occluder (the shadows proper).
test::Reference ray_traced_mask(const Scene& scene, size_t* blocked = nullptr) {
  const RayTracer tracer(scene);
  test::Reference ref;
  ref.surface.assign(kSize * kSize, -1);
  ref.shadowed.assign(kSize * kSize, 0);
  const Light& light = scene.lights[0];
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, kSize, kSize);
      Hit hit;
      if (!tracer.intersect(ray, &hit)) continue;
      const size_t i = static_cast<size_t>(y) * kSize + x;
      ref.surface[i] = static_cast<int>(hit.instance);
      const SurfaceInteraction si = tracer.interaction(ray, hit);
      vec3 ng = si.ng;
      if (glm::dot(ng, ray.direction) > 0.0f) ng = -ng;
      const bool directional = light.type == LightType::kDirectional;
      const vec3 to = directional ? -glm::normalize(light.direction) : light.position - si.p;
      const float dist = directional ? kInf : glm::length(to);
      const vec3 l = directional ? to : to / dist;
      // Outside a spot light's cone counts as shadowed (unlit in both renders).
      const bool outside_cone = light.type == LightType::kSpot &&
                                glm::dot(-l, glm::normalize(light.direction)) < light.cos_cutoff();
      if (glm::dot(ng, l) <= 0.0f || outside_cone) {
        ref.shadowed[i] = 1;
        continue;
      }
      Ray shadow;
      shadow.origin = offset_ray_origin(si.p, ng, l);
      shadow.direction = l;
      shadow.tmax = directional ? kInf : dist * (1.0f - 1e-4f);
      ref.shadowed[i] = tracer.occluded(shadow) ? 1 : 0;
      if (blocked) *blocked += ref.shadowed[i];
    }
  return ref;
}

Image render_hdr(const Scene& scene, ShadowMode mode, bool back_faces = false) {
  RendererOptions o;
  o.width = o.height = kSize;
  o.shadows = mode;
  o.pcf_taps = 1;
  o.shadow_resolution = 512;
  o.volume_back_faces = back_faces;
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  return r.hdr();
}

// Shadowed where the shadowed render is below half the unshadowed one (or both are black:
// the surface faces away from the light).
std::vector<uint8_t> gpu_mask(const Image& shadowed, const Image& unshadowed) {
  std::vector<uint8_t> m(kSize * kSize, 0);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float s = luminance(shadowed.rgb(x, y)), u = luminance(unshadowed.rgb(x, y));
      m[static_cast<size_t>(y) * kSize + x] = (u <= 0.0f || s < 0.5f * u) ? 1 : 0;
    }
  return m;
}

void check_agreement(const Scene& scene) {
  const size_t before = context().validation_message_count();
  size_t blocked = 0;
  const test::Reference ref = ray_traced_mask(scene, &blocked);
  ASSERT_GT(blocked, static_cast<size_t>(kSize * kSize / 50)) << "the test needs cast shadows";
  const std::vector<uint8_t> edge = test::edge_mask(ref, kSize, kSize, 1);
  size_t shadowed_pixels = 0;
  for (uint8_t s : ref.shadowed) shadowed_pixels += s;
  ASSERT_GT(shadowed_pixels, static_cast<size_t>(kSize * kSize / 50))
      << "the test needs visible shadows";

  const Image unshadowed = render_hdr(scene, ShadowMode::kNone);
  struct Case {
    const char* name;
    ShadowMode mode;
    bool back;
  };
  for (const Case& c :
       {Case{"shadow map", ShadowMode::kMap, false}, Case{"VSM", ShadowMode::kVsm, false},
        Case{"volumes (front casters)", ShadowMode::kVolume, false},
        Case{"volumes (back casters)", ShadowMode::kVolume, true}}) {
    const std::vector<uint8_t> mask = gpu_mask(render_hdr(scene, c.mode, c.back), unshadowed);
    size_t compared = 0, agree = 0, shadowed = 0;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (edge[i] || ref.surface[i] < 0) continue;
      ++compared;
      agree += mask[i] == ref.shadowed[i] ? 1 : 0;
      shadowed += mask[i];
    }
    const double fraction = static_cast<double>(agree) / compared;
    std::printf("%-24s agrees with the ray-traced mask on %.4f of %zu pixels (%zu shadowed)\n",
                c.name, fraction, compared, shadowed);
    EXPECT_GE(fraction, 0.99) << c.name;
  }
  EXPECT_EQ(context().validation_message_count(), before) << "validation messages were emitted";
}

TEST(ShadowAgreement, PointLightVolumesCubeMapsAndRayTracedMaskAgree) {
  check_agreement(test::cornell_point_light());
}

// A narrow spot light (one 2-D perspective shadow map instead of a cube) at the point
// light's position, aimed down past the blocks.
TEST(ShadowAgreement, SpotLightVolumesSpotMapAndRayTracedMaskAgree) {
  Scene scene = test::cornell_point_light();
  Light& spot = scene.lights[0];
  spot.type = LightType::kSpot;
  spot.direction = glm::normalize(vec3(0.1f, -1.0f, 0.15f));
  spot.cone_half_angle = radians(55.0f);
  ASSERT_LE(spot.cone_half_angle, kMaxSpotMapHalfAngle) << "the test must use a 2-D spot map";
  check_agreement(scene);
}

// A roofless box under a directional light: cascaded shadow maps and volumes with caps at
// infinity along the light direction.
TEST(ShadowAgreement, DirectionalLightVolumesCascadesAndRayTracedMaskAgree) {
  Scene scene = test::cornell_point_light();
  scene.instances.erase(scene.instances.begin() + 1);  // the ceiling
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.35f, -1.0f, -0.25f));
  sun.irradiance = Color(2.0f);
  scene.lights = {sun};
  check_agreement(scene);
}

}  // namespace
}  // namespace illum::realtime
