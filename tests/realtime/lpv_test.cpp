// The `lpv` add-on (techniques/lpv.cpp, docs/realtime-lpv.md) on the device, validation layers
// on. Surfels are injected through the reflective shadow maps' interface (rsm_views.h) from a
// test source filled here, one surfel per layer, so the tests need no RSM: a propagation step
// conserves the sender's flux; light spreads symmetrically; a closed shell of the geometry
// volume blocks it, and a partial one passes what its blocking potential leaves; the indirect
// term is the looked-up irradiance × albedo/π × amplification.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "illum/core/color.h"
#include "illum/gpu/buffer.h"
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

constexpr float kPi = 3.14159265358979f;
constexpr int kGrid = 16;
// The box is 16 unit cells around the camera, snapped: cell (i, j, k) spans
// [i − 8, i − 7] × … in world units. Cell (8, 8, 8) is [0, 1]³.
constexpr float kCellLo = -8.0f;

struct Surfel {
  vec3 position{0.0f};
  vec3 normal{0.0f, 1.0f, 0.0f};
  Color flux{0.0f};
  float area = 0.0f;  // world units²; 0: no geometry
};

std::vector<Surfel> g_surfels;

// A surfel source with the reflective shadow maps' layout: "surfels.position", ".normal",
// ".flux" (1×1 texels, one layer per surfel) and ".views" (per layer an orthographic view
// looking along the surfel's normal whose texel area is the surfel's area). Registered as a
// shadow method so that its pass is declared, and runs, before the add-ons' (lpv's).
class SurfelSource final : public ShadowMethod {
 public:
  SurfelSource(TechniqueContext& ctx, const TechniqueDecl& decl)
      : ShadowMethod(ctx, decl), surfels_(g_surfels) {
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
    table_.resize(sizeof(rsm::RsmHeader) + n * sizeof(rsm::RsmView));
    rsm::RsmHeader h{};
    h.counts = glm::ivec4(static_cast<int>(n), 1, static_cast<int>(n), 0);
    std::memcpy(table_.data(), &h, sizeof(h));
    for (size_t k = 0; k < n; ++k) {
      rsm::RsmView v{};
      v.view_proj = v.inv_view_proj = glm::mat4(1.0f);
      v.direction = glm::vec4(surfels_[k].normal, surfels_[k].area);
      v.info = glm::ivec4(0, static_cast<int>(k), 1, rsm::kRsmViewOrthographic);
      std::memcpy(table_.data() + sizeof(h) + k * sizeof(v), &v, sizeof(v));
    }
  }

