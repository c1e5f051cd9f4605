// The `vpl` add-on (techniques/vpl.cpp, docs/realtime-vpl.md) on the device, validation layers
// on: one synthetic VPL lights a floor as the closed form Φ/π·max(0, n_i·ω)·max(0, −n·ω)/d²
// says, pixel by pixel, and the frames of the forward and visibility pipelines hold
// albedo·E/π as their indirect term; the clamp replaces d² by c² inside c and nowhere else;
// with one VPL per texel the irradiance is the brute-force sum over the reflective shadow
// map's texels (a spot's one view, a point light's six faces), and with fewer the
// flux-weighted draw keeps the sum's mean.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/rsm_views.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr double kPi = 3.14159265358979;
constexpr int kSize = 48;
// The shader's point comes from the depth buffer: up to kDepthError of the camera distance t
// from the surface (its D32 depth and the perspective divide; measured on lavapipe: 3.8e-4).
// E moves by at most 4δ/d of itself for a point moved by δ at distance d from a VPL (2δ/d from
// 1/d², δ/d from each cosine). Tolerances: that, plus 1e-4 relative for float arithmetic.
constexpr double kDepthError = 1e-3;
double tolerance(double value, float t, float d) {
  return (1e-4 + 4.0 * kDepthError * t / d) * value;
}
const Color kAlbedo(0.8f, 0.6f, 0.4f);

struct Surfel {
  vec3 position{0.0f};
  vec3 normal{0.0f, -1.0f, 0.0f};
  Color flux{0.0f};
};

std::vector<Surfel> g_surfels;
int g_side = 1;  // texels per side of each layer: g_surfels holds layers × side² of them

// A source with the reflective shadow maps' layout: "surfels.position", ".normal", ".flux",
// g_side² texels a layer (1: one layer per surfel, so each surfel is one VPL exactly). A shadow
// method, so that its pass is declared, and runs, before the add-ons' (vpl's).
class SurfelSource final : public ShadowMethod {
 public:
  SurfelSource(TechniqueContext& ctx, const TechniqueDecl& decl)
      : ShadowMethod(ctx, decl), surfels_(g_surfels), side_(uint32_t(g_side)) {
    const size_t n = surfels_.size();
    staging_ = gpu::Buffer(ctx.gpu, 3 * n * 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           gpu::MemoryUsage::kUpload);
    std::vector<glm::vec4> texels(3 * n);
    for (size_t k = 0; k < n; ++k) {
      const Surfel& s = surfels_[k];
      texels[k] = glm::vec4(s.position, 1.0f);
      texels[n + k] = glm::vec4(s.normal, 0.0f);
      texels[2 * n + k] = glm::vec4(s.flux.r, s.flux.g, s.flux.b, 0.0f);
    }
    staging_.write(texels.data(), texels.size() * sizeof(glm::vec4));
  }

  void declare(FrameGraph& graph) override {
    for (const char* name : {"surfels.position", "surfels.normal", "surfels.flux"}) {
      ResourceDesc r;
      r.name = name;
      r.format = VK_FORMAT_R32G32B32A32_SFLOAT;
      r.width = r.height = side_;
      r.layers = static_cast<uint32_t>(surfels_.size()) / (side_ * side_);
      r.array = true;
      r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT;
      graph.add_resource(r);
    }
    PassDesc p;
    p.name = "surfels";
    p.technique = name();
    p.phase = Phase::kShadows;
    p.accesses = {{"surfels.position", kTransferDst},
                  {"surfels.normal", kTransferDst},
                  {"surfels.flux", kTransferDst}};
    p.record = [this](PassContext& pass) {
      const uint32_t n = static_cast<uint32_t>(surfels_.size());
      const char* names[] = {"surfels.position", "surfels.normal", "surfels.flux"};
      for (uint32_t k = 0; k < 3; ++k) {
        VkBufferImageCopy copy{};
        copy.bufferOffset = VkDeviceSize(k) * n * 16;
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, n / (side_ * side_)};
        copy.imageExtent = {side_, side_, 1};
        vkCmdCopyBufferToImage(pass.cmd(), staging_.handle(),
                               ctx_.resources.image(names[k]).handle(),
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
      }
    };
    graph.add_pass(std::move(p));
  }

 private:
  std::vector<Surfel> surfels_;
  uint32_t side_ = 1;
  gpu::Buffer staging_;
};

