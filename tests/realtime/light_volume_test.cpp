// The worked example `light_volume` (techniques/light_volume.cpp) on the device, validation
// layers on: its 3-D volume against a CPU evaluation of the same closed form; the frame with
// it against the frame without it plus the indirect term it contributes through the lighting
// inputs, in every frame pipeline; its history blend converging geometrically after a light
// moves; and, updated every N frames, its readers taking the newest copy.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "illum/core/color.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/renderer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

constexpr int kSize = 48;
// fp16 rounding, relative: one unit in the last place, as Vulkan lets a conversion to a
// 16-bit float round towards zero (lavapipe does) as well as to nearest.
constexpr float kUlp = 1.0f / 1024.0f;

class LightVolumeTest : public test::ValidatedVulkanTest {};

// A floor (y = 0) and a back wall (z = 0) spanning the unit cube, so the volume's box is
// [0, 1]³; a point light, a spot with a radius window and a directional light.
Scene floor_and_wall() {
  Scene s;
  s.name = "light-volume";
  Material white;
  white.albedo = Color(0.8f, 0.6f, 0.4f);
  s.materials = {white};
  test::add_quad(s, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, 0);  // floor, +y
  test::add_quad(s, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);  // back wall, +z
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.3f, 0.55f, 0.6f);
  point.intensity = Color(0.6f, 0.5f, 0.4f);
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(0.75f, 0.8f, 0.45f);
  spot.direction = glm::normalize(vec3(0.1f, -1.0f, -0.2f));
  spot.cone_half_angle = radians(35.0f);
  spot.intensity = Color(0.3f, 0.4f, 0.7f);
  spot.range = 0.9f;
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, -0.4f));
  sun.irradiance = Color(0.2f, 0.2f, 0.15f);
  s.lights = {point, spot, sun};
  Camera cam;
  cam.position = vec3(0.5f, 0.75f, 1.5f);
  cam.look_at = vec3(0.5f, 0.2f, 0.3f);
  cam.fov_y = radians(55.0f);
  s.camera = cam;
  return s;
}

// Per channel c: E_c(n) = a[c] + b[c]·n, the texel (a, b.x, b.y, b.z) of part c.
struct Linear {
  std::array<glm::vec4, 3> c{};
};

// The closed form the volume holds, evaluated independently of the shader: each light's
// irradiance Φ on a surface facing it (lighting.glsl's attenuation: inverse square below a
// floor of min_d2, the radius window, the cone, the cosine falloff of area spots) projected
// on SH bands 0 and 1: a = Φ/4, b = Φ/2 · l. Also returns Σ|Φ| for the arithmetic tolerance.
Linear closed_form(const std::vector<Light>& lights, vec3 p, float min_d2, float* sum_phi) {
  Linear out;
  float sum = 0.0f;
  for (const Light& light : lights) {
    vec3 l;
    Color phi;
    if (light.type == LightType::kDirectional) {
      l = -glm::normalize(light.direction);
      phi = light.irradiance;
    } else if (light.type == LightType::kPoint || light.type == LightType::kSpot) {
      const vec3 to = light.position - p;
      const float d2 = glm::dot(to, to);
      const float r = light.range;
      if (r > 0.0f && d2 >= r * r) continue;
      l = to / std::sqrt(d2);
      float atten = 1.0f / std::max(d2, min_d2);
      if (r > 0.0f) atten *= std::max(1.0f - d2 / (r * r), 0.0f);
      const float cos_axis = glm::dot(-l, glm::normalize(light.direction));
      if (light.type == LightType::kSpot && cos_axis < light.cos_cutoff()) continue;
      if (light.type == LightType::kSpot && light.cosine_falloff) atten *= cos_axis;
      phi = light.intensity * atten;
    } else {
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      out.c[size_t(c)] += glm::vec4(0.25f * phi[c], 0.5f * phi[c] * l);
      sum += std::abs(phi[c]);
    }
  }
  if (sum_phi) *sum_phi = sum;
  return out;
}

struct Grid {
  int n = 16;
  vec3 lo{0.0f}, extent{1.0f};
  vec3 centre(int x, int y, int z) const { return lo + (vec3(x, y, z) + 0.5f) * extent / float(n); }
  // light_volume.cpp: the squared half of the smallest cell side.
  float min_d2() const {
    const vec3 cell = extent / float(n);
    const float h = 0.5f * std::min({cell.x, cell.y, cell.z});
    return h * h;
  }
};

