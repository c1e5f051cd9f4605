// The probe volume on dynamic objects (shaders/probe_volume.glsl,
// realtime/probe_volume.h): the renderer's per-pixel lookup against its CPU mirror pixel by
// pixel in every frame pipeline, on probes baked for the test Cornell box (with invalid
// probes inside its blocks); the lookup varying across one flat face where the volume
// varies (one value per face with the per-instance fallback); an invalid probe's content
// never reaching a pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "illum/bake/probe_baker.h"
#include "illum/bake/probe_lookup.h"
#include "illum/core/sh.h"
#include "illum/realtime/renderer.h"
#include "illum/trace/ray_tracer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 96;
// fp16 HDR target: round to nearest with a 10-bit mantissa, relative error ≤ 2⁻¹¹.
constexpr float kHalfRounding = 1.0f / 2048.0f;

class ProbeVolumeTest : public test::ValidatedVulkanTest {};

// A UV sphere, normals along the radius (the rasterizer interpolates them across each triangle).
int add_sphere(Scene& s, vec3 centre, float radius, int material) {
  constexpr int kSlices = 32, kStacks = 16;
  Mesh m;
  for (int j = 0; j <= kStacks; ++j)
    for (int i = 0; i <= kSlices; ++i) {
      const float theta = kPi * float(j) / kStacks, phi = 2.0f * kPi * float(i) / kSlices;
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      m.positions.push_back(centre + radius * n);
      m.normals.push_back(n);
    }
  for (int j = 0; j < kStacks; ++j)
    for (int i = 0; i < kSlices; ++i) {
      const uint32_t a = uint32_t(j * (kSlices + 1) + i), b = a + 1, c = a + kSlices + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  m.material = material;
  s.meshes.push_back(m);
  s.instances.push_back({"sphere", int(s.meshes.size()) - 1, mat4(1.0f)});
  s.instances.back().dynamic = true;
  return int(s.instances.size()) - 1;
}

// What the rasterizer interpolates at a pixel centre, found by a ray from the camera: the
// instance hit (−1: none), world position, unit interpolated normal facing the viewer.
struct PixelSurface {
  int instance = -1;
  vec3 p{0.0f}, n{0.0f};
  float distance = 0.0f;
};
std::vector<PixelSurface> cast_pixels(const Scene& s, int width, int height) {
  struct Tri {
    vec3 p[3], n[3];
    int instance;
  };
  std::vector<Tri> tris;
  for (size_t i = 0; i < s.instances.size(); ++i) {
    const Instance& inst = s.instances[i];
    const Mesh& m = s.meshes[size_t(inst.mesh)];
    const mat3 normal_matrix = glm::transpose(glm::inverse(mat3(inst.transform)));
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      Tri tri;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = m.indices[t + size_t(k)];
        tri.p[k] = vec3(inst.transform * vec4(m.positions[v], 1.0f));
        tri.n[k] = normal_matrix * m.normals[v];
      }
      tri.instance = int(i);
      tris.push_back(tri);
    }
  }
  std::vector<PixelSurface> out(size_t(width) * size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Ray ray = s.camera->generate_ray(x + 0.5f, y + 0.5f, width, height);
      PixelSurface& px = out[size_t(y) * size_t(width) + size_t(x)];
      float best = kInf;
      for (const Tri& tri : tris) {  // Möller–Trumbore with barycentrics
        const vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
        const vec3 pv = glm::cross(ray.direction, e2);
        const float det = glm::dot(e1, pv);
        if (std::abs(det) < 1e-12f) continue;
        const vec3 tv = ray.origin - tri.p[0];
        const float u = glm::dot(tv, pv) / det;
        if (u < 0.0f || u > 1.0f) continue;
        const vec3 qv = glm::cross(tv, e1);
        const float v = glm::dot(ray.direction, qv) / det;
        if (v < 0.0f || u + v > 1.0f) continue;
        const float t = glm::dot(e2, qv) / det;
        if (t <= 1e-5f || t >= best) continue;
        best = t;
        px.instance = tri.instance;
        px.p = ray.origin + t * ray.direction;
        px.n = glm::normalize((1.0f - u - v) * tri.n[0] + u * tri.n[1] + v * tri.n[2]);
        px.distance = t;
      }
      if (px.instance >= 0 && glm::dot(px.n, ray.direction) > 0.0f) px.n = -px.n;  // two-sided
    }
  return out;
}

