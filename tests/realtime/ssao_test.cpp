// The SSAO add-on (docs/realtime.md "SSAO") on lavapipe under the validation layer:
// * against the offline `ao` integrator with the same estimand (radius, bias, falloff) on the
//   Cornell box, per 8×8 tile of visible pixels where screen space can know the answer, at
//   half and full estimator resolution;
// * never darkens direct light, and scales exactly the indirect term;
// * switched off, the frame is the frame without it (byte for byte, also after a toggle);
// * the combine rule with a baked AO layer (minimum) in the shader's own function.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/core/params.h"
#include "illum/core/sampling.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/baked_data.h"
#include "illum/realtime/renderer.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class SsaoTest : public test::ValidatedVulkanTest {};

// The estimand of the comparison (metres: the built-in Cornell box is 0.556 m wide).
// A falloff of R/2 (g = 0.2 at R) and a bias of 0.2 so that each part of the term moves the
// tile means well beyond their tolerance when it is wrong.
constexpr float kRadius = 0.1f, kBias = 0.2f, kFalloff = 0.05f;
constexpr int kDirections = 64;   // SSAO directions per pixel
constexpr int kOfflineRays = 16;  // offline rays per camera sample (16 samples a pixel)
constexpr int kSize = 128;
constexpr int kTile = 8;

// Φ⁻¹(1 − p) for small p, by bisection on erfc.
double normal_quantile_upper(double p) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

Image ssao_buffer(const Scene& scene, const std::string& pipeline, const std::string& resolution) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = pipeline;
  o.shadows = "none";
  o.enable("ssao");
  o.set("ssao.output", std::string("ao"));
  o.set("ssao.radius", kRadius);
  o.set("ssao.bias", kBias);
  o.set("ssao.falloff", kFalloff);
  o.set("ssao.samples", kDirections);
  o.set("ssao.blur", 0);  // independent estimates: the tile statistics below assume them
  o.set("ssao.resolution", resolution);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  return r.hdr();
}

Image offline_ao(const Scene& scene) {
  const RayTracer tracer(scene);
  RenderOptions o;
  o.width = o.height = kSize;
  o.spp = 16;
  o.seed = 3;
  o.progress = false;
  const nlohmann::json p = {
      {"samples", kOfflineRays}, {"distance", kRadius}, {"bias", kBias}, {"falloff", kFalloff}};
  return Integrator::create("ao", Params(p, "--param"))->render(tracer, *scene.camera, o);
}