// Every slice of the volume's newest copy (or `name`), as [z][part·n + x, y] texels.
std::vector<Image> read_volume(Renderer& r, int n, const std::string& name = "light_volume") {
  std::vector<Image> slices;
  for (int z = 0; z < n; ++z) slices.push_back(r.read_resource(name, uint32_t(z)));
  return slices;
}

glm::vec4 texel(const std::vector<Image>& v, int n, int c, int x, int y, int z) {
  const float* t = v[size_t(z)].pixel(c * n + x, y);
  return {t[0], t[1], t[2], t[3]};
}

// What the input module computes at p with normal nrm (E per channel, before albedo/π), from
// the read-back texels with exact trilinear weights; `spread` gets each channel's largest
// minus smallest corner value of E(nrm), the scale of the filter's weight quantization.
Color volume_irradiance(const std::vector<Image>& v, const Grid& g, vec3 p, vec3 nrm,
                        Color* spread) {
  const float n = float(g.n);
  const vec3 t = glm::clamp((p - g.lo) / g.extent * n, vec3(0.5f), vec3(n - 0.5f)) - 0.5f;
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(t)), glm::ivec3(g.n - 2));
  const vec3 f = t - vec3(i0);
  Color e(0.0f), lo(1e30f), hi(-1e30f);
  for (int c = 0; c < 3; ++c) {
    glm::vec4 sum(0.0f);
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 at = i0 + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
      const float w =
          (k & 1 ? f.x : 1.0f - f.x) * (k & 2 ? f.y : 1.0f - f.y) * (k & 4 ? f.z : 1.0f - f.z);
      const glm::vec4 tx = texel(v, g.n, c, at.x, at.y, at.z);
      sum += w * tx;
      const float corner = tx.x + glm::dot(vec3(tx.y, tx.z, tx.w), nrm);
      lo[c] = std::min(lo[c], corner);
      hi[c] = std::max(hi[c], corner);
    }
    e[c] = std::max(sum.x + glm::dot(vec3(sum.y, sum.z, sum.w), nrm), 0.0f);
  }
  if (spread) *spread = hi - lo;
  return e;
}

RenderSettings settings(const std::string& pipeline, bool on, int cells = 8) {
  RenderSettings o;
  o.width = o.height = kSize;
  o.pipeline = pipeline;
  o.shadows = "none";
  o.set("lighting.ambient", Color(0.05f, 0.04f, 0.03f));
  if (on) {
    o.enable("light_volume");
    o.set("light_volume.cells", cells);
  }
  return o;
}

// 1. Each texel is the closed form at its cell centre. Tolerance: fp16 rounding of the
// stored value, 2⁻¹⁰·|value|, plus 1e-5·Σ|Φ| at the cell for float arithmetic (a few dozen
// operations of relative error 2⁻²⁴ on terms of that size), plus 6e-8 (fp16's spacing
// below its smallest normal).
TEST_F(LightVolumeTest, TexelsAreTheClosedFormAtTheCellCentres) {
  const Scene scene = floor_and_wall();
  Grid g;
  g.n = 16;
  Renderer r(context(), scene, settings("forward", true, g.n));
  r.render(*scene.camera);
  const std::vector<Image> v = read_volume(r, g.n);
  ASSERT_EQ(v[0].width(), 3 * g.n);
  ASSERT_EQ(v[0].height(), g.n);
  float worst = 0.0f, largest = 0.0f;
  int culled = 0;
  for (int z = 0; z < g.n; ++z)
    for (int y = 0; y < g.n; ++y)
      for (int x = 0; x < g.n; ++x) {
        float sum_phi = 0.0f, spot_phi = 0.0f;
        const Linear want = closed_form(scene.lights, g.centre(x, y, z), g.min_d2(), &sum_phi);
        closed_form({scene.lights[1]}, g.centre(x, y, z), g.min_d2(), &spot_phi);
        if (spot_phi == 0.0f) ++culled;  // outside the spot's cone or radius
        for (int c = 0; c < 3; ++c)
          for (int k = 0; k < 4; ++k) {
            const float got = texel(v, g.n, c, x, y, z)[k], w = want.c[size_t(c)][k];
            const float tol = kUlp * std::abs(w) + 1e-5f * sum_phi + 6e-8f;
            largest = std::max(largest, std::abs(w));
            worst = std::max(worst, std::abs(got - w) / tol);
            if (std::abs(got - w) > tol)
              ADD_FAILURE() << "cell " << x << "," << y << "," << z << " part " << c << "[" << k
                            << "]: gpu " << got << ", closed form " << w;
          }
      }
  EXPECT_GT(largest, 1.0f) << "the lights should reach values well above fp16's precision";
  EXPECT_GT(culled, 0) << "some cells should lie outside the spot";
  std::printf("16³ cells: worst |gpu − closed form| = %.3f of its tolerance\n", worst);
}

