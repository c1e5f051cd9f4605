// Reconciliation of coplanar neighbours (bake/lightmap_coplanar.h, S002 §3.3.6 second step):
// a T-junction — one large floor quad beside two smaller ones — stitched by the path and
// radiosity bakers and in PRT transfer; folds, opposite faces, overlaps and gaps as wide as
// a thin wall never joined.
//
// ILLUM_SEAMS_IMAGES=DIR writes the figures of docs/lightmaps.md (Seams and leaks) there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "bake_test_scenes.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/lightmap_coplanar.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/core/image.h"
#include "illum/trace/ray_tracer.h"
#include "seam_figures.h"

namespace illum {
namespace {

constexpr int kAtlas = 64;  // atlas texels on a side

// The parallelogram origin, origin + u, origin + u + v, origin + v (two triangles, facing
// cross(u, v)), flat normals unless `normal_at` bends them, tangent along u, and uv1 the
// corners' (s, t) ∈ [0, 1]² mapped into the atlas rectangle [lo, hi] given in texels.
Mesh quad(const vec3& origin, const vec3& u, const vec3& v, const vec2& lo, const vec2& hi,
          int material, const std::function<vec3(const vec3&)>& normal_at = {}) {
  Mesh m;
  m.name = "quad";
  const vec3 face = glm::normalize(glm::cross(u, v));
  const vec2 corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const vec2& st : corner) {
    const vec3 p = origin + st.x * u + st.y * v;
    m.positions.push_back(p);
    m.normals.push_back(normal_at ? normal_at(p) : face);
    m.tangents.emplace_back(glm::normalize(u), 1.0f);
    m.uv1.push_back((lo + st * (hi - lo)) / float(kAtlas));
  }
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

// The T-junction floor (y = 0, facing +y): A = [−1, 0] × [−½, ½] (x, z), 24 texels on a
// side (h_A = 1/24 m), B1 = [0, ½] × [−½, 0] and B2 = [0, ½] × [0, ½], 15 texels on a side
// (h_B = 1/30 m), three instances (identity transforms), each chart at a fractional texel offset
// so no two grids line up. A's edge x = 0 meets B1's and B2's halves of it: a T-junction
// (B1 and B2 share their own edge z = 0: an ordinary seam). 4+ texels of gutter around every
// chart for dilation.
constexpr float kTexelA = 1.0f / 24.0f;
Scene t_junction(const std::function<vec3(const vec3&)>& normal_at = {}) {
  Scene scene;
  scene.name = "t-junction";
  const int mat = test::add_lambert(scene, Color(0.5f));
  const vec3 u(1, 0, 0), v(0, 0, -1);  // cross(u, v) = +y
  test::add_instance(scene,
                     quad({-1, 0, 0.5f}, u, v, {4.3f, 4.3f}, {28.3f, 28.3f}, mat, normal_at));
  test::add_instance(
      scene, quad({0, 0, 0}, 0.5f * u, 0.5f * v, {36.6f, 4.7f}, {51.6f, 19.7f}, mat, normal_at));
  test::add_instance(scene, quad({0, 0, 0.5f}, 0.5f * u, 0.5f * v, {36.2f, 30.4f}, {51.2f, 45.4f},
                                 mat, normal_at));
  return scene;
}

// Where world point p (on the quad's plane) lands in the atlas, in texels: the quad's own
// bilinear uv1 map (exact for a parallelogram split in two triangles with these corners).
vec2 uv_at(const Mesh& quad, const vec3& p) {
  const vec3 o = quad.positions[0], u = quad.positions[1] - o, v = quad.positions[3] - o;
  const float s = glm::dot(p - o, u) / glm::dot(u, u), t = glm::dot(p - o, v) / glm::dot(v, v);
  return glm::mix(glm::mix(quad.uv1[0], quad.uv1[1], s), glm::mix(quad.uv1[3], quad.uv1[2], s), t) *
         float(kAtlas);
}

// Sample pairs along the T-edge x = 0, made here from the geometry (not by find_seams): A's
// uv and B1's or B2's at 90 points, 3 per texel of the finer side.
std::vector<bake::SeamSample> t_edge_samples(const Scene& scene) {
  std::vector<bake::SeamSample> samples;
  constexpr int kPoints = 90;
  for (int k = 0; k < kPoints; ++k) {
    const vec3 p(0.0f, 0.0f, -0.5f + (float(k) + 0.5f) / float(kPoints));
    const Mesh& b = scene.meshes[p.z < 0.0f ? 1 : 2];
    samples.push_back({{uv_at(scene.meshes[0], p), uv_at(b, p)}});
  }
  return samples;
}

// The bound. A side's lookup on its chart's edge blends its border texels with gutter texels
// that dilation filled with copies of them, so it reads the light about half a texel inside
// its chart: unreconciled, the two sides of the T-edge differ by up to about
// g·(h_A + h_B)/2, g the light's gradient there. Reconciled, they must differ by less than
// g·h/10 (h = the coarser texel, h_A): less than the change the light itself makes over a
// tenth of a texel, a step the eye cannot tell from the gradient the floor shows anyway.
// g is measured on the baked map itself (whose texels here are exact: direct light, one
// deterministic estimate each, or PRT's closed form): the largest difference between
// horizontally or vertically adjacent covered texels of one chart within 2 texels of the
// T-edge, over the distance between their sample points. A floor of 1e-6 of the largest
// value keeps float rounding (the maps are f32) from failing a channel without gradient.
double seam_bound(const atlas::TexelRaster& raster, const Image& map, int channel) {
  double gradient = 0.0, largest = 0.0;
  for (const atlas::TexelSample& s : raster.samples) {
    largest = std::max(largest, double(std::abs(map.pixel(s.x, s.y)[channel])));
    if (std::abs(s.position.x) > 2.0f * kTexelA) continue;
    for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(0, 1)}) {
      if (s.x + d.x >= raster.width || s.y + d.y >= raster.height) continue;
      const int32_t j = raster.at(s.x + d.x, s.y + d.y);
      if (j < 0 || raster.samples[size_t(j)].instance != s.instance) continue;
      const atlas::TexelSample& n = raster.samples[size_t(j)];
      gradient = std::max(
          gradient, double(std::abs(map.pixel(n.x, n.y)[channel] - map.pixel(s.x, s.y)[channel])) /
                        double(glm::length(n.position - s.position)));
    }
  }
  return std::max(gradient * kTexelA / 10.0, 1e-6 * largest);
}