// The pixels where the depth buffer holds everything the estimand needs (ray traced from
// the pixel centre's surface point p along 64 directions of the hemisphere, 16 steps to R):
// every occluder hit within R is visible from the camera, and no free point of an AO ray
// lies behind a visible surface within the thickness R (screen space would count it as
// occluded); the pixel is no geometric edge (its 3×3 neighbours see the same plane) and its
// R-ball projects inside the image (off-screen occluders are unknown to screen space).
std::vector<uint8_t> screen_space_complete(const Scene& scene) {
  const RayTracer tracer(scene);
  const Camera& cam = *scene.camera;
  const vec3 o = cam.position;
  const vec3 forward = glm::normalize(cam.look_at - cam.position);
  const float tan_half = std::tan(0.5f * cam.fov_y);
  struct Surface {
    bool hit = false;
    vec3 p, n;
  };
  std::vector<Surface> surf(kSize * kSize);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Ray r = cam.generate_ray(x + 0.5f, y + 0.5f, kSize, kSize);
      Hit h;
      if (!tracer.intersect(r, &h)) continue;
      const SurfaceInteraction si = tracer.interaction(r, h);
      Surface& s = surf[y * kSize + x];
      s.hit = true;
      s.p = si.p;
      s.n = glm::dot(si.ng, si.wo) >= 0.0f ? si.ng : -si.ng;
    }
  // Distance along the camera ray through q to the first visible surface.
  auto visible_distance = [&](vec3 q) {
    Ray r{o, glm::normalize(q - o), 0.0f, kInf};
    Hit h;
    return tracer.intersect(r, &h) ? h.t : kInf;
  };
  std::vector<vec3> dirs;  // Fibonacci points on the hemisphere around +z
  const int kDirs = 64;
  for (int i = 0; i < kDirs; ++i) {
    const float z = (i + 0.5f) / kDirs;
    const float phi = 2.39996323f * i;
    const float s = std::sqrt(1.0f - z * z);
    dirs.emplace_back(s * std::cos(phi), s * std::sin(phi), z);
  }
  std::vector<uint8_t> ok(kSize * kSize, 0);
  parallel_for(kSize * kSize, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const int x = static_cast<int>(i % kSize), y = static_cast<int>(i / kSize);
      const Surface& s = surf[i];
      if (!s.hit) continue;
      bool good = true;
      for (int dy = -1; dy <= 1 && good; ++dy)
        for (int dx = -1; dx <= 1 && good; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= kSize || yy >= kSize) continue;
          const Surface& t = surf[yy * kSize + xx];
          good = t.hit && glm::dot(t.n, s.n) > 0.999f && std::abs(glm::dot(t.p - s.p, s.n)) < 1e-4f;
        }
      const float z_view = glm::dot(s.p - o, forward);
      const float r_px = kRadius * 0.5f * kSize / (tan_half * z_view);
      const float edge = std::min({x + 0.5f, y + 0.5f, kSize - x - 0.5f, kSize - y - 0.5f});
      if (edge < r_px) good = false;
      const Frame frame = Frame::from_normal(s.n);
      for (size_t d = 0; d < dirs.size() && good; ++d) {
        const vec3 w = frame.to_world(dirs[d]);
        Ray ray{offset_ray_origin(s.p, s.n, w), w, 0.0f, kRadius};
        Hit h;
        const float t_hit = tracer.intersect(ray, &h) ? h.t : kRadius;
        if (t_hit < kRadius) {
          const vec3 q = s.p + w * t_hit;
          if (visible_distance(q) < glm::length(q - o) * (1.0f - 1e-3f)) good = false;
        }
        for (int k = 1; k <= 16 && good; ++k) {
          const float t = kRadius * k / 16.0f;
          if (t >= t_hit * (1.0f - 1e-3f)) break;
          const vec3 q = s.p + w * t;
          const float dq = glm::length(q - o), ds = visible_distance(q);
          if (ds < dq * (1.0f - 1e-4f) && dq - ds < kRadius) good = false;
        }
      }
      ok[i] = good ? 1 : 0;
    }
  });
  return ok;
}

