// Hand-built test scenes and a brute-force CPU reference for the real-time renderer tests:
// a Cornell-style box (1 m, Lambert walls, two rotated blocks) lit by one point light, and
// per-pixel direct lighting with exact shadow rays (Möller–Trumbore over every triangle).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "illum/core/image.h"
#include "illum/gpu/context.h"
#include "illum/scene/scene.h"

namespace illum::test {

// One Vulkan context per test binary, validation layers on (the tests assert that it
// reported no message).
inline gpu::Context& context() {
  static gpu::Context* c = [] {
    gpu::ContextOptions o;
    o.validation = true;
    return new gpu::Context(o);
  }();
  return *c;
}

// A test on that context that fails if the validation layers report anything while it runs.
class ValidatedVulkanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(context().validation_enabled()) << "VK_LAYER_KHRONOS_validation is required";
    before_ = context().validation_message_count();
  }
  void TearDown() override {
    EXPECT_EQ(context().validation_message_count(), before_) << "validation messages were emitted";
  }

 private:
  size_t before_ = 0;
};

// Whether two HDR images hold the same bits (for changes that must not move a pixel: "close"
// is not enough).
inline bool identical(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0;
}

inline void add_quad(Scene& s, vec3 a, vec3 b, vec3 c, vec3 d, int material) {
  Mesh m;
  m.positions = {a, b, c, d};
  const vec3 n = glm::normalize(glm::cross(b - a, c - a));
  m.normals = {n, n, n, n};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  s.meshes.push_back(m);
  s.instances.push_back({"", static_cast<int>(s.meshes.size() - 1), mat4(1.0f)});
}

// Axis-aligned box of half size h at centre c, rotated by `angle` about +y.
inline void add_block(Scene& s, vec3 c, vec3 h, float angle, int material) {
  const mat4 t = glm::rotate(glm::translate(mat4(1.0f), c), angle, vec3(0, 1, 0));
  auto p = [&](float x, float y, float z) {
    return vec3(t * vec4(x * h.x, y * h.y, z * h.z, 1.0f));
  };
  add_quad(s, p(-1, 1, -1), p(-1, 1, 1), p(1, 1, 1), p(1, 1, -1), material);      // top
  add_quad(s, p(-1, -1, 1), p(1, -1, 1), p(1, 1, 1), p(-1, 1, 1), material);      // +z
  add_quad(s, p(1, -1, -1), p(-1, -1, -1), p(-1, 1, -1), p(1, 1, -1), material);  // −z
  add_quad(s, p(1, -1, 1), p(1, -1, -1), p(1, 1, -1), p(1, 1, 1), material);      // +x
  add_quad(s, p(-1, -1, -1), p(-1, -1, 1), p(-1, 1, 1), p(-1, 1, -1), material);  // −x
}

inline Scene cornell_point_light() {
  Scene s;
  s.name = "test-cornell";
  Material white, red, green;
  white.albedo = Color(0.725f, 0.71f, 0.68f);
  red.albedo = Color(0.63f, 0.065f, 0.05f);
  green.albedo = Color(0.14f, 0.45f, 0.091f);
  s.materials = {white, red, green};
  add_quad(s, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, 0);            // floor
  add_quad(s, {0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}, 0);            // ceiling
  add_quad(s, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);            // back wall (z = 0)
  add_quad(s, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, 1);            // left wall, red
  add_quad(s, {1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}, 2);            // right wall, green
  add_block(s, {0.33f, 0.3f, 0.35f}, {0.15f, 0.3f, 0.15f}, 0.3f, 0);     // tall block
  add_block(s, {0.68f, 0.15f, 0.62f}, {0.15f, 0.15f, 0.15f}, -0.3f, 0);  // short block
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(0.5f, 0.9f, 0.55f);
  light.intensity = Color(1.0f, 0.9f, 0.8f);
  s.lights.push_back(light);
  Camera cam;
  cam.position = vec3(0.5f, 0.5f, 2.2f);
  cam.look_at = vec3(0.5f, 0.5f, 0.0f);
  cam.fov_y = radians(40.0f);
  s.camera = cam;
  return s;
}

// cornell_point_light() with a second, dimmer point light whose range (0.6) ends inside the
// box: the light-volume path and the radius window are exercised.
inline Scene cornell_two_point_lights() {
  Scene s = cornell_point_light();
  Light second;
  second.type = LightType::kPoint;
  second.position = vec3(0.8f, 0.5f, 0.8f);
  second.intensity = Color(0.2f, 0.3f, 0.5f);
  second.range = 0.6f;
  s.lights.push_back(second);
  return s;
}

struct Triangle {
  vec3 a, b, c;
  int material;
  int surface;  // one id per mesh instance (edge detection)
};

inline std::vector<Triangle> world_triangles(const Scene& s) {
  std::vector<Triangle> out;
  for (size_t i = 0; i < s.instances.size(); ++i) {
    const Instance& inst = s.instances[i];
    const Mesh& m = s.meshes[static_cast<size_t>(inst.mesh)];
    auto w = [&](uint32_t k) { return vec3(inst.transform * vec4(m.positions[k], 1.0f)); };
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
      out.push_back({w(m.indices[t]), w(m.indices[t + 1]), w(m.indices[t + 2]), m.material,
                     static_cast<int>(i)});
  }
  return out;
}