// 2. With the example on, each pixel of the floor and the wall is the frame without it plus
// albedo · (E(n)/π × strength − ambient): its indirect term replaces the ambient constant in
// forward, deferred and visibility alike. E is the input module's lookup repeated on the
// CPU from the read-back volume at the point a camera ray finds (test 1 checks the volume).
// Tolerance per channel: fp16 rounding of both HDR frames, 2⁻¹⁰·(|with| + |without|); the
// filter's weight quantization, 3 · 2^−subTexelPrecisionBits of the corners' spread of E; the
// change of E when the point moves by 1/128 of the pixel's footprint (the rasterizer's vertex
// snapping, with margin); 1e-5 of the value for float arithmetic.
TEST_F(LightVolumeTest, FrameIsTheFrameWithoutItPlusItsIndirectTermInEveryPipeline) {
  const Scene scene = floor_and_wall();
  Grid g;
  g.n = 8;
  const float strength = 0.7f;
  const Color ambient(0.05f, 0.04f, 0.03f);
  const Color albedo = scene.materials[0].albedo;
  const float quantum =
      3.0f * std::ldexp(1.0f, -static_cast<int>(context().limits().subTexelPrecisionBits));
  const float footprint = 2.0f * std::tan(0.5f * scene.camera->fov_y) / float(kSize);
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    Renderer off(context(), scene, settings(pipeline, false));
    off.render(*scene.camera);
    const Image without = off.hdr();
    RenderSettings o = settings(pipeline, true, g.n);
    o.set("light_volume.strength", strength);
    Renderer on(context(), scene, o);
    on.render(*scene.camera);
    const Image with = on.hdr();
    const std::vector<Image> v = read_volume(on, g.n);
    int compared = 0, failed = 0;
    float mean = 0.0f;
    for (int y = 1; y < kSize - 1; y += 2)
      for (int x = 1; x < kSize - 1; x += 2) {
        // The nearest of the two planes, away from their edges (pixel coverage there is the
        // rasterizer's, not the ray's).
        const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, kSize, kSize);
        float t = 1e30f;
        vec3 nrm(0.0f);
        const float tf = -ray.origin.y / ray.direction.y;
        const vec3 pf = ray.origin + tf * ray.direction;
        if (tf > 0.0f && pf.x > 0.03f && pf.x < 0.97f && pf.z > 0.03f && pf.z < 0.97f) {
          t = tf;
          nrm = vec3(0, 1, 0);
        }
        const float tw = -ray.origin.z / ray.direction.z;
        const vec3 pw = ray.origin + tw * ray.direction;
        if (tw > 0.0f && tw < t && pw.x > 0.03f && pw.x < 0.97f && pw.y > 0.03f && pw.y < 0.97f) {
          t = tw;
          nrm = vec3(0, 0, 1);
        }
        if (t >= 1e30f) continue;
        const vec3 p = ray.origin + t * ray.direction;
        Color spread;
        const Color e = volume_irradiance(v, g, p, nrm, &spread);
        const float delta = t * footprint / 128.0f;
        Color moved(0.0f);
        for (int axis = 0; axis < 3; ++axis)
          for (float sign : {-1.0f, 1.0f}) {
            vec3 q = p;
            q[axis] += sign * delta;
            const Color eq = volume_irradiance(v, g, q, nrm, nullptr);
            for (int c = 0; c < 3; ++c) moved[c] = std::max(moved[c], std::abs(eq[c] - e[c]));
          }
        ++compared;
        for (int c = 0; c < 3; ++c) {
          const float want = albedo[c] * (e[c] / kPi * strength - ambient[c]);
          const float a = with.rgb(x, y)[c], b = without.rgb(x, y)[c];
          const float tol = kUlp * (std::abs(a) + std::abs(b)) +
                            albedo[c] * strength / kPi * (quantum * spread[c] + moved[c]) +
                            1e-5f * std::abs(a);
          mean += std::abs(want);
          if (std::abs((a - b) - want) > tol && ++failed <= 5)
            ADD_FAILURE() << pipeline << " pixel " << x << "," << y << " channel " << c
                          << ": with − without = " << a - b << ", indirect term " << want
                          << " (tolerance " << tol << ")";
        }
      }
    EXPECT_GT(compared, 200) << pipeline;
    mean /= float(3 * std::max(compared, 1));
    EXPECT_GT(mean, 0.01f) << pipeline << ": the term should be far above the tolerance";
    std::printf("%s: %d pixels, mean |indirect − ambient| %.4f, %d off\n", pipeline.c_str(),
                compared, mean, failed);
  }
}

