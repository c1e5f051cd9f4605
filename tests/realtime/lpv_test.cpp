// The `lpv` add-on (techniques/lpv.cpp, docs/realtime-lpv.md) on the device, validation layers
// on. Surfels are injected through the reflective shadow maps' interface (rsm_views.h) from a
// test source filled here, one surfel per layer, so the tests need no RSM: a propagation step
// conserves the sender's flux; light spreads symmetrically; a closed shell of the geometry
// volume blocks it, and a partial one passes what its blocking potential leaves; the indirect
// term is the looked-up irradiance × albedo/π × amplification, blended across the cascades'
// borders without a seam; the cascades do not crawl as the camera moves; two spot lights'
// reflective shadow maps both inject.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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
#include "illum/realtime/techniques/lpv_cascades.h"
#include "illum/realtime/techniques/techniques.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr float kPi = 3.14159265358979f;
constexpr int kGrid = 16;
constexpr int kCascades = 3;  // lpv.cascades' default
// The finest cascade is 16 unit cells around the camera, snapped: cell (i, j, k) spans
// [i − 8, i − 7] × … in world units. Cell (8, 8, 8) is [0, 1]³.
const vec3 kCamera(0.2f, 0.3f, 0.1f);

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
  cam.position = kCamera;  // snaps the finest box's corner to (−8, −8, −8)
  cam.look_at = kCamera + vec3(0.0f, 0.0f, -1.1f);
  cam.fov_y = radians(50.0f);
  s.camera = cam;
  return s;
}

// The accumulated light, as read back: per cascade, cell and channel (c0, c.x, c.y, c.z).
struct Volume {
  std::vector<Image> slices;  // cascade q's slice z is slices[q·n + z]
  std::vector<LpvCascade> boxes;
  glm::vec4 at(int c, glm::ivec3 x, int q = 0) const {
    const float* t = slices[size_t(q * kGrid + x.z)].pixel(c * kGrid + x.x, x.y);
    return {t[0], t[1], t[2], t[3]};
  }
  // The flux of channel c's lobe in cell x: ∫ I dω = 2√π·c0.
  float flux(int c, glm::ivec3 x, int q = 0) const { return 2.0f * std::sqrt(kPi) * at(c, x, q).x; }
};

Volume read_volume(Renderer& r, const Camera& camera, int cascades) {
  Volume v;
  for (int z = 0; z < kGrid * cascades; ++z)
    v.slices.push_back(r.read_resource("lpv.accum", uint32_t(z)));
  v.boxes = lpv_cascades(camera.position, kGrid, cascades, 1.0f, Bounds3{});
  return v;
}

