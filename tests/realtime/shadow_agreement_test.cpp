// Shadow techniques against a ray-traced shadow mask (illum::RayTracer): stencil shadow
// volumes (front- and back-facing casters; forward and deferred; silhouettes from the GPU
// extraction and from the CPU builder), shadow maps (PCF and VSM) must agree with it on
// ≥ 99% of the pixels in cast shadow and, separately, ≥ 99% of the lit pixels, away from
// geometry and shadow edges; a control rendered without shadows must fail the first. The
// GPU and CPU silhouettes must also give the same stencil mask as each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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
// pixel for the edge band. `cast` (optional) marks the pixels lit but for an occluder: the
// shadows proper, which only a working shadow technique gets right.
test::Reference ray_traced_mask(const Scene& scene, std::vector<uint8_t>* cast = nullptr) {
  const RayTracer tracer(scene);
  test::Reference ref;
  ref.surface.assign(kSize * kSize, -1);
  ref.shadowed.assign(kSize * kSize, 0);
  if (cast) cast->assign(kSize * kSize, 0);
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
      if (cast) (*cast)[i] = ref.shadowed[i];
    }
  return ref;
}

struct Case {
  const char* name;
  std::string mode;   // shadow method
  bool back = false;  // volumes from back-facing casters
  std::string technique = "forward";
  std::string silhouettes = "gpu";
  std::string cascade_depth = "d16";  // map's cascades: d16 (the default) or d32
  float bias = 0.002f;                // map.bias (the default)
};

Image render_hdr(const Scene& scene, const Case& c) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.shadows = c.mode;
  o.set("map.pcf_taps", 1);
  o.set("map.resolution", 512);
  o.set("vsm.resolution", 512);
  o.set("map.cascade_depth", c.cascade_depth);
  o.set("map.bias", c.bias);
  o.set("volume.back_faces", c.back);
  o.pipeline = c.technique;
  o.set("volume.silhouettes", c.silhouettes);
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

// Agreement with the ray-traced mask away from edges, reported separately over the pixels
// in cast shadow in the reference (lit but for an occluder) and over the lit ones: one
// combined figure would let a technique that never shadows pass wherever shadows are a
// small part of the image. (Pixels facing away from the light are dark in every render,
// so they test nothing and are left out of both.)
struct Agreement {
  size_t cast = 0, cast_agree = 0, lit = 0, lit_agree = 0;
  double in_shadow() const { return static_cast<double>(cast_agree) / std::max<size_t>(cast, 1); }
  double in_light() const { return static_cast<double>(lit_agree) / std::max<size_t>(lit, 1); }
};

Agreement agreement(const std::vector<uint8_t>& mask, const test::Reference& ref,
                    const std::vector<uint8_t>& cast, const std::vector<uint8_t>& edge) {
  Agreement a;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (edge[i] || ref.surface[i] < 0) continue;
    if (cast[i]) {
      ++a.cast;
      a.cast_agree += mask[i];
    } else if (!ref.shadowed[i]) {
      ++a.lit;
      a.lit_agree += 1 - mask[i];
    }
  }
  return a;
}

// Each technique must agree with the reference on ≥ 99% of the cast-shadow pixels and on
// ≥ 99% of the lit ones. The control renders without shadows and must fail the first.
void check_agreement(const Scene& scene) {
  const size_t before = context().validation_message_count();
  std::vector<uint8_t> cast;
  const test::Reference ref = ray_traced_mask(scene, &cast);
  const std::vector<uint8_t> edge = test::edge_mask(ref, kSize, kSize, 1);

  const Image unshadowed = render_hdr(scene, {"none", "none"});
  const Agreement control = agreement(gpu_mask(unshadowed, unshadowed), ref, cast, edge);
  std::printf("%-24s in shadow %.4f of %zu pixels, lit %.4f of %zu\n", "no shadows (control)",
              control.in_shadow(), control.cast, control.in_light(), control.lit);
  ASSERT_GT(control.cast, static_cast<size_t>(kSize * kSize / 50))
      << "the test needs cast shadows away from edges";
  ASSERT_GT(control.lit, static_cast<size_t>(kSize * kSize / 10)) << "and lit pixels";
  EXPECT_LT(control.in_shadow(), 0.99) << "the control without shadows must fail";
  // And a mask that shadows everything fails the lit criterion.
  EXPECT_LT(agreement(std::vector<uint8_t>(kSize * kSize, 1), ref, cast, edge).in_light(), 0.99);

  const std::string fwd = "forward", deferred = "deferred";
  const std::string gpu = "gpu", cpu = "cpu";
  const std::string volume = "volume";
  Case d32{"shadow map, d32 cascades", "map"};
  d32.cascade_depth = "d32";
  // Without a depth bias, the normal offset alone must cover d16's rounding.
  Case unbiased{"shadow map, no bias", "map"};
  unbiased.bias = 0.0f;
  for (const Case& c : {Case{"shadow map", "map"}, d32, unbiased, Case{"VSM", "vsm"},
                        Case{"volumes, front, CPU", volume, false, fwd, cpu},
                        Case{"volumes, back, CPU", volume, true, fwd, cpu},
                        Case{"volumes, front, GPU", volume, false, fwd, gpu},
                        Case{"volumes, back, GPU", volume, true, fwd, gpu},
                        Case{"deferred volumes, front", volume, false, deferred, gpu},
                        Case{"deferred volumes, back", volume, true, deferred, gpu},
                        Case{"deferred volumes, CPU", volume, false, deferred, cpu}}) {
    const Agreement a = agreement(gpu_mask(render_hdr(scene, c), unshadowed), ref, cast, edge);
    std::printf("%-24s in shadow %.4f of %zu pixels, lit %.4f of %zu\n", c.name, a.in_shadow(),
                a.cast, a.in_light(), a.lit);
    EXPECT_GE(a.in_shadow(), 0.99) << c.name;
    EXPECT_GE(a.in_light(), 0.99) << c.name;
  }
  EXPECT_EQ(context().validation_message_count(), before) << "validation messages were emitted";
}