// The closed form of every cell, for the history tests.
std::vector<Linear> target(const std::vector<Light>& lights, const Grid& g) {
  std::vector<Linear> out;
  for (int z = 0; z < g.n; ++z)
    for (int y = 0; y < g.n; ++y)
      for (int x = 0; x < g.n; ++x)
        out.push_back(closed_form(lights, g.centre(x, y, z), g.min_d2(), nullptr));
  return out;
}

// |volume − (new + (1 − b)^k (old − new))| over every texel, as a fraction of `tol`, and the
// largest |old − new|.
float blend_error(const std::vector<Image>& v, const Grid& g, const std::vector<Linear>& before,
                  const std::vector<Linear>& after, float keep, float tol, float* moved) {
  float worst = 0.0f;
  size_t i = 0;
  for (int z = 0; z < g.n; ++z)
    for (int y = 0; y < g.n; ++y)
      for (int x = 0; x < g.n; ++x, ++i)
        for (int c = 0; c < 3; ++c) {
          const glm::vec4 o = before[i].c[size_t(c)], w = after[i].c[size_t(c)];
          const glm::vec4 want = w + keep * (o - w);
          const glm::vec4 got = texel(v, g.n, c, x, y, z);
          for (int k = 0; k < 4; ++k) {
            worst = std::max(worst, std::abs(got[k] - want[k]) / tol);
            if (moved) *moved = std::max(*moved, std::abs(o[k] - w[k]));
          }
        }
  return worst;
}

float largest_value(const std::vector<Linear>& a) {
  float m = 0.0f;
  for (const Linear& l : a)
    for (const glm::vec4& c : l.c)
      m = std::max({m, std::abs(c.x), std::abs(c.y), std::abs(c.z), std::abs(c.w)});
  return m;
}

bool ran(const Renderer& r, const std::string& pass) {
  for (const gpu::PassTime& t : r.pass_times())
    if (t.depth == 0 && t.name == pass) return true;
  return false;
}

Scene moved_light(const Scene& scene) {
  Scene s = scene;
  s.lights[0].position = vec3(0.8f, 0.3f, 0.25f);
  return s;
}

// 3a. After the point light moves, frame k holds new + (1 − b)^k (old − new) in every texel.
// Tolerance: each update rounds to fp16 (2⁻¹⁰ of the largest value) and the blend shrinks
// earlier roundings by (1 − b) each, so they sum to at most 2⁻¹⁰·largest/b; plus 1e-5 of the
// largest value for float arithmetic.
TEST_F(LightVolumeTest, AfterALightMovesTheVolumeConvergesGeometrically) {
  const Scene scene = floor_and_wall();
  const Scene next = moved_light(scene);
  Grid g;
  g.n = 8;
  const float b = 0.3f;
  RenderSettings o = settings("forward", true, g.n);
  o.set("light_volume.blend", b);
  Renderer r(context(), scene, o);
  r.render(*scene.camera);  // the first update has no previous copy: the closed form itself
  const std::vector<Linear> before = target(scene.lights, g), after = target(next.lights, g);
  const float largest = std::max(largest_value(before), largest_value(after));
  const float tol = kUlp * largest / b + 1e-5f * largest;
  float moved = 0.0f;
  EXPECT_LT(blend_error(read_volume(r, g.n), g, before, after, 1.0f, tol, &moved), 1.0f);
  ASSERT_GT(moved, 50.0f * tol) << "the move should change the volume far beyond the tolerance";
  r.update_lights(realtime_lights(next));
  for (int k = 1; k <= 8; ++k) {
    r.render(*scene.camera);
    const float keep = std::pow(1.0f - b, float(k));
    const float e = blend_error(read_volume(r, g.n), g, before, after, keep, tol, nullptr);
    EXPECT_LT(e, 1.0f) << "frame " << k << " after the move: expected (1 − b)^" << k << " = "
                       << keep << " of the old value left";
    std::printf("frame %d: (1 − b)^k = %.4f, worst error %.3f of the tolerance\n", k, keep, e);
  }
}