// One cascade unless told: the light's flux is compared cell by cell, and a finer cascade's
// outer cells hold a blend with the next one.
Volume propagate(const std::vector<Surfel>& surfels, int iterations, int cascades = 1,
                 const vec3& camera = kCamera) {
  g_surfels = surfels;
  Scene scene = far_quad();
  scene.camera->position = camera;
  scene.camera->look_at = camera + vec3(0.0f, 0.0f, -1.0f);
  RenderSettings o;
  o.width = o.height = 16;
  o.shadows = "surfels";
  o.enable("lpv");
  o.set("lpv.source", std::string("surfels"));
  o.set("lpv.grid", 16);
  o.set("lpv.cell", 1.0f);
  o.set("lpv.iterations", iterations);
  o.set("lpv.cascades", cascades);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  return read_volume(r, *scene.camera, cascades);
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

// The lookup as the input module does it, repeated on the CPU from the read-back volume: the
// finest cascade holding p (inside its outermost cell centres), trilinear weights over the 8
// cells around p (coordinates clamped to the outer centres), E(n) = max(0, √π/2·c0 −
// √(π/3)·c·n)/s² per channel. `spread` gets each channel's largest minus smallest corner
// value, the scale of the filter's weight rounding.
Color cascade_irradiance(const Volume& v, int q, vec3 p, vec3 nrm, Color* spread,
                         float dampening = 0.0f, float* damp_error = nullptr) {
  const float n = float(kGrid);
  const LpvCascade& box = v.boxes[size_t(q)];
  const vec3 t = glm::clamp((p - box.lo) / box.cell, vec3(0.5f), vec3(n - 0.5f)) - 0.5f;
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(t)), glm::ivec3(kGrid - 2));
  const vec3 f = t - vec3(i0);
  Color e(0.0f), lo(1e30f), hi(-1e30f);
  const float area = box.cell * box.cell;
  const auto irradiance = [&](const glm::vec4& c) {
    return (0.886226925f * c.x - 1.0233267f * glm::dot(vec3(c.y, c.z, c.w), nrm)) / area;
  };
  for (int c = 0; c < 3; ++c) {
    glm::vec4 sum(0.0f);
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 at = i0 + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
      const float w =
          (k & 1 ? f.x : 1.0f - f.x) * (k & 2 ? f.y : 1.0f - f.y) * (k & 4 ? f.z : 1.0f - f.z);
      sum += w * v.at(c, at, q);
      lo[c] = std::min(lo[c], irradiance(v.at(c, at, q)));
      hi[c] = std::max(hi[c], irradiance(v.at(c, at, q)));
    }
    e[c] = std::max(irradiance(sum), 0.0f);
  }
  if (spread) *spread = hi - lo;
  // The leak dampening from the fourth part, (∇Σc0, Σc0): 1 + dampening·min(∇Σc0·n, 0)/Σc0.
  // `damp_error`: the factor's error bound per unit of the filter's weight rounding, from the
  // corners' spread of the derivative and the sum.
  if (dampening > 0.0f) {
    glm::vec4 d(0.0f);
    float dlo = 1e30f, dhi = -1e30f, wlo = 1e30f, whi = -1e30f;
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 at = i0 + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
      const float w =
          (k & 1 ? f.x : 1.0f - f.x) * (k & 2 ? f.y : 1.0f - f.y) * (k & 4 ? f.z : 1.0f - f.z);
      const glm::vec4 g = v.at(3, at, q);
      d += w * g;
      dlo = std::min(dlo, glm::dot(vec3(g), nrm));
      dhi = std::max(dhi, glm::dot(vec3(g), nrm));
      wlo = std::min(wlo, g.w);
      whi = std::max(whi, g.w);
    }
    const float sum = std::max(d.w, 1e-20f), derivative = glm::dot(vec3(d), nrm);
    const float damp = std::clamp(1.0f + dampening * std::min(derivative, 0.0f) / sum, 0.0f, 1.0f);
    if (damp_error)
      *damp_error = dampening * ((dhi - dlo) + std::abs(derivative / sum) * (whi - wlo)) / sum;
    e = e * damp;
  } else if (damp_error) {
    *damp_error = 0.0f;
  }
  return e;
}

int finest_holding(const Volume& v, vec3 p) {
  int q = static_cast<int>(v.boxes.size()) - 1;
  for (int k = q - 1; k >= 0; --k)
    if (lpv_inside_cells(v.boxes[size_t(k)], kGrid, p) > 0.0f) q = k;
  return q;
}

Color lookup(const Volume& v, vec3 p, vec3 nrm, Color* spread) {
  return cascade_irradiance(v, finest_holding(v, p), p, nrm, spread);
}

// The frame with lpv on and off (ambient 0) for an isotropic source two cells in front of
// the quad (z = −6, facing +z), four steps, seen from `camera`: each pixel of the quad with
// lpv on is the frame without it plus albedo·E(n)/π × amplification, E looked up on the CPU
// from the read-back volume. Tolerance per channel: fp16 rounding of both frames,
// 2⁻¹⁰·(|with| + |without|); the filter's weight rounding, 3·2^−subTexelPrecisionBits of the
// corners' spread; 1e-4 of the term for the pixel's point found by a ray rather than
// rasterized.
struct TermCheck {
  Volume volume;
  int compared = 0, failed = 0;
  float largest = 0.0f;
  std::vector<float> xs;  // the compared pixels' world x
};