  void declare(FrameGraph& graph) override {
    for (const char* name : {"surfels.position", "surfels.normal", "surfels.flux"}) {
      ResourceDesc r;
      r.name = name;
      r.format = VK_FORMAT_R32G32B32A32_SFLOAT;
      r.layers = static_cast<uint32_t>(surfels_.size());
      r.array = true;
      // Sampled by lpv; also where it is off (the frame without it), for the image's view.
      r.extra_usage = VK_IMAGE_USAGE_SAMPLED_BIT;
      graph.add_resource(r);
    }
    ResourceDesc views;
    views.name = "surfels.views";
    views.kind = ResourceDesc::Kind::kBuffer;
    views.bytes = table_.size();
    graph.add_resource(views);
    PassDesc p;
    p.name = "surfels";
    p.technique = name();
    p.phase = Phase::kShadows;
    p.accesses = {{"surfels.position", kTransferDst},
                  {"surfels.normal", kTransferDst},
                  {"surfels.flux", kTransferDst},
                  {"surfels.views", kTransferDst}};
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

 private:
  void record(PassContext& pass) {
    const VkCommandBuffer c = pass.cmd();
    const uint32_t n = static_cast<uint32_t>(surfels_.size());
    const char* names[] = {"surfels.position", "surfels.normal", "surfels.flux"};
    for (uint32_t k = 0; k < 3; ++k) {
      VkBufferImageCopy copy{};
      copy.bufferOffset = VkDeviceSize(k) * n * 16;
      copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, n};
      copy.imageExtent = {1, 1, 1};
      vkCmdCopyBufferToImage(c, staging_.handle(), ctx_.resources.image(names[k]).handle(),
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    }
    vkCmdUpdateBuffer(c, ctx_.resources.buffer("surfels.views").handle(), 0, table_.size(),
                      table_.data());
  }

  std::vector<Surfel> surfels_;
  gpu::Buffer staging_;
  std::vector<unsigned char> table_;
};

class LpvTest : public test::ValidatedVulkanTest {
 protected:
  void SetUp() override {
    test::ValidatedVulkanTest::SetUp();
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

// A quad far from the cells the tests look at, one point light for the RSM lpv switches on.
Scene far_quad() {
  Scene s;
  s.name = "lpv";
  Material white;
  white.albedo = Color(0.5f);
  s.materials = {white};
  test::add_quad(s, {-3, -3, -6}, {3, -3, -6}, {3, 3, -6}, {-3, 3, -6}, 0);
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.0f, 0.0f, -3.0f);
  point.intensity = Color(1.0f);
  s.lights = {point};
  Camera cam;
  cam.position = vec3(0.2f, 0.3f, 0.1f);  // snaps the box's corner to (−8, −8, −8)
  cam.look_at = vec3(0.2f, 0.3f, -1.0f);
  cam.fov_y = radians(50.0f);
  s.camera = cam;
  return s;
}

// The accumulated light, as read back: per cell and channel (c0, c.x, c.y, c.z).
struct Volume {
  std::vector<Image> slices;
  glm::vec4 at(int c, glm::ivec3 x) const {
    const float* t = slices[size_t(x.z)].pixel(c * kGrid + x.x, x.y);
    return {t[0], t[1], t[2], t[3]};
  }
  // The flux of channel c's lobe in cell x: ∫ I dω = 2√π·c0.
  float flux(int c, glm::ivec3 x) const { return 2.0f * std::sqrt(kPi) * at(c, x).x; }
};

Volume propagate(const std::vector<Surfel>& surfels, int iterations) {
  g_surfels = surfels;
  const Scene scene = far_quad();
  RenderSettings o;
  o.width = o.height = 16;
  o.shadows = "surfels";
  o.enable("lpv");
  o.set("lpv.source", std::string("surfels"));
  o.set("lpv.grid", 16);
  o.set("lpv.cell", 1.0f);
  o.set("lpv.iterations", iterations);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  Volume v;
  for (int z = 0; z < kGrid; ++z) v.slices.push_back(r.read_resource("lpv.accum", uint32_t(z)));
  return v;
}

template <typename F>
void each_cell(F f) {
  for (int z = 0; z < kGrid; ++z)
    for (int y = 0; y < kGrid; ++y)
      for (int x = 0; x < kGrid; ++x) f(glm::ivec3(x, y, z));
}

const glm::ivec3 kSender(8, 8, 8);
const vec3 kCentre(0.5f);  // cell (8, 8, 8)'s centre in world units

// A clamped-cosine lobe along `n` injected into the sender: its position a quarter cell
// behind the centre, so position + ½·normal lies inside the cell.
Surfel lobe(vec3 n, Color flux) {
  Surfel s;
  s.normal = n;
  s.position = kCentre - 0.25f * n;
  s.flux = flux;
  return s;
}

// Six lobes along ±x, ±y, ±z: an isotropic source (its linear coefficients cancel).
std::vector<Surfel> isotropic(Color flux) {
  std::vector<Surfel> s;
  for (int a = 0; a < 3; ++a)
    for (float sign : {1.0f, -1.0f}) {
      vec3 n(0.0f);
      n[a] = sign;
      s.push_back(lobe(n, flux));
    }
  return s;
}

// fp16 storage of the read-back coefficients: 2⁻¹⁰ relative per value.
constexpr float kHalf = 1.0f / 1024.0f;

// 1. The injection puts the lobe's flux in the sender; one step moves it all to the
// neighbours (none leaves: the sender is interior), and seven steps keep it — 8× the
// sender's flux accumulated. Tolerance: 1 % (the task's bound); fp16 rounding is 0.1 %.
TEST_F(LpvTest, AStepConservesTheSendersFlux) {
  const Color flux(1.0f, 2.0f, 0.5f);
  const std::vector<Surfel> one = {lobe(glm::normalize(vec3(1.0f, 0.3f, -0.2f)), flux)};
  const Volume injected = propagate(one, 0);
  const Volume step = propagate(one, 1);
  const Volume seven = propagate(one, 7);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(injected.flux(c, kSender), flux[c], 2 * kHalf * flux[c]) << "channel " << c;
    float others = 0.0f, received = 0.0f, total = 0.0f;
    int reached = 0;
    each_cell([&](glm::ivec3 x) {
      if (x == kSender) return;
      others += std::abs(injected.flux(c, x));
      received += step.flux(c, x);
      reached += step.flux(c, x) > 0.0f ? 1 : 0;
    });
    each_cell([&](glm::ivec3 x) { total += seven.flux(c, x); });
    EXPECT_EQ(others, 0.0f) << "the injection touched other cells";
    EXPECT_EQ(step.at(c, kSender), injected.at(c, kSender)) << "nothing comes back in one step";
    EXPECT_GE(reached, 5) << "channel " << c;
    EXPECT_NEAR(received, flux[c], 0.01f * flux[c]) << "channel " << c << ": one step";
    EXPECT_NEAR(total, 8.0f * flux[c], 0.01f * 8.0f * flux[c]) << "channel " << c << ": 7 steps";
    std::printf("channel %d: sender %.5f, one step %.5f (%.3f%%), 7 steps %.5f of %.5f\n", c,
                injected.flux(c, kSender), received, 100.0f * (received / flux[c] - 1.0f), total,
                8.0f * flux[c]);
  }
}

// 2. An isotropic source gives its 6 neighbours equal flux, each lobe pointing away from the
// sender; after three steps every cell agrees with its mirror images through the sender's
// centre on each axis (c0 equal, the mirrored axis's coefficient negated). A lobe along +x
// sends more to +x than to −x, and the y and z mirrors still agree. Tolerance: fp16 rounding
// of both values, 2·2⁻¹⁰ of the larger, plus 1e-6 absolute.
TEST_F(LpvTest, LightSpreadsSymmetrically) {
  const Volume iso = propagate(isotropic(Color(1.0f)), 3);
  const Volume one = propagate({lobe(vec3(1.0f, 0.0f, 0.0f), Color(1.0f))}, 3);
  const auto near = [](float a, float b) {
    return std::abs(a - b) <= 2.0f * kHalf * std::max(std::abs(a), std::abs(b)) + 1e-6f;
  };
  const glm::ivec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const float first = iso.at(0, kSender + axes[0]).x;
  EXPECT_GT(first, 0.0f);
  for (const glm::ivec3& d : axes) {
    const glm::vec4 v = iso.at(0, kSender + d);
    EXPECT_TRUE(near(v.x, first)) << "neighbour " << d.x << "," << d.y << "," << d.z << ": " << v.x
                                  << " vs " << first;
    EXPECT_GT(glm::dot(vec3(v.y, v.z, v.w), vec3(d)), 0.0f) << "its lobe points away";
  }
  const auto mirror = [](glm::ivec3 x, int axis) {
    x[axis] = 2 * kSender[axis] - x[axis];
    return x;
  };
  int compared = 0, failed = 0;
  const auto check = [&](const Volume& v, int axis, const char* what) {
    each_cell([&](glm::ivec3 x) {
      const glm::ivec3 m = mirror(x, axis);
      if (m[axis] < 0 || m[axis] >= kGrid) return;
      for (int c = 0; c < 3; ++c) {
        const glm::vec4 a = v.at(c, x), b = v.at(c, m);
        for (int k = 0; k < 4; ++k) {
          const float want = (k == axis + 1) ? -b[k] : b[k];
          ++compared;
          if (!near(a[k], want) && ++failed <= 5)
            ADD_FAILURE() << what << " axis " << axis << " cell " << x.x << "," << x.y << "," << x.z
                          << "[" << k << "]: " << a[k] << " vs mirror " << want;
        }
      }
    });
  };
  for (int axis = 0; axis < 3; ++axis) check(iso, axis, "isotropic");
  for (int axis = 1; axis < 3; ++axis) check(one, axis, "+x lobe");
  EXPECT_EQ(failed, 0) << "of " << compared;
  EXPECT_GT(one.at(0, kSender + axes[0]).x, one.at(0, kSender + axes[1]).x);
}

// The shell: at each of the sender's 8 corners (the geometry volume's cells) three surfels
// facing into the sender along the axes, each of area a·s². At a shared face every corner's
// blocking potential seen by light leaving is ¾·a (the lobe facing it) + 2·¼·a (the two
// across) = 1.25·a, so a step passes 1 − 1.25·a of the sender's flux (nothing, a ≥ 0.8).
std::vector<Surfel> shell(float area) {
  std::vector<Surfel> s = isotropic(Color(1.0f, 0.5f, 0.25f));
  for (int k = 0; k < 8; ++k) {
    const vec3 corner(k & 1 ? 1.0f : 0.0f, k & 2 ? 1.0f : 0.0f, k & 4 ? 1.0f : 0.0f);
    for (int a = 0; a < 3; ++a) {
      Surfel g;
      g.position = corner;
      g.normal = vec3(0.0f);
      g.normal[a] = corner[a] > 0.5f ? -1.0f : 1.0f;
      g.area = area;
      s.push_back(g);
    }
  }
  return s;
}

float flux_outside(const Volume& v, int c) {
  float sum = 0.0f;
  each_cell([&](glm::ivec3 x) {
    if (x != kSender) sum += v.flux(c, x);
  });
  return sum;
}

// 3. A closed shell (a = 1: potential 1.25, clamped to 1) lets nothing out in eight steps:
// bound 1e-6 of the sender's flux (float rounding of a transmittance of exactly 0). A
// partial one (a = 0.4: potential 0.5) passes half in one step, within 1 %.
TEST_F(LpvTest, TheGeometryVolumeBlocks) {
  const Color flux(1.0f, 0.5f, 0.25f);
  const Volume closed = propagate(shell(1.0f), 8);
  const Volume partial = propagate(shell(0.4f), 1);
  for (int c = 0; c < 3; ++c) {
    const float sender = 6.0f * flux[c];
    EXPECT_NEAR(closed.flux(c, kSender), sender, 2 * kHalf * sender);
    EXPECT_LE(flux_outside(closed, c), 1e-6f * sender) << "channel " << c;
    EXPECT_NEAR(flux_outside(partial, c), 0.5f * sender, 0.01f * sender) << "channel " << c;
    std::printf("channel %d: closed shell passes %.3g, a = 0.4 passes %.5f of %.5f\n", c,
                flux_outside(closed, c), flux_outside(partial, c), sender);
  }
}

// The lookup as the input module does it, repeated on the CPU from the read-back volume:
// trilinear weights over the 8 cells around p (coordinates clamped to the outer centres),
// E(n) = max(0, √π/2·c0 − √(π/3)·c·n)/s² per channel (s = 1 here). `spread` gets each
// channel's largest minus smallest corner value, the scale of the filter's weight rounding.
Color lookup(const Volume& v, vec3 p, vec3 nrm, Color* spread) {
  const float n = float(kGrid);
  const vec3 t = glm::clamp(p - vec3(kCellLo), vec3(0.5f), vec3(n - 0.5f)) - 0.5f;
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(t)), glm::ivec3(kGrid - 2));
  const vec3 f = t - vec3(i0);
  Color e(0.0f), lo(1e30f), hi(-1e30f);
  const auto irradiance = [&](const glm::vec4& c) {
    return 0.886226925f * c.x - 1.0233267f * glm::dot(vec3(c.y, c.z, c.w), nrm);
  };
  for (int c = 0; c < 3; ++c) {
    glm::vec4 sum(0.0f);
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 at = i0 + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
      const float w =
          (k & 1 ? f.x : 1.0f - f.x) * (k & 2 ? f.y : 1.0f - f.y) * (k & 4 ? f.z : 1.0f - f.z);
      sum += w * v.at(c, at);
      lo[c] = std::min(lo[c], irradiance(v.at(c, at)));
      hi[c] = std::max(hi[c], irradiance(v.at(c, at)));
    }
    e[c] = std::max(irradiance(sum), 0.0f);
  }
  if (spread) *spread = hi - lo;
  return e;
}