class VplTest : public test::ValidatedVulkanTest {
 protected:
  void SetUp() override {
    test::ValidatedVulkanTest::SetUp();
    g_side = 1;
    TechniqueDecl d;
    d.name = "surfels";
    d.kind = TechniqueKind::kShadowMethod;
    d.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
      return std::make_unique<SurfelSource>(ctx, *find_technique("surfels"));
    };
    registration_ = std::make_unique<TechniqueRegistration>(d);
  }
  void TearDown() override {
    registration_.reset();
    test::ValidatedVulkanTest::TearDown();
  }

 private:
  std::unique_ptr<TechniqueRegistration> registration_;
};

// A floor y = 0, |x|, |z| ≤ 4, seen from above at an angle.
Scene floor_scene() {
  Scene s;
  s.name = "vpl-floor";
  Material m;
  m.albedo = kAlbedo;
  s.materials = {m};
  test::add_quad(s, {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, 0);
  Camera cam;
  cam.position = vec3(0.3f, 3.0f, 3.0f);
  cam.look_at = vec3(0.0f, 0.0f, 0.0f);
  cam.fov_y = radians(60.0f);
  s.camera = cam;
  return s;
}

// Where pixel (x, y)'s centre ray meets the plane n·p = offset (t < 0: it does not).
struct Hit {
  vec3 p{0.0f};
  float t = -1.0f;
};
Hit pixel_on_plane(const Scene& s, int x, int y, vec3 n, float offset) {
  const FrameView v = camera_view(*s.camera, s.bounds(), kSize, kSize);
  const vec2 ndc((x + 0.5f) / kSize * 2.0f - 1.0f, (y + 0.5f) / kSize * 2.0f - 1.0f);
  const vec4 a = v.inv_view_proj * vec4(ndc, 0.0f, 1.0f);
  const vec4 b = v.inv_view_proj * vec4(ndc, 1.0f, 1.0f);
  const vec3 o = vec3(a) / a.w, d = glm::normalize(vec3(b) / b.w - o);
  Hit h;
  const float den = glm::dot(n, d);
  if (std::abs(den) < 1e-6f) return h;
  h.t = (offset - glm::dot(n, o)) / den;
  h.p = o + h.t * d;
  return h;
}

// The closed form, in double: E at p (normal n) from a VPL at x (normal m) of flux Φ.
double irradiance(const vec3& p, const vec3& n, const vec3& x, const vec3& m, double flux,
                  double clamp) {
  const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(x);
  const double d2 = glm::dot(d, d), dist = std::sqrt(d2);
  const double cs = glm::dot(glm::dvec3(m), d) / dist, cr = -glm::dot(glm::dvec3(n), d) / dist;
  if (cs <= 0.0 || cr <= 0.0) return 0.0;
  return flux / kPi * cs * cr / std::max(d2, clamp * clamp);
}

RenderSettings surfel_settings(const std::string& pipeline, float clamp) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = pipeline;
  o.shadows = "surfels";
  o.enable("vpl");
  o.set("vpl.source", std::string("surfels"));
  o.set("vpl.clamp", clamp);
  o.set("lighting.ambient", Color(0.05f, 0.04f, 0.03f));
  return o;
}

// Every floor pixel at least two pixels inside the quad (the shader's normal takes a
// neighbour): "vpl.irradiance" against the closed form, `tolerance` plus 1e-6 of the largest
// value. A wrong cosine, falloff or 1/π is off by far more.
struct Checked {
  int pixels = 0, lit = 0, dark = 0;
  double worst = 0.0;  // the largest error as a depth error δ/t
};
Checked check_floor(const Scene& scene, const Image& e, const Surfel& s, float clamp) {
  Checked c;
  double largest = 0.0;
  for (int ch = 0; ch < 3; ++ch)
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) largest = std::max(largest, double(e.pixel(x, y)[ch]));
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      const Hit h = pixel_on_plane(scene, x, y, vec3(0, 1, 0), 0.0f);
      if (h.t <= 0.0f || std::abs(h.p.x) > 3.8f || std::abs(h.p.z) > 3.8f) continue;
      ++c.pixels;
      for (int ch = 0; ch < 3; ++ch) {
        const double want =
            irradiance(h.p, vec3(0, 1, 0), s.position, s.normal, double(s.flux[ch]), clamp);
        const double got = e.pixel(x, y)[ch];
        const float d = glm::length(h.p - s.position);
        if (want > 1e-3 * largest)
          c.worst = std::max(c.worst, (std::abs(got / want - 1.0) - 1e-4) * d / (4.0 * h.t));
        EXPECT_NEAR(got, want, tolerance(want, h.t, d) + 1e-6 * largest)
            << "pixel " << x << "," << y << " channel " << ch;
        if (ch == 0) (want > 0.0 ? c.lit : c.dark) += 1;
      }
    }
  return c;
}