// Whether a pixel and its 8 neighbours show the same instance (silhouettes excluded: there
// the rasterizer's coverage of a pixel centre and the ray's may differ).
bool interior(const std::vector<PixelSurface>& px, int x, int y, int width, int height) {
  const int inst = px[size_t(y) * size_t(width) + size_t(x)].instance;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= width || yy >= height) return false;
      if (px[size_t(yy) * size_t(width) + size_t(xx)].instance != inst) return false;
    }
  return true;
}

ProbeVolume volume_of(const bake::ProbeBake& baked, int instance) {
  ProbeVolume v;
  v.size = baked.grid.size;
  v.origin = baked.grid.origin;
  v.spacing = vec3(baked.grid.spacing);
  v.probes = bake::probe_volume_data(baked.probes);
  v.instances = {instance};
  return v;
}

// The trilinear weight of the invalid probes of the cell around p.
float invalid_share(const ProbeVolume& v, const vec3& p) {
  const vec3 g = glm::clamp((p - v.origin) / v.spacing, vec3(0.0f), vec3(v.size - 1));
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(g)), v.size - 1);
  const vec3 t = g - vec3(i0);
  float share = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 c = glm::min(i0 + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2), v.size - 1);
    const size_t record = size_t((c.z * v.size.y + c.y) * v.size.x + c.x);
    if (v.probes[record * kProbeFloats + kProbeFloats - 1] == 0.0f)
      share += (k & 1 ? t.x : 1.0f - t.x) * (k & 2 ? t.y : 1.0f - t.y) * (k & 4 ? t.z : 1.0f - t.z);
  }
  return share;
}

Image render_hdr(const Scene& scene, const ProbeVolume& volume, const std::string& pipeline,
                 const std::string& lookup = "pixel") {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = pipeline;
  o.shadows = "none";
  o.set("baked.probe_lookup", lookup);
  Renderer r(context(), scene, o);
  r.set_probe_volume(volume);
  r.render(*scene.camera);
  return r.hdr();
}

// Probes baked for the test Cornell box (point light; its blocks, open at the bottom, hold
// invalid probes) light a dynamic sphere resting on the short block. The frame is drawn without
// the light, so the sphere shows only albedo·max(E, 0)/π of the lookup, and each of its
// pixels is compared with the CPU mirror at the surface a camera ray finds there.
//
// Tolerance per channel: fp16 rounding of the HDR target, 2⁻¹¹·|value|; plus the change of
// the mirror when the surface point moves by δ = 1/256 of the pixel's footprint along any
// axis (the rasterizer snaps vertices to 1/256 pixel, so its interpolated position may
// differ from the ray's by that much); plus 1e-5 of the largest Σ|E_i| in the volume times
// albedo/π for float arithmetic (≈ 100 operations of relative error 2⁻²⁴ on terms of that
// size, order and fused multiply-adds free).
TEST_F(ProbeVolumeTest, PerPixelLookupMatchesCpuMirrorInEveryPipeline) {
  Scene scene = test::cornell_point_light();
  scene.name = "probe-volume-cornell";
  const Scene statics = scene;
  const int sphere = add_sphere(scene, vec3(0.62f, 0.42f, 0.6f), 0.12f, 0);
  const RayTracer tracer(statics);
  bake::ProbeBakeOptions options;
  options.spacing = 0.1f;  // 10³ over the unit box; the layer y = 0.25 inside the short block
  options.spp = 32;
  options.seed = 3;
  options.threads = 2;
  options.progress = false;
  const bake::ProbeBake baked = bake::bake_probes(statics, tracer, options);
  ASSERT_GT(baked.stats.invalid, 0) << "the blocks should hold invalid probes";
  const ProbeVolume volume = volume_of(baked, sphere);
  float largest = 0.0f;
  for (size_t i = 0; i < volume.count(); ++i) {
    float sum = 0.0f;
    for (int k = 0; k < 27; ++k) sum += std::abs(volume.probes[i * kProbeFloats + size_t(k)]);
    largest = std::max(largest, sum);
  }
  scene.lights.clear();
  // Close up and low, so the sphere fills 2/3 of the frame and its lower band, whose cells
  // reach down to the invalid probes inside the block, is in view.
  scene.camera->position = vec3(0.62f, 0.36f, 1.6f);
  scene.camera->look_at = vec3(0.62f, 0.40f, 0.6f);
  scene.camera->fov_y = radians(20.0f);
  const Color albedo = scene.materials[0].albedo;
  const std::vector<PixelSurface> px = cast_pixels(scene, kSize, kSize);
  const float footprint_per_metre = 2.0f * std::tan(0.5f * scene.camera->fov_y) / kSize;
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    const Image hdr = render_hdr(scene, volume, pipeline);
    int compared = 0, failed = 0, near_invalid = 0;
    float worst = 0.0f;  // |gpu − mirror| / tolerance
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const PixelSurface& s = px[size_t(y) * kSize + size_t(x)];
        if (s.instance != sphere || !interior(px, x, y, kSize, kSize)) continue;
        auto shade = [&](const vec3& p) {
          return albedo * kInvPi *
                 glm::max(probe_volume_irradiance(volume, p, s.n, s.n).irradiance, Color(0.0f));
        };
        const Color expected = shade(s.p);
        const float delta = s.distance * footprint_per_metre / 256.0f;
        Color moved(0.0f);
        for (int axis = 0; axis < 3; ++axis)
          for (float sign : {-1.0f, 1.0f}) {
            vec3 q = s.p;
            q[axis] += sign * delta;
            moved = glm::max(moved, glm::abs(shade(q) - expected));
          }
        const Color got = hdr.rgb(x, y);
        ++compared;
        near_invalid += invalid_share(volume, s.p) > 0.05f;
        bool bad = false;
        for (int c = 0; c < 3; ++c) {
          const float tol = kHalfRounding * std::abs(expected[c]) + moved[c] +
                            1e-5f * largest * albedo[c] * kInvPi;
          const float err = std::abs(got[c] - expected[c]);
          worst = std::max(worst, err / tol);
          bad |= !(err <= tol);
        }
        if (bad && failed++ < 3)
          ADD_FAILURE() << pipeline << " pixel " << x << "," << y << ": gpu " << got.r << " "
                        << got.g << " " << got.b << ", mirror " << expected.r << " " << expected.g
                        << " " << expected.b;
      }
    EXPECT_GT(compared, 1000) << pipeline;
    EXPECT_GT(near_invalid, 50) << pipeline << ": too few pixels where validity matters";
    EXPECT_EQ(failed, 0) << pipeline << ": " << failed << " of " << compared
                         << " sphere pixels off the mirror";
    std::printf(
        "%s: %d sphere pixels (%d with invalid probes > 5%% of the trilinear weight), "
        "worst |gpu − mirror| / tolerance %.3f\n",
        pipeline.c_str(), compared, near_invalid, worst);
  }
}