// Möller–Trumbore; returns t or −1.
inline float intersect(const Triangle& tri, const vec3& o, const vec3& d) {
  const vec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
  const vec3 p = glm::cross(d, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return -1.0f;
  const float inv = 1.0f / det;
  const vec3 s = o - tri.a;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return -1.0f;
  const vec3 q = glm::cross(s, e1);
  const float v = glm::dot(d, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return -1.0f;
  return glm::dot(e2, q) * inv;
}

struct Reference {
  Image radiance;                 // direct lighting, RGB
  std::vector<int> surface;       // per pixel, −1 = background
  std::vector<uint8_t> shadowed;  // per pixel: the (first) light is blocked
};

// Direct lighting from the scene's point lights with exact shadows, Lambert BRDF, two-sided
// surfaces (normal facing the viewer), pixel centres; the same model the GPU shades.
inline Reference direct_lighting_reference(const Scene& s, int width, int height) {
  const std::vector<Triangle> tris = world_triangles(s);
  Reference ref;
  ref.radiance = Image(width, height, 3);
  ref.surface.assign(static_cast<size_t>(width) * height, -1);
  ref.shadowed.assign(static_cast<size_t>(width) * height, 0);
  auto closest = [&](const vec3& o, const vec3& d, float tmax, int* index) {
    float best = tmax;
    *index = -1;
    for (size_t i = 0; i < tris.size(); ++i) {
      const float t = intersect(tris[i], o, d);
      if (t > 1e-5f && t < best) {
        best = t;
        *index = static_cast<int>(i);
      }
    }
    return best;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Ray ray = s.camera->generate_ray(x + 0.5f, y + 0.5f, width, height);
      int hit = -1;
      const float t = closest(ray.origin, ray.direction, kInf, &hit);
      if (hit < 0) continue;
      const Triangle& tri = tris[static_cast<size_t>(hit)];
      const size_t pi = static_cast<size_t>(y) * width + x;
      ref.surface[pi] = tri.surface;
      const vec3 p = ray.origin + t * ray.direction;
      vec3 n = glm::normalize(glm::cross(tri.b - tri.a, tri.c - tri.a));
      if (glm::dot(n, ray.direction) > 0.0f) n = -n;
      const Material& m = s.materials[static_cast<size_t>(tri.material)];
      Color L = m.emission;
      for (size_t li = 0; li < s.lights.size(); ++li) {
        const Light& light = s.lights[li];
        const vec3 to = light.position - p;
        const float d2 = glm::dot(to, to);
        const vec3 l = to / std::sqrt(d2);
        const float cos_theta = glm::dot(n, l);
        if (cos_theta <= 0.0f) {
          if (li == 0) ref.shadowed[pi] = 1;  // self-shadowed: unlit for both techniques
          continue;
        }
        int blocker = -1;
        const vec3 o = p + n * 1e-4f;
        closest(o, l, std::sqrt(d2) - 2e-4f, &blocker);
        if (blocker >= 0) {
          if (li == 0) ref.shadowed[pi] = 1;
          continue;
        }
        L += m.albedo * kInvPi * light.intensity * (cos_theta / d2);
      }
      ref.radiance.set_rgb(x, y, L);
    }
  return ref;
}

// Pixels within `radius` of a change of surface or of shadowing (geometry and shadow edges).
inline std::vector<uint8_t> edge_mask(const Reference& ref, int width, int height, int radius) {
  std::vector<uint8_t> edge(static_cast<size_t>(width) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      bool e = false;
      for (int dy = -radius; dy <= radius && !e; ++dy)
        for (int dx = -radius; dx <= radius && !e; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
          const size_t j = static_cast<size_t>(yy) * width + xx;
          e = ref.surface[j] != ref.surface[i] || ref.shadowed[j] != ref.shadowed[i];
        }
      edge[i] = e ? 1 : 0;
    }
  return edge;
}

struct Agreement {
  size_t compared = 0, within = 0;
  double mean_rel = 0.0;
};

// The fraction of non-edge pixels whose RGB agree within `rel` relative error (against
// max(reference, floor) so black pixels compare absolutely).
inline Agreement compare(const Image& gpu, const Image& cpu, const std::vector<uint8_t>& edge,
                         float rel, float floor) {
  Agreement a;
  for (int y = 0; y < cpu.height(); ++y)
    for (int x = 0; x < cpu.width(); ++x) {
      if (edge[static_cast<size_t>(y) * cpu.width() + x]) continue;
      const Color g = gpu.rgb(x, y), c = cpu.rgb(x, y);
      float worst = 0.0f;
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(g[k] - c[k]) / std::max(c[k], floor));
      ++a.compared;
      a.within += worst <= rel ? 1 : 0;
      a.mean_rel += worst;
    }
  a.mean_rel /= std::max<size_t>(1, a.compared);
  return a;
}

// 1 where a pixel or one of its 8 neighbours sees another surface of the reference.
inline std::vector<uint8_t> geometry_edges(const Reference& ref, int width, int height) {
  std::vector<uint8_t> edge(static_cast<size_t>(width) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, width - 1), yy = std::clamp(y + dy, 0, height - 1);
          if (ref.surface[static_cast<size_t>(yy) * width + xx] !=
              ref.surface[static_cast<size_t>(y) * width + x])
            edge[static_cast<size_t>(y) * width + x] = 1;
        }
  return edge;
}

}  // namespace illum::test