// 4. The lookup: each pixel of the quad (z = −6, facing +z) with lpv on is the frame without
// it (ambient 0) plus albedo·E(n)/π × amplification, E looked up on the CPU from the
// read-back volume; an isotropic source two cells in front of it, four steps. Tolerance per
// channel: fp16 rounding of both frames, 2⁻¹⁰·(|with| + |without|); the filter's weight rounding,
// 3·2^−subTexelPrecisionBits of the corners' spread; 1e-4 of the term for the pixel's point found
// by a ray rather than rasterized.
TEST_F(LpvTest, TheIndirectTermIsTheVolumesIrradiance) {
  g_surfels = isotropic(Color(40.0f, 30.0f, 20.0f));
  for (Surfel& s : g_surfels) s.position += vec3(0.0f, 0.0f, -6.0f);  // cell (8, 8, 2)
  const Scene scene = far_quad();
  const Color albedo = scene.materials[0].albedo;
  const float amplification = 1.5f;
  const float quantum =
      3.0f * std::ldexp(1.0f, -static_cast<int>(context().limits().subTexelPrecisionBits));
  RenderSettings o;
  o.width = o.height = 48;
  o.shadows = "surfels";
  o.set("lighting.ambient", Color(0.0f));
  Renderer off(context(), scene, o);
  off.render(*scene.camera);
  const Image without = off.hdr();
  o.enable("lpv");
  o.set("lpv.source", std::string("surfels"));
  o.set("lpv.grid", 16);
  o.set("lpv.cell", 1.0f);
  o.set("lpv.iterations", 4);
  o.set("lpv.amplification", amplification);
  Renderer on(context(), scene, o);
  on.render(*scene.camera);
  const Image with = on.hdr();
  Volume v;
  for (int z = 0; z < kGrid; ++z) v.slices.push_back(on.read_resource("lpv.accum", uint32_t(z)));
  int compared = 0, failed = 0;
  float largest = 0.0f;
  for (int y = 1; y < o.height - 1; ++y)
    for (int x = 1; x < o.width - 1; ++x) {
      const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, o.width, o.height);
      const float t = (-6.0f - ray.origin.z) / ray.direction.z;
      const vec3 p = ray.origin + t * ray.direction;
      if (std::abs(p.x) > 2.9f || std::abs(p.y) > 2.9f) continue;
      Color spread;
      const Color e = lookup(v, p, vec3(0.0f, 0.0f, 1.0f), &spread);
      ++compared;
      for (int c = 0; c < 3; ++c) {
        const float want = albedo[c] * e[c] / kPi * amplification;
        const float a = with.rgb(x, y)[c], b = without.rgb(x, y)[c];
        const float tol = kHalf * (std::abs(a) + std::abs(b)) +
                          albedo[c] * amplification / kPi * quantum * spread[c] + 1e-4f * want;
        largest = std::max(largest, want);
        if (std::abs((a - b) - want) > tol && ++failed <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " channel " << c
                        << ": with − without = " << a - b << ", albedo·E/π·amplification " << want
                        << " (tolerance " << tol << ")";
      }
    }
  EXPECT_GT(compared, 500);
  EXPECT_GT(largest, 0.05f) << "the term should be far above the tolerance";
  std::printf("%d pixels, largest term %.4f, %d off\n", compared, largest, failed);
}