// One VPL tilted over the floor: the points in front of its lobe lit as the closed form says,
// those behind it black; the frame's indirect term is albedo·E/π in place of albedo·ambient
// (no lights: the frame is emission 0 + indirect), in both pipelines that take it.
TEST_F(VplTest, OneVplLightsTheFloorAsTheClosedForm) {
  const Scene scene = floor_scene();
  const Surfel s{vec3(0.4f, 0.7f, -0.3f), glm::normalize(vec3(0.8f, -1.0f, 0.3f)),
                 Color(2.0f, 1.0f, 0.5f)};
  g_surfels = {s};
  for (const std::string pipeline : {"forward", "visibility"}) {
    Renderer r(context(), scene, surfel_settings(pipeline, 0.0f));
    r.render(*scene.camera);
    const Image e = r.read_resource("vpl.irradiance");
    const Checked c = check_floor(scene, e, s, 0.0f);
    EXPECT_GT(c.pixels, kSize * kSize / 3);
    EXPECT_GT(c.lit, c.pixels / 4);
    EXPECT_GT(c.dark, c.pixels / 10);
    const Image with = r.hdr();
    RenderSettings off = surfel_settings(pipeline, 0.0f);
    off.disable("vpl");
    Renderer r0(context(), scene, off);
    r0.render(*scene.camera);
    const Image without = r0.hdr();
    const Color ambient(0.05f, 0.04f, 0.03f);
    int compared = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        if (e.pixel(x, y)[3] != 1.0f) continue;
        ++compared;
        for (int ch = 0; ch < 3; ++ch) {
          // fp16 HDR targets: half an ulp of each frame's value.
          const float want = kAlbedo[ch] * (e.pixel(x, y)[ch] / float(kPi) - ambient[ch]);
          const float got = with.rgb(x, y)[ch] - without.rgb(x, y)[ch];
          const float tol = 1e-3f * (std::abs(with.rgb(x, y)[ch]) + without.rgb(x, y)[ch]) + 1e-6f;
          EXPECT_NEAR(got, want, tol) << pipeline << " pixel " << x << "," << y;
        }
      }
    EXPECT_GT(compared, kSize * kSize / 3) << pipeline;
    std::printf(
        "%s: %d floor pixels checked, %d lit, %d behind the lobe, depth error δ/t up to %.1e\n",
        pipeline.c_str(), c.pixels, c.lit, c.dark, c.worst);
  }
}

// The clamp c: d² becomes c² where the VPL is closer than c, and nothing changes farther.
TEST_F(VplTest, ClampBoundsTheFalloffInsideItsDistanceOnly) {
  const Scene scene = floor_scene();
  const Surfel s{vec3(0.1f, 0.3f, 0.2f), vec3(0, -1, 0), Color(1.0f, 0.5f, 0.25f)};
  g_surfels = {s};
  const float clamp = 0.6f;
  Renderer r(context(), scene, surfel_settings("forward", clamp));
  r.render(*scene.camera);
  const Image clamped = r.read_resource("vpl.irradiance");
  check_floor(scene, clamped, s, clamp);
  Renderer u(context(), scene, surfel_settings("forward", 0.0f));
  u.render(*scene.camera);
  const Image free = u.read_resource("vpl.irradiance");
  int inside = 0, outside = 0;
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      const Hit h = pixel_on_plane(scene, x, y, vec3(0, 1, 0), 0.0f);
      if (h.t <= 0.0f || std::abs(h.p.x) > 3.8f || std::abs(h.p.z) > 3.8f) continue;
      const float d = glm::length(h.p - s.position);
      const float a = clamped.pixel(x, y)[0], b = free.pixel(x, y)[0];
      if (d < clamp - 1e-3f) {
        ++inside;
        // The shader's d² is the depth buffer's point's: 2δ/d relative.
        const float ratio = d * d / (clamp * clamp);
        EXPECT_NEAR(a / b, ratio, 0.5 * tolerance(ratio, h.t, d)) << x << "," << y;
      } else if (d > clamp + 1e-3f) {
        ++outside;
        EXPECT_NEAR(a, b, 1e-6f * b) << x << "," << y;  // the same point in both frames
      }
    }
  EXPECT_GT(inside, 4);
  EXPECT_GT(outside, 100);
  std::printf("clamp %.2f: %d pixels inside, %d outside\n", clamp, inside, outside);
}