// The largest difference of one channel of the two sides' bilinear lookups over `samples`.
double largest_step(const std::vector<bake::SeamSample>& samples, const Image& map, int channel) {
  double step = 0.0;
  for (const bake::SeamSample& s : samples)
    step = std::max(step, double(std::abs(bake::bilinear_lookup(map, s.side[0])[channel] -
                                          bake::bilinear_lookup(map, s.side[1])[channel])));
  return step;
}

// The floor around the T point (0, 0, 0), x, z ∈ [−¼, ¼], seen from above: each pixel the
// renderer's bilinear lookup of `map` at that floor point's uv1, minus the exact E/π of the
// point light there, × 20 / `brightest` (as the sphere's figure): steps show as lines.
Image t_view(const Scene& scene, const Image& map, const Light& light, float brightest, int size) {
  Image out(size, size, 3);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const float x = -0.25f + 0.5f * (float(i) + 0.5f) / float(size);
      const float z = -0.25f + 0.5f * (float(j) + 0.5f) / float(size);
      for (const Mesh& m : scene.meshes) {  // axis-aligned quads, identity transforms
        const vec3 lo = glm::min(m.positions[0], m.positions[2]);
        const vec3 hi = glm::max(m.positions[0], m.positions[2]);
        if (x < lo.x || x > hi.x || z < lo.z || z > hi.z) continue;
        const Color shown = bake::bilinear_lookup(map, uv_at(m, vec3(x, 0.0f, z)));
        const vec3 to_light = light.position - vec3(x, 0.0f, z);
        const float d2 = glm::dot(to_light, to_light);
        const Color exact = light.intensity * (to_light.y / std::sqrt(d2) / (kPi * d2));
        out.set_rgb(i, j, glm::abs(shown - exact) * (20.0f / brightest));
        break;
      }
    }
  return out;
}