TermCheck check_indirect_term(const vec3& eye, const vec3& target) {
  g_surfels = isotropic(Color(40.0f, 30.0f, 20.0f));
  for (Surfel& s : g_surfels) s.position += vec3(0.0f, 0.0f, -6.0f);  // cell (8, 8, 2)
  Scene scene = far_quad();
  scene.camera->position = eye;
  scene.camera->look_at = target;
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
  o.set("lpv.dampening", 0.0f);  // a heuristic, tested on its own (10)
  Renderer on(context(), scene, o);
  on.render(*scene.camera);
  const Image with = on.hdr();
  TermCheck r;
  r.volume = read_volume(on, *scene.camera, kCascades);
  for (int y = 1; y < o.height - 1; ++y)
    for (int x = 1; x < o.width - 1; ++x) {
      const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, o.width, o.height);
      const float t = (-6.0f - ray.origin.z) / ray.direction.z;
      const vec3 p = ray.origin + t * ray.direction;
      if (std::abs(p.x) > 2.9f || std::abs(p.y) > 2.9f) continue;
      Color spread;
      const Color e = lookup(r.volume, p, vec3(0.0f, 0.0f, 1.0f), &spread);
      ++r.compared;
      r.xs.push_back(p.x);
      for (int c = 0; c < 3; ++c) {
        const float want = albedo[c] * e[c] / kPi * amplification;
        const float a = with.rgb(x, y)[c], b = without.rgb(x, y)[c];
        const float tol = kHalf * (std::abs(a) + std::abs(b)) +
                          albedo[c] * amplification / kPi * quantum * spread[c] + 1e-4f * want;
        r.largest = std::max(r.largest, want);
        if (std::abs((a - b) - want) > tol && ++r.failed <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " channel " << c
                        << ": with − without = " << a - b << ", albedo·E/π·amplification " << want
                        << " (tolerance " << tol << ")";
      }
    }
  return r;
}

// 4. The lookup from the tests' camera: the quad lies 1.5 cells inside the finest cascade's
// outer cell centres (z), where its cells hold a blend with the next cascade.
TEST_F(LpvTest, TheIndirectTermIsTheVolumesIrradiance) {
  const TermCheck r = check_indirect_term(kCamera, kCamera + vec3(0.0f, 0.0f, -1.1f));
  EXPECT_NEAR(lpv_inside_cells(r.volume.boxes[0], kGrid, vec3(0.0f, 0.0f, -6.0f)), 1.5f, 1e-5f);
  EXPECT_GT(r.compared, 500);
  EXPECT_GT(r.largest, 0.05f) << "the term should be far above the tolerance";
  std::printf("%d pixels, largest term %.4f, %d off\n", r.compared, r.largest, r.failed);
}

// 5. The finest cascade's border across the quad: from a camera 5.2 cells along +x the finest
// box's outer cell centres lie at x = −2.5. Pixels on both sides match the lookup (as 4), and
// the lookup is continuous across the border: just inside and just outside it (±10⁻³ cells)
// the irradiance agrees within 2 % — the finer cascade's outer cells hold the coarser one's
// light sampled at their centres, interpolated again between them — where the two cascades
// differ by far more two cells inside (printed; the test needs it above 10 %), the jump a
// lookup without the blend would show.
TEST_F(LpvTest, CascadesBlendWithoutASeam) {
  const TermCheck r = check_indirect_term(vec3(5.2f, 0.3f, 0.1f), vec3(0.0f, 0.3f, -6.0f));
  const LpvCascade& fine = r.volume.boxes[0];
  const float border = fine.lo.x + 0.5f * fine.cell;
  ASSERT_NEAR(border, -2.5f, 1e-5f);
  const auto count = [&](bool inside) {
    return std::count_if(r.xs.begin(), r.xs.end(), [&](float x) { return (x > border) == inside; });
  };
  EXPECT_GT(count(true), 50);
  EXPECT_GT(count(false), 5);
  EXPECT_EQ(r.failed, 0);
  const vec3 n(0.0f, 0.0f, 1.0f);
  for (float y : {-2.0f, 0.3f, 1.5f}) {
    const vec3 at(border, y, -6.0f), eps(1e-3f * fine.cell, 0.0f, 0.0f);
    const Color in = lookup(r.volume, at + eps, n, nullptr);
    const Color out = lookup(r.volume, at - eps, n, nullptr);
    const vec3 deep = at + vec3(2.0f * fine.cell, 0.0f, 0.0f);
    const Color e0 = cascade_irradiance(r.volume, 0, deep, n, nullptr);
    const Color e1 = cascade_irradiance(r.volume, 1, deep, n, nullptr);
    for (int c = 0; c < 3; ++c) {
      const float scale = std::max(in[c], out[c]);
      EXPECT_NEAR(in[c], out[c], 0.02f * scale) << "y " << y << " channel " << c;
      EXPECT_GT(std::abs(e0[c] - e1[c]), 0.1f * std::max(e0[c], e1[c]))
          << "the cascades agree: no seam to test";
    }
    std::printf("y %.1f: inside %.4f, outside %.4f; two cells in, finest %.4f, next %.4f\n", y,
                in[0], out[0], e0[0], e1[0]);
  }
}