TEST_F(SsaoTest, MatchesTheOfflineAoEstimandOnTheCornellBox) {
  const Scene scene = load_scene("cornell");
  ASSERT_TRUE(scene.camera.has_value());
  const Image offline = offline_ao(scene);
  const std::vector<uint8_t> complete = screen_space_complete(scene);
  // Deterministic allowances beside the noise: the hit distance is known to R/384 (6 steps,
  // 6 halvings; R/256 taken), g = 1/(1 + (t/s)²) moves by at most (3√3/8)/s per unit of t, and
  // O = (2/N) Σ (cos θ_i − b)·g ≤ (N + 1)/N with stratified cos θ_i ≤ (i + 1)/N; the fp16
  // octahedral normals tilt the hemisphere by ≤ 1e-3 rad (2^-11 per component), moving
  // each cos θ by as much; the AO goes through the fp16 HDR target (2^-11).
  const double lipschitz = 3.0 * std::sqrt(3.0) / 8.0 / kFalloff;
  const double o_max = (kDirections + 1.0) / kDirections;
  const double allowance =
      o_max * lipschitz * kRadius / 256.0 + o_max * 1e-3 + std::ldexp(1.0, -11);
  for (const auto& [pipeline, resolution] : {std::pair<std::string, std::string>{"forward", "half"},
                                             {"deferred", "half"},
                                             {"forward", "full"},
                                             {"deferred", "full"}}) {
    const std::string name = pipeline + "/" + resolution;
    const Image ao = ssao_buffer(scene, pipeline, resolution);
    // Paired per estimate: d = SSAO − offline, one unit per SSAO estimate — a pixel at full
    // resolution, a 2×2 block at half (without blur its pixels on the estimate's surface
    // take that one estimate), its offline value the mean over the unit's compared pixels.
    // Both are independent estimates of the unit's AO, so d's spread over a tile is their
    // noise (plus how their biases vary), not the AO's variation across the tile.
    const int unit = resolution == "half" ? 2 : 1;
    const int units = kSize / unit;
    struct Unit {
      double n = 0, a = 0, b = 0;
    };
    std::vector<Unit> per_unit(units * units);
    struct Tile {
      double pixels = 0, n = 0, s = 0, o = 0, d = 0, d2 = 0;
    };
    std::vector<Tile> tiles((kSize / kTile) * (kSize / kTile));
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        if (!complete[y * kSize + x]) continue;
        Unit& u = per_unit[(y / unit) * units + x / unit];
        u.n += 1;
        u.a += ao.pixel(x, y)[0];
        u.b += offline.pixel(x, y)[0];
        tiles[(y / kTile) * (kSize / kTile) + x / kTile].pixels += 1;
      }
    for (int uy = 0; uy < units; ++uy)
      for (int ux = 0; ux < units; ++ux) {
        const Unit& u = per_unit[uy * units + ux];
        if (u.n == 0) continue;
        Tile& t = tiles[(uy * unit / kTile) * (kSize / kTile) + ux * unit / kTile];
        const double a = u.a / u.n, b = u.b / u.n;
        t.n += 1;
        t.s += a;
        t.o += b;
        t.d += a - b;
        t.d2 += (a - b) * (a - b);
      }
    int compared = 0, occluded = 0;
    for (const Tile& t : tiles) compared += t.pixels >= 16 && t.n >= 4;
    // One family of checks at kFamilyFalseAlarm = 1e-4 (Bonferroni, two-sided).
    const double z = normal_quantile_upper(1e-4 / (2.0 * compared));
    double worst = 0.0;
    for (size_t i = 0; i < tiles.size(); ++i) {
      const Tile& t = tiles[i];
      if (t.pixels < 16 || t.n < 4) continue;
      const double ms = t.s / t.n, mo = t.o / t.n, md = t.d / t.n;
      const double vd = std::max(t.d2 / t.n - md * md, 0.0) * t.n / (t.n - 1);
      const double tol = z * std::sqrt(vd / t.n) + allowance;
      worst = std::max(worst, std::abs(ms - mo) / tol);
      if (mo < 0.95) ++occluded;
      EXPECT_NEAR(ms, mo, tol) << name << ": tile " << i % (kSize / kTile) << ", "
                               << i / (kSize / kTile) << " (" << t.n << " estimates)";
    }
    std::printf(
        "%s: %d tiles compared (%d with offline AO < 0.95), z = %.2f, allowance %.4f, "
        "worst |difference| / tolerance %.3f\n",
        name.c_str(), compared, occluded, z, allowance, worst);
    // The comparison must reach the occluded regions (corners, the blocks' feet), not only
    // the open walls.
    EXPECT_GE(compared, 60) << name;
    EXPECT_GE(occluded, 15) << name;
    if (const char* dir = std::getenv("ILLUM_SSAO_IMAGES"); dir && name == "deferred/half") {
      // docs/images: the AO buffer, the offline image and |difference| as a heat map (black
      // 0 → red 0.05 → yellow 0.1 → white ≥ 0.15; blue: pixels outside the comparison).
      Image heat(kSize, kSize, 3);
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const float d = std::abs(ao.pixel(x, y)[0] - offline.pixel(x, y)[0]) / 0.15f;
          Color c(std::clamp(3 * d, 0.0f, 1.0f), std::clamp(3 * d - 1, 0.0f, 1.0f),
                  std::clamp(3 * d - 2, 0.0f, 1.0f));
          if (!complete[y * kSize + x]) c = Color(0.1f, 0.15f, 0.35f) + 0.5f * c;
          heat.set_rgb(x, y, c);
        }
      write_image(std::string(dir) + "/ssao_cornell_error.png", heat);
      write_image(std::string(dir) + "/ssao_cornell_offline_ao.png", offline);
      write_image(std::string(dir) + "/ssao_cornell_ssao_ao.png", ao);
    }
  }
}