// A floor in front of a wall z = −1, lit by `light`, seen from the front.
Scene wall_scene(const Light& light) {
  Scene scene = floor_scene();
  scene.name = "vpl-wall";
  test::add_quad(scene, {-4, 0, -1}, {4, 0, -1}, {4, 4, -1}, {-4, 4, -1}, 0);
  scene.lights = {light};
  scene.camera->position = vec3(0.3f, 2.0f, 3.0f);
  scene.camera->look_at = vec3(0.0f, 1.0f, -1.0f);
  return scene;
}

// "vpl.irradiance" with `count` VPLs a view from 64² maps, and the maps' `layers` layers
// (position, normal, flux of each) when asked.
Image run_maps(const Scene& scene, int count, int layers, std::vector<Image>* maps) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = "forward";
  o.shadows = "none";
  o.enable("vpl");
  o.set("rsm.resolution", 64);
  o.set("vpl.count", count);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  if (maps)
    for (int k = 0; k < layers; ++k)
      for (const char* name : {rsm::kPosition, rsm::kNormal, rsm::kFlux})
        maps->push_back(r.read_resource(name, uint32_t(k)));
  return r.read_resource("vpl.irradiance");
}

// Every wall pixel of the 4096-VPL image (one VPL per texel) against the brute-force sum over
// the maps' texels; returns the wall pixels and the sum's mean (R).
struct Wall {
  std::vector<std::pair<int, int>> pixels;
  double mean_sum = 0.0, mean_image = 0.0;
};
Wall check_wall(const Scene& scene, const Image& all, const std::vector<Image>& maps) {
  Wall w;
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      const Hit h = pixel_on_plane(scene, x, y, vec3(0, 0, 1), -1.0f);
      const Hit f = pixel_on_plane(scene, x, y, vec3(0, 1, 0), 0.0f);
      if (h.t <= 0.0f || (f.t > 0.0f && f.t < h.t) || h.p.y < 0.05f || h.p.y > 3.9f ||
          std::abs(h.p.x) > 3.9f)
        continue;
      w.pixels.push_back({x, y});
      glm::dvec3 sum(0.0);
      float nearest = 1e30f;  // the nearest VPL, for the depth buffer's share of the tolerance
      for (size_t k = 0; k + 2 < maps.size(); k += 3)
        for (int ty = 0; ty < 64; ++ty)
          for (int tx = 0; tx < 64; ++tx) {
            const float* pos = maps[k].pixel(tx, ty);
            if (pos[3] != 1.0f) continue;
            const float* nrm = maps[k + 1].pixel(tx, ty);
            const vec3 m = glm::normalize(vec3(nrm[0], nrm[1], nrm[2]));
            const vec3 x0(pos[0], pos[1], pos[2]);
            nearest = std::min(nearest, glm::length(h.p - x0));
            for (int ch = 0; ch < 3; ++ch)
              sum[ch] += irradiance(h.p, vec3(0, 0, 1), x0, m, maps[k + 2].pixel(tx, ty)[ch], 0.0);
          }
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(all.pixel(x, y)[ch], sum[ch], tolerance(sum[ch], h.t, nearest) + 1e-9)
            << "pixel " << x << "," << y << " channel " << ch;
      w.mean_image += all.pixel(x, y)[0];
      w.mean_sum += sum[0];
    }
  if (!w.pixels.empty()) {
    w.mean_image /= double(w.pixels.size());
    w.mean_sum /= double(w.pixels.size());
  }
  return w;
}

// A spot on the floor in front of the wall: the wall's irradiance from one VPL per texel
// (count 4096 on 64² maps) is the sum over the read-back map's texels, and with 64 or 256
// VPLs (blocks of 8² or 4² texels, one drawn texel each) the mean over the wall stays that
// sum's.
TEST_F(VplTest, OneVplPerTexelIsTheSumOverTheMapAndFewerKeepItsMean) {
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(0.2f, 2.0f, 0.3f);
  spot.direction = glm::normalize(vec3(0.1f, -1.0f, -0.3f));
  spot.cone_half_angle = radians(35.0f);
  spot.intensity = Color(3.0f, 2.0f, 1.0f);
  const Scene scene = wall_scene(spot);
  std::vector<Image> maps;
  const Image all = run_maps(scene, 4096, 1, &maps);
  const Wall w = check_wall(scene, all, maps);
  ASSERT_GT(w.pixels.size(), size_t(kSize * kSize / 4));
  ASSERT_GT(w.mean_sum, 0.0);
  std::printf("4096 VPLs on 64² maps: %zu wall pixels, mean E %.5f, brute force %.5f\n",
              w.pixels.size(), w.mean_image, w.mean_sum);
  for (int count : {64, 256}) {
    const Image e = run_maps(scene, count, 1, nullptr);
    double mean = 0.0;
    for (auto [x, y] : w.pixels) mean += e.pixel(x, y)[0];
    mean /= double(w.pixels.size());
    std::printf("%d VPLs: mean E over the wall / brute force - 1 = %+.4f\n", count,
                mean / w.mean_sum - 1.0);
    EXPECT_NEAR(mean / w.mean_sum, 1.0, 0.05) << count << " VPLs";
  }
}