// 6. Boxes (lpv_cascades): each cascade's corner is a multiple of its cell size, the cell
// doubles from one to the next, each lies inside the next coarser one with kLpvBlendCells of
// its cells to spare (so where a cascade blends the coarser one has full weight), and a camera
// moved within a cell of every cascade leaves every corner where it was; moved by one finest
// cell, only the cascades whose snap it crosses move, by one of their cells. cell = 0: the
// coarsest spans the scene's bounds.
TEST(LpvCascades, SnappedNestedAndStill) {
  const Bounds3 none;
  for (const int n : {16, 32, 64}) {
    for (const vec3 eye : {vec3(0.2f, 0.3f, 0.1f), vec3(-13.7f, 5.1f, 100.3f)}) {
      const std::vector<LpvCascade> a = lpv_cascades(eye, n, 4, 0.5f, none);
      ASSERT_EQ(a.size(), 4u);
      for (size_t k = 0; k < a.size(); ++k) {
        EXPECT_FLOAT_EQ(a[k].cell, 0.5f * float(1 << k));
        const vec3 m = a[k].lo / a[k].cell;
        EXPECT_EQ(m, glm::round(m)) << "cascade " << k << " not snapped";
        if (k + 1 < a.size()) {
          const float margin = kLpvBlendCells + 0.5f;  // in the coarser one's cells
          const vec3 lo = a[k + 1].lo + margin * a[k + 1].cell;
          const vec3 hi = a[k + 1].lo + (float(n) - margin) * a[k + 1].cell;
          EXPECT_TRUE(glm::all(glm::greaterThanEqual(a[k].lo, lo)) &&
                      glm::all(glm::lessThanEqual(a[k].lo + float(n) * a[k].cell, hi)))
              << "cascade " << k << " not nested, n " << n;
        }
      }
      // Within the finest cell holding the eye (the coarser cells hold it too).
      const vec3 cell0 = glm::floor(eye / 0.5f) * 0.5f;
      const std::vector<LpvCascade> b =
          lpv_cascades(cell0 + vec3(0.49f, 0.01f, 0.3f), n, 4, 0.5f, none);
      for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].lo, b[k].lo) << "cascade " << k;
      // One finest cell along x.
      const std::vector<LpvCascade> c =
          lpv_cascades(eye + vec3(0.5f, 0.0f, 0.0f), n, 4, 0.5f, none);
      for (size_t k = 0; k < a.size(); ++k) {
        const bool crosses =
            std::floor((eye.x + 0.5f) / a[k].cell) != std::floor(eye.x / a[k].cell);
        EXPECT_EQ(c[k].lo.x - a[k].lo.x, crosses ? a[k].cell : 0.0f) << "cascade " << k;
        EXPECT_EQ(c[k].lo.y, a[k].lo.y);
        EXPECT_EQ(c[k].lo.z, a[k].lo.z);
      }
    }
  }
  Bounds3 scene;
  scene.extend(vec3(-1.0f, 0.0f, 2.0f));
  scene.extend(vec3(3.0f, 1.0f, 2.5f));
  const std::vector<LpvCascade> d = lpv_cascades(vec3(1.0f, 0.5f, -3.0f), 32, 3, 0.0f, scene);
  EXPECT_FLOAT_EQ(d[2].cell, 4.0f / 31.0f);
  EXPECT_TRUE(glm::all(glm::lessThanEqual(d[2].lo, scene.min)) &&
              glm::all(glm::greaterThanEqual(d[2].lo + 32.0f * d[2].cell, scene.max)));
  EXPECT_FLOAT_EQ(d[0].cell, d[2].cell / 4.0f);
}