struct FrameSetup {
  std::string pipeline, shadows;
  bool lightmap = false;    // a constant plain light-map in place of the constant ambient
  bool duplicates = false;  // every surface drawn twice, coplanar (as in Sibenik)
  bool prt = false;         // PRT: per-vertex transfer (zero without ambient)
};

Image frame(const Scene& scene, const FrameSetup& setup, bool ssao, Color ambient,
            const std::string& output = "frame") {
  RenderSettings o;
  o.width = o.height = 64;
  o.pipeline = setup.pipeline;
  o.shadows = setup.shadows;
  o.set("lighting.ambient", ambient);
  o.set("map.resolution", 256);
  if (ssao) {
    o.enable("ssao");
    o.set("ssao.output", output);
    o.set("ssao.radius", kRadius);
  }
  Scene drawn = scene;
  if (setup.duplicates) {
    const size_t n = drawn.instances.size();
    for (size_t i = 0; i < n; ++i) drawn.instances.push_back(drawn.instances[i]);
  }
  Renderer r(context(), drawn, o);
  if (setup.lightmap && ambient.r > 0.0f)
    r.set_lightmap({LightmapKind::kPlain, {Image(4, 4, 3, ambient.r)}});
  if (setup.prt) {
    // PRT takes the ambient term's place (albedo · transfer · sun SH), an indirect term SSAO
    // leaves alone (the transfer holds the visibility); the lights still add the direct part. Zero
    // transfers without ambient: the frame holds only the direct part.
    size_t vertices = 0;
    for (const Mesh& m : drawn.meshes) vertices += m.positions.size();
    const float k = ambient.r > 0.0f ? 1.0f : 0.0f;
    PrtTransfer prt;
    prt.bands = 2;
    for (size_t i = 0; i < vertices; ++i)
      for (float t : {1.0f, 0.2f * std::sin(0.1f * float(i)), 0.3f, 0.1f})
        for (int c = 0; c < 3; ++c) prt.vertices.push_back(k * t * (1.0f - 0.2f * float(c)));
    r.set_prt(prt);
  }
  r.render(*scene.camera);
  return r.hdr();
}

TEST_F(SsaoTest, NeverDarkensDirectLightAndScalesExactlyTheIndirectTerm) {
  const Scene scene = load_scene("cornell");
  for (const FrameSetup& setup :
       {FrameSetup{"forward", "map"}, FrameSetup{"deferred", "map"},
        FrameSetup{"forward", "volume"}, FrameSetup{"deferred", "volume"},
        FrameSetup{"forward", "map", true}, FrameSetup{"deferred", "map", true},
        FrameSetup{"forward", "map", false, true}, FrameSetup{"deferred", "map", false, true},
        FrameSetup{"forward", "map", false, false, true},
        FrameSetup{"deferred", "map", false, false, true}}) {
    const std::string name = setup.pipeline + "/" + setup.shadows +
                             (setup.lightmap ? "/light-map" : "") +
                             (setup.duplicates ? "/duplicates" : "") + (setup.prt ? "/PRT" : "");
    // Direct light only (no ambient): identical bytes with SSAO on and off.
    const Image direct = frame(scene, setup, false, Color(0.0f));
    const Image direct_ssao = frame(scene, setup, true, Color(0.0f));
    ASSERT_EQ(direct.data().size(), direct_ssao.data().size());
    EXPECT_EQ(std::memcmp(direct.data().data(), direct_ssao.data().data(),
                          direct.data().size() * sizeof(float)),
              0)
        << name << ": SSAO changed a frame without indirect light";
    // With an indirect term: frame = direct + a·(indirect part), a the AO buffer.
    const Color ambient(0.4f, 0.35f, 0.3f);
    const Image off = frame(scene, setup, false, ambient);
    const Image on = frame(scene, setup, true, ambient);
    if (setup.prt) {
      // PRT transfer holds the visibility already (lighting.glsl,
      // ambient_term_includes_visibility): SSAO leaves the frame's bytes alone. The AO buffer
      // itself must still be computed, with occlusion in it, or this would pass vacuously.
      EXPECT_EQ(std::memcmp(off.data().data(), on.data().data(), off.data().size() * sizeof(float)),
                0)
          << name << ": SSAO darkened PRT, whose transfer already holds the visibility";
      const Image a = frame(scene, setup, true, ambient, "ao");
      int occluded = 0;
      for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) occluded += a.pixel(x, y)[0] < 0.95f;
      EXPECT_GT(occluded, 100) << name << ": no occlusion in the AO buffer";
      continue;
    }
    const Image a = frame(scene, setup, true, ambient, "ao");
    int darkened = 0;
    for (int y = 0; y < off.height(); ++y)
      for (int x = 0; x < off.width(); ++x)
        for (int c = 0; c < 3; ++c) {
          const double d = direct.pixel(x, y)[c], full = off.pixel(x, y)[c];
          const double expected = d + a.pixel(x, y)[0] * (full - d);
          // fp16 targets: each of the three images is rounded to 2^-11 relative, the AO too.
          const double tol = 4.0 * std::ldexp(1.0, -11) * std::abs(full);
          EXPECT_NEAR(on.pixel(x, y)[c], expected, tol) << name << " " << x << "," << y;
          if (on.pixel(x, y)[c] < full - 0.05 * (full - d)) ++darkened;
        }
    EXPECT_GT(darkened, 100) << name << ": SSAO darkened nothing";
  }
}