// The face integrals the propagation uses: the far face's and side faces' solid angles sum to
// the shared face's, 4π/6; the far face's has the closed form 4·asin(1/10) (a square of side
// 1 at distance 3⁄2); the side faces' vector integrals balance on the axis.
TEST(LpvFaces, TheFacesTileTheSharedFacesSolidAngle) {
  const LpvFaces f = lpv_face_integrals(256);
  EXPECT_NEAR(f.far_solid_angle, 4.0 * std::asin(0.1), 1e-5);
  EXPECT_NEAR(f.far_solid_angle + 4.0 * f.side_solid_angle, 4.0 * M_PI / 6.0, 1e-5);
  // The five faces cover the shared face's (z = ½, |x|, |y| ≤ ½) directions, so their ∫ω·d dω
  // sum to the shared face's, integrated here on its own plane at 4× the samples.
  double shared = 0.0;
  const int m = 1024;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = (i + 0.5) / m - 0.5, v = (j + 0.5) / m - 0.5, z = 0.5;
      const double r = std::sqrt(u * u + v * v + z * z);
      shared += z / r * z / (r * r * r) / (double(m) * m);
    }
  EXPECT_NEAR(f.far_along + 4.0 * f.side_along, shared, 1e-5);
  std::printf("far face %.6f sr (∫ω·d %.6f), side face %.6f sr (∫ω·e %.6f, ∫ω·d %.6f)\n",
              f.far_solid_angle, f.far_along, f.side_solid_angle, f.side_across, f.side_along);
}

}  // namespace
}  // namespace illum::realtime