// GPU and CPU silhouettes build the same volumes, so their stencil masks must agree. They
// may differ only where float rounding moves a volume face across a pixel centre (the GPU
// normalises and offsets the same vertices in its own arithmetic), i.e. on a shadow
// boundary: every differing pixel must lie in the reference's edge band, and there may be
// at most 0.1% of the image (16 pixels) of them. (The GPU's spot-cone test keeps 1e-3 rad
// more casters; those shadow only points outside the cone, unlit either way.)
void check_gpu_silhouettes_match_cpu(const Scene& scene) {
  const size_t before = context().validation_message_count();
  const test::Reference ref = ray_traced_mask(scene);
  const std::vector<uint8_t> edge = test::edge_mask(ref, kSize, kSize, 1);
  const Image unshadowed = render_hdr(scene, {"none", "none"});
  for (const bool back : {false, true}) {
    const Case cpu{"CPU", "volume", back, "forward", "cpu"};
    Case gpu = cpu;
    gpu.silhouettes = "gpu";
    const std::vector<uint8_t> a = gpu_mask(render_hdr(scene, cpu), unshadowed);
    const std::vector<uint8_t> b = gpu_mask(render_hdr(scene, gpu), unshadowed);
    size_t differ = 0, differ_off_edge = 0, cast = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      differ += a[i] != b[i];
      differ_off_edge += a[i] != b[i] && !edge[i];
      const int x = static_cast<int>(i % kSize), y = static_cast<int>(i / kSize);
      cast += a[i] && luminance(unshadowed.rgb(x, y)) > 0.0f;  // lit but for an occluder
    }
    std::printf(
        "GPU vs CPU silhouettes (%s casters): %zu of %zu pixels differ (%zu off edges), "
        "%zu in cast shadow\n",
        back ? "back" : "front", differ, a.size(), differ_off_edge, cast);
    EXPECT_GT(cast, a.size() / 50) << "the comparison needs cast shadows";
    EXPECT_EQ(differ_off_edge, 0u) << (back ? "back" : "front");
    EXPECT_LE(differ, a.size() / 1000) << (back ? "back" : "front");
  }
  EXPECT_EQ(context().validation_message_count(), before) << "validation messages were emitted";
}