TEST_F(SsaoTest, OffIsTheFrameWithoutItAlsoAfterAToggle) {
  const Scene scene = load_scene("cornell");
  RenderSettings o;
  o.width = o.height = 64;
  o.set("lighting.ambient", Color(0.3f));
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  const Image before = r.ldr();
  RenderSettings on = o;
  on.enable("ssao");
  r.configure(on);
  r.render(*scene.camera);
  const Image with = r.ldr();
  r.configure(o);
  r.render(*scene.camera);
  const Image after = r.ldr();
  EXPECT_EQ(
      std::memcmp(before.data().data(), after.data().data(), before.data().size() * sizeof(float)),
      0);
  EXPECT_NE(
      std::memcmp(before.data().data(), with.data().data(), before.data().size() * sizeof(float)),
      0);
}

TEST_F(SsaoTest, BakedAoCombinesByMinimum) {
  // shaders/ambient_occlusion.glsl's combine_ambient_occlusion, run on the GPU.
  using namespace gpu;
  std::vector<float> pairs;
  std::vector<float> expected;
  for (float a : {0.0f, 0.2f, 0.5f, 0.9f, 1.0f})
    for (float b : {0.0f, 0.3f, 0.5f, 1.0f}) {
      pairs.insert(pairs.end(), {a, b});
      expected.push_back(std::min(a, b));
    }
  const uint32_t n = static_cast<uint32_t>(expected.size());
  Context& ctx = context();
  Buffer in = make_device_buffer(ctx, pairs.data(), pairs.size() * sizeof(float),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  Buffer out(ctx, n * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::kReadback);
  DescriptorSetLayout set_layout(
      ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
  DescriptorAllocator descriptors(ctx);
  const VkDescriptorSet set = descriptors.allocate(set_layout);
  DescriptorWriter()
      .buffer(set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.handle())
      .buffer(set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, out.handle())
      .commit(ctx.device());
  PipelineLayout layout(ctx, {set_layout.handle()}, 4);
  Pipeline pipeline(ctx, layout.handle(), "test_ao_combine.comp");
  ctx.immediate([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &set, 0,
                            nullptr);
    vkCmdPushConstants(cmd, layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(n), &n);
    vkCmdDispatch(cmd, 1, 1, 1);
  });
  std::vector<float> got(n);
  out.read(got.data(), n * sizeof(float));
  for (uint32_t i = 0; i < n; ++i)
    EXPECT_EQ(got[i], expected[i]) << pairs[2 * i] << ", " << pairs[2 * i + 1];
}

}  // namespace
}  // namespace illum::realtime