// 7. The cascades do not crawl: a camera moved within the finest cell gives the same volume,
// every cascade bit for bit; moved by one finest cell along x, the finest cascade's cells are
// its old ones shifted by one (the light sits in the same world cells) and the coarser ones,
// whose snap it does not cross, are unchanged. One lobe, three steps: the light stays away
// from the boxes' faces; the finest cascade is compared where neither copy blends (two cells
// from its faces).
TEST_F(LpvTest, TheCascadesStayPutAsTheCameraMoves) {
  const std::vector<Surfel> one = {lobe(glm::normalize(vec3(1.0f, 0.3f, -0.2f)), Color(1.0f))};
  const Volume a = propagate(one, 3, kCascades);
  const Volume b = propagate(one, 3, kCascades, kCamera + vec3(0.4f, 0.3f, 0.2f));
  const Volume c = propagate(one, 3, kCascades, kCamera + vec3(1.0f, 0.0f, 0.0f));
  ASSERT_EQ(c.boxes[0].lo.x, a.boxes[0].lo.x + 1.0f);
  ASSERT_EQ(c.boxes[1].lo, a.boxes[1].lo);
  const auto interior = [](glm::ivec3 x) {
    return glm::all(glm::greaterThanEqual(x, glm::ivec3(2))) &&
           glm::all(glm::lessThan(x, glm::ivec3(kGrid - 2)));
  };
  int differ = 0, compared = 0;
  std::vector<int> lit(kCascades, 0);
  for (int q = 0; q < kCascades; ++q)
    each_cell([&](glm::ivec3 x) {
      for (int ch = 0; ch < 3; ++ch) {
        lit[size_t(q)] += a.at(ch, x, q).x > 0.0f ? 1 : 0;
        differ += a.at(ch, x, q) != b.at(ch, x, q) ? 1 : 0;
        const glm::ivec3 next = x + glm::ivec3(1, 0, 0);
        if (q == 0 && interior(x) && interior(next)) {
          ++compared;
          differ += c.at(ch, x, 0) != a.at(ch, next, 0) ? 1 : 0;
        }
        if (q > 0) differ += c.at(ch, x, q) != a.at(ch, x, q) ? 1 : 0;
      }
    });
  for (int q = 0; q < kCascades; ++q)
    EXPECT_GT(lit[size_t(q)], 3 * 20) << "the light should reach many cells of cascade " << q;
  EXPECT_GT(compared, 1000);
  EXPECT_EQ(differ, 0);
}

// 8. Several lights: two spot lights over a floor, one on each half (x < 0 and x > 0), the
// right one three times as bright. With both, the injected flux (no steps, the coarsest
// cascade, which spans the scene) of each half is what that light alone injects, within 1 %
// (fp16 storage of each cell), and the right half's is three times the left's: both lights'
// reflective-shadow-map layers are injected.
TEST_F(LpvTest, EverySpotLightsMapIsInjected) {
  Scene scene;
  scene.name = "two spots";
  Material white;
  white.albedo = Color(0.5f);
  scene.materials = {white};
  test::add_quad(scene, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, 0);
  Light left;
  left.type = LightType::kSpot;
  left.position = vec3(-2.0f, 1.5f, 0.0f);
  left.direction = vec3(0.0f, -1.0f, 0.0f);
  left.cone_half_angle = radians(30.0f);
  left.intensity = Color(1.0f);
  Light right = left;
  right.position.x = 2.0f;
  right.intensity = Color(3.0f);
  Camera cam;
  cam.position = vec3(0.0f, 3.0f, 6.0f);
  cam.look_at = vec3(0.0f);
  scene.camera = cam;
  const auto halves = [&](const std::vector<Light>& lights) {
    scene.lights = lights;
    RenderSettings o;
    o.width = o.height = 16;
    o.enable("lpv");
    o.set("lpv.grid", 16);
    o.set("lpv.iterations", 0);
    Renderer r(context(), scene, o);
    r.render(*scene.camera);
    const Volume v = read_volume(r, cam, kCascades);
    const LpvCascade box = lpv_cascades(cam.position, kGrid, kCascades, 0.0f, scene.bounds())[2];
    std::array<double, 2> sum{0.0, 0.0};
    each_cell([&](glm::ivec3 x) {
      const float centre = box.lo.x + (float(x.x) + 0.5f) * box.cell;
      sum[centre > 0.0f ? 1 : 0] += v.flux(0, x, kCascades - 1);
    });
    return sum;
  };
  const std::array<double, 2> a = halves({left}), b = halves({right}), both = halves({left, right});
  EXPECT_GT(a[0], 0.0);
  EXPECT_LT(a[1], 1e-6 * a[0]) << "the left spot lights the left half only";
  EXPECT_LT(b[0], 1e-6 * b[1]);
  EXPECT_NEAR(both[0], a[0], 0.01 * a[0]);
  EXPECT_NEAR(both[1], b[1], 0.01 * b[1]);
  EXPECT_NEAR(both[1], 3.0 * both[0], 0.01 * 3.0 * both[0]);
  std::printf("injected flux: left alone %.5f, right alone %.5f, both %.5f + %.5f\n", a[0], b[1],
              both[0], both[1]);
}