// One mesh of quads with their own vertices and flat normals (the volume builders weld
// them by position).
void add_faces(Scene& s, const std::vector<std::array<vec3, 4>>& quads, int material) {
  Mesh m;
  for (const auto& q : quads) {
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    const vec3 n = glm::normalize(glm::cross(q[1] - q[0], q[2] - q[0]));
    for (const vec3& p : q) {
      m.positions.push_back(p);
      m.normals.push_back(n);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  m.material = material;
  s.meshes.push_back(m);
  s.instances.push_back({"", static_cast<int>(s.meshes.size() - 1), mat4(1.0f)});
}

// A floor, a folded sheet (one open mesh of three panels, consistently wound; the steep
// middle one faces away from the light, so open casters of both orientations meet at its
// folds) and a closed box (one mesh with a bottom) under a point light.
Scene open_mesh_scene() {
  Scene s;
  s.name = "test-open-mesh";
  Material white;
  white.albedo = Color(0.7f);
  s.materials = {white};
  add_faces(s, {{vec3(-0.5f, 0, -0.5f), {-0.5f, 0, 1.5f}, {1.5f, 0, 1.5f}, {1.5f, 0, -0.5f}}}, 0);
  const float xs[4] = {0.15f, 0.4f, 0.55f, 0.8f}, ys[4] = {0.45f, 0.55f, 0.3f, 0.4f};
  std::vector<std::array<vec3, 4>> sheet;
  for (int k = 0; k < 3; ++k)
    sheet.push_back({vec3(xs[k], ys[k], 0.25f), vec3(xs[k], ys[k], 0.75f),
                     vec3(xs[k + 1], ys[k + 1], 0.75f), vec3(xs[k + 1], ys[k + 1], 0.25f)});
  add_faces(s, sheet, 0);
  const vec3 c(0.3f, 0.1f, 1.05f), h(0.1f);
  auto p = [&](int x, int y, int z) { return c + h * vec3(x, y, z); };
  add_faces(s,
            {{p(-1, -1, -1), p(-1, -1, 1), p(-1, 1, 1), p(-1, 1, -1)},
             {p(1, -1, -1), p(1, 1, -1), p(1, 1, 1), p(1, -1, 1)},
             {p(-1, -1, -1), p(1, -1, -1), p(1, -1, 1), p(-1, -1, 1)},
             {p(-1, 1, -1), p(-1, 1, 1), p(1, 1, 1), p(1, 1, -1)},
             {p(-1, -1, -1), p(-1, 1, -1), p(1, 1, -1), p(1, -1, -1)},
             {p(-1, -1, 1), p(1, -1, 1), p(1, 1, 1), p(-1, 1, 1)}},
            0);
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(0.0f, 0.9f, 0.5f);
  light.intensity = Color(1.0f);
  s.lights.push_back(light);
  Camera cam;
  cam.position = vec3(0.5f, 1.4f, 2.3f);
  cam.look_at = vec3(0.5f, 0.15f, 0.6f);
  cam.fov_y = radians(45.0f);
  s.camera = cam;
  return s;
}

TEST(ShadowAgreement, PointLightVolumesCubeMapsAndRayTracedMaskAgree) {
  check_agreement(test::cornell_point_light());
}

TEST(ShadowAgreement, GpuSilhouettesMatchCpuOnCornellBox) {
  check_gpu_silhouettes_match_cpu(test::cornell_point_light());
}

TEST(ShadowAgreement, OpenMeshVolumesMapsAndRayTracedMaskAgree) {
  check_agreement(open_mesh_scene());
}

TEST(ShadowAgreement, GpuSilhouettesMatchCpuOnOpenMesh) {
  check_gpu_silhouettes_match_cpu(open_mesh_scene());
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
  check_gpu_silhouettes_match_cpu(scene);  // exercises the GPU's cone test
}

// A roofless box under a directional light.
Scene roofless_box_in_the_sun() {
  Scene scene = test::cornell_point_light();
  scene.instances.erase(scene.instances.begin() + 1);  // the ceiling
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.35f, -1.0f, -0.25f));
  sun.irradiance = Color(2.0f);
  scene.lights = {sun};
  return scene;
}

// Cascaded shadow maps and volumes with caps at infinity along the light direction.
TEST(ShadowAgreement, DirectionalLightVolumesCascadesAndRayTracedMaskAgree) {
  const Scene scene = roofless_box_in_the_sun();
  check_agreement(scene);
  check_gpu_silhouettes_match_cpu(scene);
}

// The same world, each object's vertices in a frame of its own and placed by its instance's
// transform, a different one for every instance: every view must draw each object with its
// own model matrix, though the depth-only views push constants only when they change
// (SceneDrawer::draw_clusters).
TEST(ShadowAgreement, CascadesAndVolumesFollowEachInstanceTransform) {
  Scene scene = roofless_box_in_the_sun();
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    Instance& instance = scene.instances[i];
    const float k = static_cast<float>(i + 1);
    const mat4 place = glm::translate(mat4(1.0f), vec3(0.05f * k, -0.03f * k, 0.02f * k)) *
                       glm::rotate(mat4(1.0f), radians(7.0f * k), glm::normalize(vec3(1, 2, 3)));
    Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
    ASSERT_EQ(std::count_if(scene.instances.begin(), scene.instances.end(),
                            [&](const Instance& o) { return o.mesh == instance.mesh; }),
              1)
        << "each mesh must be placed once";
    const mat4 into = glm::inverse(place) * instance.transform;
    for (vec3& p : mesh.positions) p = vec3(into * vec4(p, 1.0f));
    const glm::mat3 normals = glm::transpose(glm::inverse(glm::mat3(into)));
    for (vec3& n : mesh.normals) n = glm::normalize(normals * n);
    instance.transform = place;
  }
  check_agreement(scene);
}

}  // namespace
}  // namespace illum::realtime