// The T-junction under a point light off the T-edge's side (a gradient across it and along
// it), direct light only: every texel exact. With stitching but coplanar neighbours off (the
// code before this step), the step along the T-edge must exceed the bound, else the scene
// tests nothing; with them on, every sample must be under it. Both light-map bakers.
TEST(LightmapCoplanar, TJunctionIsStitched) {
  Scene scene = t_junction();
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(-0.3f, 0.5f, 0.15f);
  light.intensity = Color(1.0f);
  scene.lights.push_back(light);
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, kAtlas, kAtlas);

  const bake::Seams seams = bake::find_seams(scene, kAtlas, kAtlas);
  EXPECT_EQ(seams.edges, 1);           // B1–B2, same end points
  EXPECT_EQ(seams.coplanar_pairs, 2);  // A's long edge with B1's and with B2's
  // find_seams' own samples for the pairs: 3 per texel of the finer side, 15 per half.
  const bake::Seams same_ends = bake::find_seams(scene, kAtlas, kAtlas, {.coplanar = false});
  EXPECT_EQ(seams.samples.size() - same_ends.samples.size(),
            2u * 15u * size_t(bake::kSeamSamplesPerTexel));
  const std::vector<bake::SeamSample> t_edge = t_edge_samples(scene);

  for (const bool radiosity : {false, true}) {
    const auto bake = [&](bool coplanar) {
      if (radiosity) {
        bake::RadiosityBakeOptions o;
        o.stitch = true;
        o.stitch_coplanar = coplanar;
        o.progress = false;
        return bake::bake_radiosity(scene, tracer, raster, o).layers[0];
      }
      bake::LightmapBakeOptions o;
      o.spp = 1;
      o.max_bounces = 0;
      o.stitch = true;
      o.stitch_coplanar = coplanar;
      o.progress = false;
      return bake::bake_lightmap(scene, tracer, raster, o).layers[0];
    };
    const Image before = bake(false), after = bake(true);
    const double bound = seam_bound(raster, before, 0);
    const double step_before = largest_step(t_edge, before, 0);
    const double step_after = largest_step(t_edge, after, 0);
    std::printf(
        "%s: T-edge step %.5f before, %.5f after reconciliation; bound g*h/10 = %.5f "
        "(g = %.4f per m)\n",
        radiosity ? "radiosity" : "path", step_before, step_after, bound, bound * 10.0 / kTexelA);
    EXPECT_GT(step_before, bound) << "no visible T-junction seam before: nothing tested";
    EXPECT_LT(step_after, bound);
    if (!radiosity) {
      float brightest = 0.0f;
      for (const atlas::TexelSample& s : raster.samples)
        brightest = std::max(brightest, before.pixel(s.x, s.y)[0]);
      test::write_seam_figure("seam_tjunction_before.png",
                              t_view(scene, before, light, brightest, 320));
      test::write_seam_figure("seam_tjunction_after.png",
                              t_view(scene, after, light, brightest, 320));
    }
  }
}