// 9. Temporal amortisation. Period 1: a running renderer switched from two steps to four gives
// a fresh four-step renderer's volume bit for bit (every cascade rebuilt, nothing kept).
// Period 3, switched from two steps to four after the first frame (which builds every
// cascade): frame f rebuilds cascade f mod 3 only; a rebuilt cascade's cells move halfway from
// the two-step light to the four-step light (fp16 rounding of both, 2·2⁻¹⁰ of the larger),
// the others stay the two-step light bit for bit. The finer cascades are compared two cells
// from their faces, where they do not blend with the next.
TEST_F(LpvTest, AnUpdatePeriodRebuildsOneCascadeAFrame) {
  g_surfels = {lobe(glm::normalize(vec3(1.0f, 0.3f, -0.2f)), Color(1.0f, 2.0f, 0.5f))};
  const Scene scene = far_quad();
  const auto settings = [](int iterations, int period) {
    RenderSettings o;
    o.width = o.height = 16;
    o.shadows = "surfels";
    o.enable("lpv");
    o.set("lpv.source", std::string("surfels"));
    o.set("lpv.grid", 16);
    o.set("lpv.cell", 1.0f);
    o.set("lpv.iterations", iterations);
    o.set("lpv.update_period", period);
    return o;
  };
  const auto fresh = [&](int iterations) {
    Renderer r(context(), scene, settings(iterations, 1));
    r.render(*scene.camera);
    return read_volume(r, *scene.camera, kCascades);
  };
  const Volume two = fresh(2), four = fresh(4);
  const auto compared = [](int q, glm::ivec3 x) {
    return q == kCascades - 1 || (glm::all(glm::greaterThanEqual(x, glm::ivec3(2))) &&
                                  glm::all(glm::lessThan(x, glm::ivec3(kGrid - 2))));
  };
  {
    Renderer r(context(), scene, settings(2, 1));
    r.render(*scene.camera);
    r.configure(settings(4, 1));
    r.render(*scene.camera);
    const Volume v = read_volume(r, *scene.camera, kCascades);
    int differ = 0;
    for (int q = 0; q < kCascades; ++q)
      each_cell([&](glm::ivec3 x) {
        for (int c = 0; c < 3; ++c) differ += v.at(c, x, q) != four.at(c, x, q) ? 1 : 0;
      });
    EXPECT_EQ(differ, 0) << "period 1";
  }
  Renderer r(context(), scene, settings(2, 3));
  r.render(*scene.camera);
  r.configure(settings(4, 3));
  std::vector<bool> rebuilt(kCascades, false);
  for (int frame = 1; frame <= 3; ++frame) {
    r.render(*scene.camera);
    rebuilt[size_t(frame % 3)] = true;
    const Volume v = read_volume(r, *scene.camera, kCascades);
    for (int q = 0; q < kCascades; ++q) {
      int differ = 0, moved = 0, cells = 0;
      each_cell([&](glm::ivec3 x) {
        if (!compared(q, x)) return;
        for (int c = 0; c < 3; ++c) {
          const glm::vec4 got = v.at(c, x, q), a = two.at(c, x, q), b = four.at(c, x, q);
          ++cells;
          moved += a != b ? 1 : 0;
          for (int k = 0; k < 4; ++k) {
            const float want = rebuilt[size_t(q)] ? 0.5f * (a[k] + b[k]) : a[k];
            const float tol = rebuilt[size_t(q)]
                                  ? 2.0f * kHalf * std::max(std::abs(a[k]), std::abs(b[k])) + 1e-7f
                                  : 0.0f;
            if (std::abs(got[k] - want) > tol && ++differ <= 3)
              ADD_FAILURE() << "frame " << frame << " cascade " << q << " cell " << x.x << ","
                            << x.y << "," << x.z << "[" << k << "]: " << got[k] << ", want "
                            << want;
          }
        }
      });
      EXPECT_GT(moved, 30) << "cascade " << q << ": two and four steps should differ";
      EXPECT_EQ(differ, 0) << "frame " << frame << " cascade " << q << " of " << cells;
    }
  }
}