// A synthetic volume: 3×3×3 probes 0.5 m apart around the origin, isotropic irradiance
// E(n) = e(probe) (only E_0 = e/Y00 set), all valid.
ProbeVolume isotropic_volume(const std::function<float(vec3)>& e) {
  ProbeVolume v;
  v.size = glm::ivec3(3);
  v.origin = vec3(-0.5f);
  v.spacing = vec3(0.5f);
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        const float e0 = e(v.origin + v.spacing * vec3(x, y, z)) / float(sh::kY00);
        for (int c = 0; c < 3; ++c) v.probes.push_back(e0 * (c == 0 ? 1.0f : c == 1 ? 0.8f : 0.6f));
        v.probes.insert(v.probes.end(), 24, 0.0f);
        v.probes.push_back(1.0f);
      }
  v.instances = {0};
  return v;
}

// One dynamic quad facing the camera (+z), 0.8 m wide across the grid's middle; no lights.
Scene facing_quad() {
  Scene s;
  s.name = "probe-volume-quad";
  Material m;
  m.albedo = Color(0.5f, 0.6f, 0.7f);
  s.materials = {m};
  test::add_quad(s, {-0.4f, -0.4f, 0.1f}, {0.4f, -0.4f, 0.1f}, {0.4f, 0.4f, 0.1f},
                 {-0.4f, 0.4f, 0.1f}, 0);
  s.instances[0].dynamic = true;
  Camera cam;
  cam.position = vec3(0.0f, 0.0f, 2.0f);
  cam.look_at = vec3(0.0f, 0.0f, 0.1f);
  cam.fov_y = radians(30.0f);
  s.camera = cam;
  return s;
}