// PRT transfer is stitched per coefficient with the same system. Unshadowed transfer on a
// plane is T_i = (Λ_l/π) Y_i(n), the same for every texel of a flat floor, so the floor's
// shading normals are bent, n ∝ (0.6 x, 1, 0.6 z) at the vertices, giving every
// coefficient but the constant one a gradient across and along the T-edge; the values are
// the closed form (no rays), exact per texel. Every coefficient's step along the T-edge is
// under its bound after; some coefficient's above it before.
TEST(LightmapCoplanar, PrtTransferIsStitchedPerCoefficient) {
  const Scene scene =
      t_junction([](const vec3& p) { return glm::normalize(vec3(0.6f * p.x, 1.0f, 0.6f * p.z)); });
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, kAtlas, kAtlas);
  const std::vector<bake::SeamSample> t_edge = t_edge_samples(scene);
  bake::PrtBakeOptions o;
  o.bands = 3;
  o.mode = bake::PrtMode::kUnshadowed;
  o.vertices = false;
  o.stitch = true;
  o.progress = false;
  const auto coefficients = [&](bool coplanar) {
    o.stitch_coplanar = coplanar;
    const bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, o);
    EXPECT_EQ(baked.coplanar_edges, coplanar ? 2 : 0);
    std::vector<Image> maps;
    for (int i = 0; i < baked.texel_transfer.channels / 3; ++i) {
      Image map(raster.width, raster.height, 3);
      for (int y = 0; y < raster.height; ++y)
        for (int x = 0; x < raster.width; ++x)
          std::copy_n(baked.texel_transfer.pixel(x, y) + 3 * i, 3, map.pixel(x, y));
      maps.push_back(std::move(map));
    }
    return maps;
  };
  const std::vector<Image> before = coefficients(false), after = coefficients(true);
  double worst_before = 0.0, worst_after = 0.0;  // step / bound
  for (size_t i = 0; i < before.size(); ++i) {
    const double bound = seam_bound(raster, before[i], 0);
    const double b = largest_step(t_edge, before[i], 0), a = largest_step(t_edge, after[i], 0);
    std::printf("coefficient %zu: T-edge step %.6f before, %.6f after; bound %.6f\n", i, b, a,
                bound);
    worst_before = std::max(worst_before, b / bound);
    worst_after = std::max(worst_after, a / bound);
  }
  EXPECT_GT(worst_before, 1.0) << "no coefficient shows the T-junction: nothing tested";
  EXPECT_LT(worst_after, 1.0);
}

// Neighbours that must never be joined, each a second quad beside A's edge x = 0 (B1's
// place) in the atlas spot of B1: a fold of 90° (a wall standing on the edge) and of 5°
// (shading normals within kSeamNormalCos, so only the plane test refuses it), the same
// plane facing the other way, a quad overlapping A on A's side of the line, and one across
// a gap of 1.25 texels (a 5 cm wall between two floors at 4 cm texels). And the two that
// must: a gap of a hundredth of a texel, and the T-junction itself.
TEST(LightmapCoplanar, OnlyCoplanarNeighboursFacingAlikeAreJoined) {
  const auto pairs_with = [](const vec3& origin, const vec3& u, const vec3& v) {
    Scene scene;
    const int mat = test::add_lambert(scene, Color(0.5f));
    test::add_instance(
        scene, quad({-1, 0, 0.5f}, {1, 0, 0}, {0, 0, -1}, {4.3f, 4.3f}, {28.3f, 28.3f}, mat));
    test::add_instance(scene, quad(origin, u, v, {36.6f, 4.7f}, {51.6f, 19.7f}, mat));
    return bake::find_seams(scene, kAtlas, kAtlas).coplanar_pairs;
  };
  const vec3 flat_u(0.5f, 0, 0), v(0, 0, -0.5f);
  const float fold = glm::radians(5.0f);
  EXPECT_EQ(pairs_with({0, 0, 0}, flat_u, v), 1) << "the T-junction's half";
  EXPECT_EQ(pairs_with({0.01f * kTexelA, 0, 0}, flat_u, v), 1) << "a hair's gap";
  EXPECT_EQ(pairs_with({0, 0, 0}, {0, 0.5f, 0}, v), 0) << "a wall standing on the edge";
  EXPECT_EQ(pairs_with({0, 0, 0}, 0.5f * vec3(std::cos(fold), std::sin(fold), 0), v), 0)
      << "a 5 degree fold";
  EXPECT_EQ(pairs_with({0, 0, -0.5f}, flat_u, -v), 0) << "facing the other way";
  EXPECT_EQ(pairs_with({-0.5f, 0, 0}, flat_u, v), 0) << "overlapping A on its side";
  EXPECT_EQ(pairs_with({1.25f * kTexelA, 0, 0}, flat_u, v), 0) << "across a thin wall's gap";
}

}  // namespace
}  // namespace illum