// A point light: six cube faces, 4096 VPLs each, every one of them summed — the wall's
// irradiance is the brute-force sum over all six layers' texels.
TEST_F(VplTest, APointLightsSixFacesAreAllSummed) {
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(-0.3f, 1.2f, 0.2f);
  point.intensity = Color(1.0f, 2.0f, 3.0f);
  const Scene scene = wall_scene(point);
  std::vector<Image> maps;
  const Image all = run_maps(scene, 4096, 6, &maps);
  const Wall w = check_wall(scene, all, maps);
  ASSERT_GT(w.pixels.size(), size_t(kSize * kSize / 4));
  // The floor in front of the wall is seen by several faces, each adding its share.
  int faces = 0;
  for (size_t k = 0; k < maps.size(); k += 3) {
    double flux = 0.0;
    for (int ty = 0; ty < 64; ++ty)
      for (int tx = 0; tx < 64; ++tx) flux += maps[k + 2].pixel(tx, ty)[0];
    faces += flux > 0.0;
  }
  EXPECT_GE(faces, 3);
  std::printf("point light: %d faces with flux, mean E %.5f, brute force %.5f\n", faces,
              w.mean_image, w.mean_sum);
}

// The draw within a block: 2×2 blocks of a 16² source (64 VPLs), each with a texel A of flux 3
// facing the floor, a texel B of flux 1 facing away and two empty texels. A is drawn with
// probability ¾ and weighted 4, so the floor's irradiance averages the sum's, Σ 3·f(A); a
// draw of the first texel with flux gives 4/3 of it, Φ_j without the 1/p_j weight 1/4 of it.
TEST_F(VplTest, TheDrawIsInProportionToFlux) {
  const Scene scene = floor_scene();
  constexpr int side = 16;
  g_side = side;
  g_surfels.assign(side * side, Surfel{vec3(0.0f), vec3(0, 1, 0), Color(0.0f)});
  std::vector<vec3> senders;
  for (int by = 0; by < side / 2; ++by)
    for (int bx = 0; bx < side / 2; ++bx) {
      const vec3 at(-1.75f + 0.5f * bx, 1.0f, -1.75f + 0.5f * by);
      senders.push_back(at);
      g_surfels[size_t(2 * by) * side + 2 * bx] = {at, vec3(0, -1, 0), Color(3.0f)};
      g_surfels[size_t(2 * by) * side + 2 * bx + 1] = {at, vec3(0, 1, 0), Color(1.0f)};
    }
  RenderSettings o = surfel_settings("forward", 0.0f);
  o.set("vpl.count", 64);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  const Image e = r.read_resource("vpl.irradiance");
  double image = 0.0, sum = 0.0;
  int pixels = 0;
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      const Hit h = pixel_on_plane(scene, x, y, vec3(0, 1, 0), 0.0f);
      if (h.t <= 0.0f || std::abs(h.p.x) > 3.8f || std::abs(h.p.z) > 3.8f) continue;
      ++pixels;
      image += e.pixel(x, y)[0];
      for (const vec3& a : senders)
        sum += irradiance(h.p, vec3(0, 1, 0), a, vec3(0, -1, 0), 3.0, 0.0);
    }
  ASSERT_GT(pixels, kSize * kSize / 3);
  // One draw per block with the fixed seed: 48 ± 3.5 of the 64 blocks take A, so the ratio is
  // 1 ± 0.07 (measured −0.073).
  std::printf("64 blocks of A (flux 3) and B (flux 1): mean E / sum - 1 = %+.4f\n",
              image / sum - 1.0);
  EXPECT_NEAR(image / sum, 1.0, 0.2);
}

TEST_F(VplTest, DeferredPipelineIsRefused) {
  const Scene scene = floor_scene();
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = "deferred";
  o.enable("vpl");
  EXPECT_THROW(Renderer(context(), scene, o), Error);
}

}  // namespace
}  // namespace illum::realtime