// 10. Leak dampening. An isotropic source one cell behind the quad (z = −7; no geometry
// volume: a wall thinner than a cell), so the quad's front (facing +z, away from the light)
// is lit through the wall. Each pixel against the CPU's damped lookup (the tolerance of 4,
// plus the dampening factor's rounding), and the light that leaks to the front, summed over
// the pixels, against the light the back of the wall receives at the same points (the lookup
// with the normal −z): without dampening the front gets over half of it (measured 95 %), with
// dampening 1 under ¾ of that undamped leak (measured 62 % of the back's light).
TEST_F(LpvTest, DampeningCutsLightThroughAThinWall) {
  g_surfels = isotropic(Color(40.0f, 30.0f, 20.0f));
  for (Surfel& s : g_surfels) s.position += vec3(0.0f, 0.0f, -7.0f);  // cell (8, 8, 1)
  const Scene scene = far_quad();
  const Color albedo = scene.materials[0].albedo;
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
  o.set("lpv.dampening", 1.0f);
  Renderer on(context(), scene, o);
  on.render(*scene.camera);
  const Image with = on.hdr();
  const Volume v = read_volume(on, *scene.camera, kCascades);
  const vec3 front(0.0f, 0.0f, 1.0f);
  int compared = 0, failed = 0;
  double back = 0.0, leak = 0.0, damped = 0.0;
  for (int y = 1; y < o.height - 1; ++y)
    for (int x = 1; x < o.width - 1; ++x) {
      const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, o.width, o.height);
      const float t = (-6.0f - ray.origin.z) / ray.direction.z;
      const vec3 p = ray.origin + t * ray.direction;
      if (std::abs(p.x) > 2.9f || std::abs(p.y) > 2.9f) continue;
      const int q = finest_holding(v, p);
      Color spread;
      float damp_error = 0.0f;
      const Color e = cascade_irradiance(v, q, p, front, &spread, 1.0f, &damp_error);
      const Color undamped = cascade_irradiance(v, q, p, front, nullptr);
      const Color behind = cascade_irradiance(v, q, p, -front, nullptr);
      ++compared;
      for (int c = 0; c < 3; ++c) {
        const float want = albedo[c] * e[c] / kPi;
        const float a = with.rgb(x, y)[c], b = without.rgb(x, y)[c];
        const float tol = kHalf * (std::abs(a) + std::abs(b)) +
                          albedo[c] / kPi * quantum * (spread[c] + undamped[c] * damp_error) +
                          1e-4f * want;
        back += behind[c];
        leak += undamped[c];
        damped += (a - b) * kPi / albedo[c];
        if (std::abs((a - b) - want) > tol && ++failed <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " channel " << c
                        << ": with − without = " << a - b << ", damped term " << want
                        << " (tolerance " << tol << ")";
      }
    }
  EXPECT_GT(compared, 500);
  EXPECT_GT(leak, 0.5 * back) << "the undamped lookup should leak";
  EXPECT_LT(damped, 0.75 * leak);
  std::printf("%d pixels: front/back undamped %.1f%%, damped %.1f%%\n", compared,
              100.0 * leak / back, 100.0 * damped / back);
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