// Where the volume varies (e rising along x from 1 to 3 W/m² across the quad's cells), the
// per-pixel lookup varies across the flat quad — one normal everywhere — from its left edge
// to its right edge as the mirror does; the per-instance fallback gives the whole quad one
// value (its ambient cube's +z face, the mirror at the quad's centre).
TEST_F(ProbeVolumeTest, PerPixelLookupVariesAcrossTheObjectWhereTheVolumeVaries) {
  const Scene scene = facing_quad();
  const ProbeVolume volume = isotropic_volume([](vec3 p) { return 2.0f + 2.0f * p.x; });
  const Color albedo = scene.materials[0].albedo;
  const std::vector<PixelSurface> px = cast_pixels(scene, kSize, kSize);
  const Image pixel = render_hdr(scene, volume, "forward", "pixel");
  const Image instance = render_hdr(scene, volume, "forward", "instance");
  float lo = kInf, hi = 0.0f, inst_lo = kInf, inst_hi = 0.0f, mirror_lo = kInf, mirror_hi = 0.0f;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const PixelSurface& s = px[size_t(y) * kSize + size_t(x)];
      if (s.instance != 0 || !interior(px, x, y, kSize, kSize)) continue;
      const float g = pixel.rgb(x, y).g, gi = instance.rgb(x, y).g;
      lo = std::min(lo, g), hi = std::max(hi, g);
      inst_lo = std::min(inst_lo, gi), inst_hi = std::max(inst_hi, gi);
      const float m =
          albedo.g * kInvPi * probe_volume_irradiance(volume, s.p, s.n, s.n).irradiance.g;
      mirror_lo = std::min(mirror_lo, m), mirror_hi = std::max(mirror_hi, m);
    }
  std::printf("per pixel %.4f .. %.4f (mirror %.4f .. %.4f); per instance %.4f .. %.4f\n", lo, hi,
              mirror_lo, mirror_hi, inst_lo, inst_hi);
  EXPECT_GT(hi / lo, 1.5f) << "the per-pixel lookup should follow the volume across the quad";
  EXPECT_NEAR(lo, mirror_lo, 2.0f * kHalfRounding * mirror_lo);
  EXPECT_NEAR(hi, mirror_hi, 2.0f * kHalfRounding * mirror_hi);
  EXPECT_LE(inst_hi - inst_lo, kHalfRounding * inst_hi) << "one cube, one normal: one value";
  const Color centre =
      probe_volume_irradiance(volume, vec3(0.0f, 0.0f, 0.1f), vec3(0, 0, 1), vec3(0, 0, 1))
          .irradiance;
  EXPECT_NEAR(inst_hi, albedo.g * kInvPi * centre.g, 2.0f * kHalfRounding * inst_hi);
}

// An invalid probe holding a huge value beside the quad: with validity weight 0 the frame is
// the one of the volume without it (the constant the valid probes hold, renormalised, not
// darkened), in every pipeline; made valid, it shows.
TEST_F(ProbeVolumeTest, ValidityWeightsDropAnInvalidProbe) {
  const Scene scene = facing_quad();
  ProbeVolume volume = isotropic_volume([](vec3) { return 1.0f; });
  const size_t probe =
      size_t((1 * 3 + 1) * 3 + 2);  // (0.5, 0, 0): a corner of the quad's right cells
  volume.probes[probe * kProbeFloats + 1] *= 1000.0f;  // green only
  volume.probes[probe * kProbeFloats + 27] = 0.0f;
  const Color albedo = scene.materials[0].albedo;
  const float expected = albedo.g * kInvPi * 0.8f;  // E = 0.8 in green everywhere
  const std::vector<PixelSurface> px = cast_pixels(scene, kSize, kSize);
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    const Image hdr = render_hdr(scene, volume, pipeline);
    float worst = 0.0f;
    int compared = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        if (px[size_t(y) * kSize + size_t(x)].instance != 0 || !interior(px, x, y, kSize, kSize))
          continue;
        worst = std::max(worst, std::abs(hdr.rgb(x, y).g - expected));
        ++compared;
      }
    EXPECT_GT(compared, 1000);
    EXPECT_LE(worst, 2.0f * kHalfRounding * expected) << pipeline;
  }
  volume.probes[probe * kProbeFloats + 27] = 1.0f;
  const Image shown = render_hdr(scene, volume, "forward");
  EXPECT_GT(shown.rgb(kSize * 3 / 4, kSize / 2).g, 10.0f * expected) << "the probe is in reach";
}