// 3b. Updated every 3 frames, the copies alternate at each update; every frame in between
// reads the newest one: the volume the graph names "light_volume" holds new + (1 − b)^j
// (old − new) after j updates, and the frame's pixels are the ones that copy gives (the
// lookup of test 2 on it), not the other copy's.
TEST_F(LightVolumeTest, EveryNFramesReadersSeeTheNewestCopy) {
  const Scene scene = floor_and_wall();
  const Scene next = moved_light(scene);
  Grid g;
  g.n = 8;
  const float b = 0.5f;
  RenderSettings o = settings("forward", true, g.n);
  o.set("light_volume.blend", b);
  o.set("light_volume.period", 3);
  Renderer r(context(), scene, o);
  Renderer off(context(), next, settings("forward", false));
  off.render(*scene.camera);
  const Image without = off.hdr();
  r.render(*scene.camera);
  ASSERT_TRUE(ran(r, "light_volume"));
  const std::vector<Linear> before = target(scene.lights, g), after = target(next.lights, g);
  const float largest = std::max(largest_value(before), largest_value(after));
  const float tol = kUlp * largest / b + 1e-5f * largest;
  r.update_lights(realtime_lights(next));
  const Color ambient(0.05f, 0.04f, 0.03f);
  const Color albedo = scene.materials[0].albedo;
  const float quantum =
      3.0f * std::ldexp(1.0f, -static_cast<int>(context().limits().subTexelPrecisionBits));
  int updates = 0, skipped = 0;
  for (int frame = 1; frame <= 9; ++frame) {
    r.render(*scene.camera);
    if (ran(r, "light_volume"))
      ++updates;
    else
      ++skipped;
    const float keep = std::pow(1.0f - b, float(updates));
    const std::vector<Image> v = read_volume(r, g.n);
    EXPECT_LT(blend_error(v, g, before, after, keep, tol, nullptr), 1.0f)
        << "frame " << frame << ", " << updates << " updates";
    // One floor pixel below the moved light, where the two copies differ most.
    const Image hdr = r.hdr();
    int off_pixels = 0;
    for (int y = kSize / 2; y < kSize - 2; y += 3)
      for (int x = 2; x < kSize - 2; x += 3) {
        const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, kSize, kSize);
        const float t = -ray.origin.y / ray.direction.y;
        const vec3 p = ray.origin + t * ray.direction;
        if (!(t > 0.0f) || p.x < 0.03f || p.x > 0.97f || p.z < 0.03f || p.z > 0.97f) continue;
        Color spread;
        const Color e = volume_irradiance(v, g, p, vec3(0, 1, 0), &spread);
        for (int c = 0; c < 3; ++c) {
          const float want = albedo[c] * (e[c] / kPi - ambient[c]);
          const float a = hdr.rgb(x, y)[c], w0 = without.rgb(x, y)[c];
          const float tol_px = kUlp * (std::abs(a) + std::abs(w0)) +
                               albedo[c] / kPi * (quantum * spread[c] + 1e-3f * e[c]) +
                               1e-5f * std::abs(a);
          if (std::abs((a - w0) - want) > tol_px) ++off_pixels;
        }
      }
    EXPECT_EQ(off_pixels, 0) << "frame " << frame << ": pixels not lit by the newest copy";
  }
  EXPECT_GE(updates, 3);
  EXPECT_GE(skipped, 5) << "the schedule should leave frames without an update";
  std::printf("9 frames: %d updates, %d frames reading a copy written earlier\n", updates, skipped);
}

}  // namespace
}  // namespace illum::realtime