// The leak guard on the CPU mirror (the GPU is held to the mirror above): the probe leak
// test's two rooms (docs/probes.md: a closed wall 5 cm thick at x = 0, a point light at
// x > 0, probes every 0.25 m so the cell x ∈ [−0.125, 0.125] straddles the wall). On the dark
// side (x = −0.03 … −0.1 m) the true irradiance is 0; for surfaces facing away from the wall
// (normal −x) the lit probes lie behind them. Validity weights alone give them a share
// a = (x + 0.125)/0.25 ∈ [0.1, 0.38] of the lit probes' light (all probes here are valid).
// The guard multiplies a lit probe's weight by g_b ∈ [0.2, 0.29] (from straight behind to
// 114° off the normal, for offsets up to 0.25 m along the wall) and a dark one's by
// g_f ∈ [0.48, 1.2]; the dark probes hold exactly 0, so the guarded leak is at most
// 0.29 / (0.2·a + 0.48·(1 − a)) ≤ 0.66 of the validity-only leak at the same point:
// asserted ≤ 0.7 of it over the points.
TEST(ProbeVolumeMirror, LeakGuardCutsTheLightLeakingThroughAThinWall) {
  Scene s;
  s.name = "two-rooms";
  Material m;
  m.albedo = Color(0.5f);
  s.materials = {m};
  const vec3 lo(-1.0f, 0.0f, -1.0f), hi(1.0f, 2.0f, 1.0f);
  auto at = [&](float x, float y, float z) { return lo + (hi - lo) * vec3(x, y, z); };
  test::add_quad(s, at(0, 0, 0), at(0, 0, 1), at(1, 0, 1), at(1, 0, 0), 0);  // floor, inward
  test::add_quad(s, at(0, 1, 0), at(1, 1, 0), at(1, 1, 1), at(0, 1, 1), 0);  // ceiling
  test::add_quad(s, at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0), 0);  // z = −1
  test::add_quad(s, at(0, 0, 1), at(0, 1, 1), at(1, 1, 1), at(1, 0, 1), 0);  // z = +1
  test::add_quad(s, at(0, 0, 0), at(0, 1, 0), at(0, 1, 1), at(0, 0, 1), 0);  // x = −1
  test::add_quad(s, at(1, 0, 0), at(1, 0, 1), at(1, 1, 1), at(1, 1, 0), 0);  // x = +1
  // The wall: a closed block through the whole room (its open bottom below the floor).
  test::add_block(s, vec3(0.0f, 1.0f, 0.0f), vec3(0.025f, 1.05f, 1.05f), 0.0f, 0);
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(0.6f, 1.2f, 0.1f);
  light.intensity = Color(5.0f);
  s.lights.push_back(light);
  const RayTracer tracer(s);
  bake::ProbeBakeOptions options;
  options.spacing = 0.25f;
  options.spp = 64;
  options.threads = 2;
  options.progress = false;
  bake::ProbeBake baked = bake::bake_probes(s, tracer, options);
  ProbeVolume volume;
  volume.size = baked.grid.size;
  volume.origin = baked.grid.origin;
  volume.spacing = vec3(baked.grid.spacing);
  volume.probes = bake::probe_volume_data(baked.probes);
  baked::ProbeSet set;
  set.grid = baked.grid;
  set.probes = std::move(baked.probes);
  ASSERT_NEAR(set.grid.origin.x + 3.0f * set.grid.spacing, -0.125f, 1e-5f);  // the straddling cell
  const vec3 away(-1.0f, 0.0f, 0.0f);
  float validity_only = 0.0f, guarded = 0.0f, lit = 0.0f;
  for (float x : {-0.03f, -0.06f, -0.1f})
    for (float y : {0.3f, 0.9f, 1.3f, 1.7f})
      for (float z : {-0.6f, -0.1f, 0.2f, 0.7f}) {
        const vec3 p(x, y, z);
        validity_only = std::max(validity_only, bake::lookup_irradiance(set, p, away).g);
        guarded = std::max(guarded, probe_volume_irradiance(volume, p, away, away).irradiance.g);
        lit = std::max(lit, bake::lookup_irradiance(set, vec3(-x, y, z), -away).g);
      }
  std::printf(
      "dark side, facing away from the wall: E ≤ %.4f validity only, ≤ %.4f with the "
      "leak guard (lit side, facing away: %.4f)\n",
      validity_only, guarded, lit);
  EXPECT_GT(validity_only, 0.1f * lit) << "the scene should leak without the guard";
  EXPECT_LE(guarded, 0.7f * validity_only);
}

// Bad volumes are refused at the renderer's entry.
TEST_F(ProbeVolumeTest, RefusesMalformedVolumes) {
  const Scene scene = facing_quad();
  RenderSettings o;
  o.width = o.height = 8;
  o.shadows = "none";
  Renderer r(context(), scene, o);
  const ProbeVolume good = isotropic_volume([](vec3) { return 1.0f; });
  ProbeVolume v = good;
  v.probes.pop_back();
  EXPECT_THROW(r.set_probe_volume(v), Error);
  v = good;
  v.probes[27] = 2.0f;  // validity outside [0, 1]
  EXPECT_THROW(r.set_probe_volume(v), Error);
  v = good;
  v.instances = {5};
  EXPECT_THROW(r.set_probe_volume(v), Error);
  v = good;
  v.spacing.y = 0.0f;
  EXPECT_THROW(r.set_probe_volume(v), Error);
  EXPECT_NO_THROW(r.set_probe_volume(good));
}

}  // namespace
}  // namespace illum::realtime
