// Seams and leaks (bake/lightmap_seams.h): texel samples pushed out of geometry (two rooms
// and a 5 cm wall, the floor continuous under it).
//
// ILLUM_SEAMS_IMAGES=DIR writes the figures of docs/lightmaps.md (Seams and leaks) there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "../render/render_test_scenes.h"
#include "bake_test_scenes.h"
#include "charted_cornell.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/core/image.h"
#include "illum/trace/ray_tracer.h"
#include "seam_figures.h"

namespace illum {
namespace {

using test::add_material;
using test::add_triangles;
using test::inward_box;

constexpr float kHalfWall = 0.025f;  // the wall is 5 cm thick, centred on x = 0
constexpr float kTexel = 0.042f;     // world size of a texel on every (planar) chart

// Two rooms [−1, 0] and [0, 1] (x) × [0, 1] × [−0.5, 0.5]; the room box is one mesh, so its
// floor, ceiling and side walls run on under the closed 5 cm wall between the rooms. A
// point light in the room at x > 0. Charted at 4.2 cm per texel: the floor and ceiling get
// an even number (48) of texels across, symmetric about x = 0, so texel centres fall at
// ±2.1 cm, inside the wall (checked below, so an atlas change cannot quietly lose them).
struct TwoRooms {
  TwoRooms() {
    scene.name = "two-rooms";
    Material m;
    m.albedo = Color(0.5f);
    const int mat = add_material(scene, m);
    room = add_triangles(scene, inward_box(vec3(-1.0f, 0.0f, -0.5f), vec3(1.0f, 1.0f, 0.5f)), mat,
                         "room");
    add_triangles(scene,
                  inward_box(vec3(-kHalfWall, 0.0f, -0.5f), vec3(kHalfWall, 1.0f, 0.5f), false),
                  mat, "wall");
    Light light;
    light.type = LightType::kPoint;
    light.position = vec3(0.5f, 0.7f, 0.1f);
    light.intensity = Color(1.0f);
    scene.lights.push_back(light);
    const atlas::Atlas a = atlas::chart_scene(scene, {.resolution = 128, .texel_size = kTexel});
    tracer = std::make_unique<RayTracer>(scene);
    raster = atlas::rasterize_texels(scene, a.width, a.height);
  }
  Scene scene;
  int room = 0;
  std::unique_ptr<RayTracer> tracer;
  atlas::TexelRaster raster;
};

bake::LightmapBakeOptions path_options() {
  bake::LightmapBakeOptions o;
  o.spp = 16;
  o.max_bounces = 2;  // the leak needs one bounce (off the wall's inner faces)
  o.progress = false;
  return o;
}

// Texels whose centre (the raster's own sample point, before any push-out) lies in the
// dark half x < 0: the dark room and the dark half of the wall's footprint.
std::vector<uint8_t> dark_half(const atlas::TexelRaster& raster) {
  std::vector<uint8_t> dark(raster.sample_of.size(), 0);
  for (const atlas::TexelSample& s : raster.samples)
    dark[size_t(s.y) * size_t(raster.width) + size_t(s.x)] = s.position.x < 0.0f ? 1 : 0;
  return dark;
}

double max_over(const Image& image, const std::vector<uint8_t>& mask) {
  double m = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (mask[size_t(y) * size_t(image.width()) + size_t(x)])
        m = std::max(m, double(max_component(image.rgb(x, y))));
  return m;
}

// The floor's light-map seen from above, x ∈ [−0.4, 0.4] (wall in the middle), z ∈ [−½, ½],
// each pixel a bilinear lookup at the floor point's uv1 (what the renderer shows), scaled
// up for the figure.
Image floor_view(const Scene& scene, int room, const Image& map) {
  const Instance& inst = scene.instances[size_t(room)];
  const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
  const int w = 320, h = 400;
  Image out(w, h, 3);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float x = -0.4f + 0.8f * (float(i) + 0.5f) / float(w);
      const float z = -0.5f + (float(j) + 0.5f) / float(h);
      for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const vec3& a = mesh.positions[mesh.indices[3 * t]];
        const vec3& b = mesh.positions[mesh.indices[3 * t + 1]];
        const vec3& c = mesh.positions[mesh.indices[3 * t + 2]];
        if (a.y != 0.0f || b.y != 0.0f || c.y != 0.0f) continue;
        const float det = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
        const float b1 = ((x - a.x) * (c.z - a.z) - (c.x - a.x) * (z - a.z)) / det;
        const float b2 = ((b.x - a.x) * (z - a.z) - (x - a.x) * (b.z - a.z)) / det;
        if (b1 < 0.0f || b2 < 0.0f || b1 + b2 > 1.0f) continue;
        const vec2 uv = (1.0f - b1 - b2) * mesh.uv1[mesh.indices[3 * t]] +
                        b1 * mesh.uv1[mesh.indices[3 * t + 1]] +
                        b2 * mesh.uv1[mesh.indices[3 * t + 2]];
        out.set_rgb(i, j, map.sample_bilinear(uv.x, uv.y));
        break;
      }
    }
  return out;
}

// The dark room has no light path to the light: the wall is closed and reaches floor and
// ceiling, every shadow ray from the dark room is blocked, and no emitter is there. So its
// true light-map is exactly 0 and every estimate of a texel whose sample point lies in it
// is a sum of exact zeros, whatever the spp: the bound is 0, for every texel whose centre
// lies in the dark half x < 0 (the dark room and the dark half of the wall's footprint).
// Materials are two-sided opaque, so the inside of the closed wall is black: samples left
// under the wall do not leak light into the dark room here, they leak *shadow* into the
// lit room (a black texel row along the lit side of the wall, a "dark seam").
// The push-out must fix that — every lit-half texel centred under the wall reads > 0 after
// (the point light is in plain view of the wall's foot, so each sample's next-event
// estimate is positive) and exactly 0 before — without pushing dark-half samples to the
// lit side, which the dark-room bound catches.
TEST(LightmapSeams, NoLightLeaksThroughAThinWall) {
  TwoRooms rooms;
  const atlas::TexelRaster& before = rooms.raster;
  int under_wall_dark = 0, under_wall_lit = 0;
  std::vector<uint8_t> lit_under_wall(before.sample_of.size(), 0);
  for (const atlas::TexelSample& s : before.samples) {
    if (s.instance != rooms.room || std::abs(s.position.x) >= kHalfWall) continue;
    (s.position.x < 0.0f ? under_wall_dark : under_wall_lit)++;
    // The floor's texels on the lit half (the ceiling's are lit only by bounces).
    if (s.position.x > 0.0f && s.position.y == 0.0f)
      lit_under_wall[size_t(s.y) * size_t(before.width) + size_t(s.x)] = 1;
  }
  ASSERT_GT(under_wall_dark, 0) << "no texel centre under the wall: the scene tests nothing";
  ASSERT_GT(under_wall_lit, 0);
  const std::vector<uint8_t> dark = dark_half(before);

  atlas::TexelRaster after = before;
  const bake::TexelPushOut pushed =
      bake::keep_texels_out_of_geometry(rooms.scene, *rooms.tracer, after);
  std::printf(
      "texel centres under the wall: %d dark half, %d lit half; moved %lld, rejected %lld\n",
      under_wall_dark, under_wall_lit, static_cast<long long>(pushed.moved),
      static_cast<long long>(pushed.rejected));
  EXPECT_GE(pushed.moved, under_wall_dark + under_wall_lit);
  // No sample is left strictly inside the wall, and every moved one stays on its plane,
  // within its texel (the push is at most h + 0.01 h).
  for (size_t i = 0; i < after.samples.size(); ++i) {
    const atlas::TexelSample& s = after.samples[i];
    if (s.instance == rooms.room) {
      EXPECT_FALSE(std::abs(s.position.x) < kHalfWall)
          << "texel (" << s.x << ", " << s.y << ") still at x = " << s.position.x;
    }
    const int32_t j = before.at(s.x, s.y);
    ASSERT_GE(j, 0);
    const vec3 d = s.position - before.samples[size_t(j)].position;
    EXPECT_LE(glm::length(d), 1.01f * kTexel * 1.0001f);
    EXPECT_NEAR(glm::dot(d, s.geometric_normal), 0.0f, 1e-5f);
  }

  const bake::LightmapBake unfixed =
      bake::bake_lightmap(rooms.scene, *rooms.tracer, before, path_options());
  const bake::LightmapBake fixed =
      bake::bake_lightmap(rooms.scene, *rooms.tracer, after, path_options());
  const double dark_before = max_over(unfixed.layers[0], dark);
  const double dark_after = max_over(fixed.layers[0], dark);
  double seam_before = 0.0, seam_after = kInf;
  for (int y = 0; y < before.height; ++y)
    for (int x = 0; x < before.width; ++x) {
      if (!lit_under_wall[size_t(y) * size_t(before.width) + size_t(x)]) continue;
      seam_before = std::max(seam_before, double(max_component(unfixed.layers[0].rgb(x, y))));
      seam_after = std::min(seam_after, double(max_component(fixed.layers[0].rgb(x, y))));
    }
  std::printf(
      "path: dark half max E/pi %.5f before, %.5f after; lit floor texels centred under "
      "the wall: max %.5f before, min %.5f after\n",
      dark_before, dark_after, seam_before, seam_after);
  EXPECT_EQ(dark_after, 0.0);
  EXPECT_EQ(seam_before, 0.0) << "the unfixed raster must show the dark seam";
  EXPECT_GT(seam_after, 0.0);

  // The radiosity baker reads the same raster: the same bound (every form factor from a
  // dark patch to a lit one is blocked, direct light by its shadow ray).
  bake::RadiosityBakeOptions ro;
  ro.threshold = 0.05;
  ro.progress = false;
  const bake::RadiosityBake radiosity = bake::bake_radiosity(rooms.scene, *rooms.tracer, after, ro);
  const double radiosity_dark = max_over(radiosity.layers[0], dark);
  std::printf("radiosity: dark half max E/pi %.5f with push-out\n", radiosity_dark);
  EXPECT_EQ(radiosity_dark, 0.0);

  test::write_seam_figure("leak_floor_before.png",
                          floor_view(rooms.scene, rooms.room, unfixed.layers[0]));
  test::write_seam_figure("leak_floor_after.png",
                          floor_view(rooms.scene, rooms.room, fixed.layers[0]));
}

// A 2 m square plane at y = 0 facing +y with one default material (its index in *material).
Scene open_plane(int* material) {
  Scene scene;
  *material = add_material(scene, Material{});
  std::vector<vec3> tris;
  test::push_quad(tris, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
  add_triangles(scene, tris, *material, "plane");
  return scene;
}

// A sample on an open plane, nothing near: never moved, nothing rejected.
TEST(LightmapSeams, LeavesFreeSamplesAlone) {
  int mat = 0;
  Scene scene = open_plane(&mat);
  test::ChartedScene c(std::move(scene), 32);
  atlas::TexelRaster& raster = c.raster;
  const atlas::TexelRaster before = raster;
  const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(c.scene, *c.tracer, raster);
  EXPECT_EQ(pushed.moved, 0);
  EXPECT_EQ(pushed.rejected, 0);
  ASSERT_EQ(raster.samples.size(), before.samples.size());
  for (size_t i = 0; i < raster.samples.size(); ++i)
    EXPECT_EQ(raster.samples[i].position, before.samples[i].position);
}

// A texel sample inside a closed tiny box, smaller than a texel in every direction: it
// cannot be pushed out (past one face it is still behind another) and is rejected, the
// texel left to dilation.
TEST(LightmapSeams, RejectsSamplesWithNoFreePosition) {
  int mat = 0;
  Scene scene = open_plane(&mat);
  // A shell around the plane's centre, 2 mm high and 1 cm wide: closed on all sides, so
  // the sample at its centre sees back faces everywhere in its plane; a second shell
  // around it keeps the first push inside geometry.
  add_triangles(scene,
                inward_box(vec3(-0.005f, -0.001f, -0.005f), vec3(0.005f, 0.001f, 0.005f), false),
                mat, "inner");
  add_triangles(scene, inward_box(vec3(-0.02f, -0.001f, -0.02f), vec3(0.02f, 0.001f, 0.02f), false),
                mat, "outer");
  test::ChartedScene c(std::move(scene), atlas::AtlasOptions{.resolution = 64, .texel_size = 0.1f});
  atlas::TexelRaster& raster = c.raster;
  const size_t covered = raster.covered();
  const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(c.scene, *c.tracer, raster);
  EXPECT_GT(pushed.rejected, 0);
  EXPECT_EQ(raster.covered(), covered - size_t(pushed.rejected));
  for (size_t i = 0; i < raster.samples.size(); ++i)
    EXPECT_EQ(raster.at(raster.samples[i].x, raster.samples[i].y), int32_t(i));
}

// An outward UV sphere with shared vertices and smooth normals (the normal is the
// direction from the centre), so the atlas's chart boundaries are the only seams.
Mesh smooth_sphere(float radius, int rings, int segments, int material) {
  Mesh m;
  m.name = "sphere";
  m.material = material;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j <= segments; ++j) {
      const float theta = kPi * float(i) / float(rings),
                  phi = 2.0f * kPi * float(j) / float(segments);
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      m.positions.push_back(radius * n);
      m.normals.push_back(n);
    }
  // The seam column j = segments repeats j = 0 at the same positions: joined by index so
  // the sphere is closed (the poles likewise collapse to one vertex each).
  const auto index = [&](int i, int j) {
    if (i == 0) return uint32_t(0);
    if (i == rings) return uint32_t(rings * (segments + 1));
    return uint32_t(i * (segments + 1) + (j % segments));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1),
                     d = index(i, j + 1);
      if (i != 0) m.indices.insert(m.indices.end(), {a, d, b});
      if (i != rings - 1) m.indices.insert(m.indices.end(), {d, c, b});
    }
  return m;
}

// Seam mismatch: per seam sample, the two sides' bilinear lookups of the map (luminance),
// relative to the larger; samples darker than 5% of the brightest are left out (a relative
// step means nothing near black, and the light's terminator is there).
struct Mismatch {
  double max_relative = 0.0;
  size_t counted = 0;
};
Mismatch seam_mismatch(const bake::Seams& seams, const Image& map) {
  std::vector<std::pair<double, double>> sides;
  double brightest = 0.0;
  for (const bake::SeamSample& s : seams.samples) {
    const double a = luminance(bake::bilinear_lookup(map, s.side[0]));
    const double b = luminance(bake::bilinear_lookup(map, s.side[1]));
    sides.emplace_back(a, b);
    brightest = std::max({brightest, a, b});
  }
  Mismatch m;
  for (const auto& [a, b] : sides) {
    if (std::max(a, b) < 0.05 * brightest) continue;
    ++m.counted;
    const double rel = std::abs(a - b) / std::max(a, b);
    m.max_relative = std::max(m.max_relative, rel);
  }
  return m;
}

// The figure: the sphere seen from `eye` towards its centre, each pixel the error of the
// bilinear lookup of `map` at the hit point's uv1 (what the renderer shows, before albedo)
// against the exact E/π of `light` there, |error| × 20 / `brightest`: seams show as lines.
Image sphere_view(const test::ChartedScene& c, const Image& map, const Light& light,
                  float brightest, const vec3& eye, int size) {
  Image out(size, size, 3);
  const Frame frame = Frame::from_normal(glm::normalize(-eye));
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const float u = 2.0f * (float(i) + 0.5f) / float(size) - 1.0f;
      const float v = 1.0f - 2.0f * (float(j) + 0.5f) / float(size);
      const vec3 dir = glm::normalize(frame.n + 0.3f * (u * frame.t + v * frame.b));
      Ray ray{eye, dir};
      Hit hit;
      if (!c.tracer->intersect(ray, &hit)) continue;
      const Mesh& mesh = c.scene.meshes[size_t(c.scene.instances[hit.instance].mesh)];
      const uint32_t* idx = &mesh.indices[3 * size_t(hit.primitive)];
      const vec2 uv = (1.0f - hit.barycentric.x - hit.barycentric.y) * mesh.uv1[idx[0]] +
                      hit.barycentric.x * mesh.uv1[idx[1]] + hit.barycentric.y * mesh.uv1[idx[2]];
      const Color shown =
          bake::bilinear_lookup(map, uv * vec2(float(map.width()), float(map.height())));
      const vec3 p = eye + hit.t * dir, to_light = light.position - p;
      const float cos_theta = std::max(0.0f, glm::dot(glm::normalize(p), glm::normalize(to_light)));
      const Color exact = light.intensity * (cos_theta / (kPi * glm::dot(to_light, to_light)));
      out.set_rgb(i, j, glm::abs(shown - exact) * (20.0f / brightest));
    }
  return out;
}

// Across a seam the two sides show the same surface point, so a visible step there is the
// baker's artefact. The criterion: a step below 1% of the brightness (the Weber fraction of
// brightness discrimination, about 1–2%) cannot be seen. A sphere (smooth normals, charted
// into several charts) under a point light, direct light only: every texel's value is
// exact (one deterministic next-event estimate, no occluder on the lit side), so all of
// the mismatch before stitching comes from the two sides' bilinear lookups over different
// texel grids and dilated gutters — which stitching must bring under 1% on every seam
// sample, while it must have been above it before (else the scene tests nothing).
TEST(LightmapSeams, StitchingJoinsTheChartsOfASmoothSphere) {
  Scene scene;
  Material m;
  m.albedo = Color(0.5f);
  const int mat = add_material(scene, m);
  scene.meshes.push_back(smooth_sphere(0.5f, 24, 48, mat));
  Instance inst;
  inst.name = "sphere";
  scene.instances.push_back(inst);
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(1.0f, 2.0f, 1.5f);
  light.intensity = Color(4.0f);
  scene.lights.push_back(light);
  test::ChartedScene c(std::move(scene), 128);

  const bake::Seams seams = bake::find_seams(c.scene, c.raster.width, c.raster.height);
  std::printf("sphere: %lld seam edges (%lld within the instance), %zu samples\n",
              static_cast<long long>(seams.edges), static_cast<long long>(seams.within_instance),
              seams.samples.size());
  ASSERT_GT(seams.edges, 0) << "the atlas split the sphere into one chart?";
  EXPECT_EQ(seams.within_instance, seams.edges);

  bake::LightmapBakeOptions o;
  o.spp = 1;
  o.max_bounces = 0;
  o.progress = false;
  bake::LightmapBake baked = bake::bake_lightmap(c.scene, *c.tracer, c.raster, o);
  const Mismatch before = seam_mismatch(seams, baked.layers[0]);
  const std::vector<Image> unstitched = baked.layers;
  const bake::SeamStitchStats stats = bake::stitch_seams(seams, c.raster, baked.layers);
  const Mismatch after = seam_mismatch(seams, baked.layers[0]);
  // How far stitching moved any texel, relative to the brightest texel.
  double moved = 0.0, brightest = 0.0;
  for (int y = 0; y < c.raster.height; ++y)
    for (int x = 0; x < c.raster.width; ++x) {
      moved = std::max(moved, double(std::abs(luminance(baked.layers[0].rgb(x, y)) -
                                              luminance(unstitched[0].rgb(x, y)))));
      brightest = std::max(brightest, double(luminance(unstitched[0].rgb(x, y))));
    }
  std::printf(
      "seam step max %.4f before, %.4f after stitching (%zu samples counted); %lld texels, "
      "%d CG iterations, %.3fs; largest texel change %.4f of the brightest\n",
      before.max_relative, after.max_relative, after.counted, static_cast<long long>(stats.texels),
      stats.iterations, stats.seconds, moved / brightest);
  EXPECT_GT(after.counted, 100u);
  EXPECT_GT(before.max_relative, 0.01) << "no visible seam before stitching: nothing tested";
  // Seen from the light's side.
  const vec3 eye = 1.7f * glm::normalize(c.scene.lights[0].position);
  test::write_seam_figure("seam_sphere_before.png", sphere_view(c, unstitched[0], c.scene.lights[0],
                                                                float(brightest), eye, 320));
  test::write_seam_figure(
      "seam_sphere_after.png",
      sphere_view(c, baked.layers[0], c.scene.lights[0], float(brightest), eye, 320));
  EXPECT_LT(after.max_relative, 0.01);

  // The bakers stitch when asked (the CLI's default): the same result.
  o.stitch = true;
  const bake::LightmapBake stitched = bake::bake_lightmap(c.scene, *c.tracer, c.raster, o);
  EXPECT_EQ(stitched.seam_edges, seams.edges);
  EXPECT_LT(seam_mismatch(seams, stitched.layers[0]).max_relative, 0.01);
}

// Two coplanar squares, separate instances with hand-set uv1 in two corners of the atlas,
// sharing an edge under a point light: a seam between objects.
TEST(LightmapSeams, StitchingJoinsTwoObjects) {
  Scene scene;
  const int mat = test::add_lambert(scene, Color(0.5f));
  test::add_instance(scene, test::uv_plane(0.5f, mat, vec4(1, 0, 0, 1), vec2(0.05f), vec2(0.45f)),
                     glm::translate(mat4(1.0f), vec3(-0.5f, 0.0f, 0.0f)));
  test::add_instance(scene, test::uv_plane(0.5f, mat, vec4(1, 0, 0, 1), vec2(0.55f), vec2(0.95f)),
                     glm::translate(mat4(1.0f), vec3(0.5f, 0.0f, 0.0f)));
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(0.1f, 0.6f, 0.2f);
  light.intensity = Color(1.0f);
  scene.lights.push_back(light);
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, 32, 32);
  const bake::Seams seams = bake::find_seams(scene, raster.width, raster.height);
  EXPECT_EQ(seams.edges, 1);
  EXPECT_EQ(seams.within_instance, 0);
  bake::LightmapBakeOptions o;
  o.spp = 1;
  o.max_bounces = 0;
  o.progress = false;
  bake::LightmapBake baked = bake::bake_lightmap(scene, tracer, raster, o);
  const Mismatch before = seam_mismatch(seams, baked.layers[0]);
  bake::stitch_seams(seams, raster, baked.layers);
  const Mismatch after = seam_mismatch(seams, baked.layers[0]);
  std::printf("two squares: seam step max %.4f before, %.4f after\n", before.max_relative,
              after.max_relative);
  EXPECT_GT(before.max_relative, 0.01);
  EXPECT_LT(after.max_relative, 0.01);
}

// Edges that are no seams: a crease (the two faces of a box's corner) and one chart's inner
// edges (same uv1 on both sides).
TEST(LightmapSeams, CreasesAreNoSeams) {
  Scene scene;
  Material m;
  const int mat = add_material(scene, m);
  add_triangles(scene, inward_box(vec3(-1.0f), vec3(1.0f), false), mat, "box");
  Mesh& box = scene.meshes.back();
  for (size_t v = 0; v < box.positions.size(); v += 3)  // flat: each corner its face's normal
    box.normals.insert(box.normals.end(), 3,
                       glm::normalize(glm::cross(box.positions[v + 1] - box.positions[v],
                                                 box.positions[v + 2] - box.positions[v])));
  test::ChartedScene c(std::move(scene), 64);
  EXPECT_EQ(bake::find_seams(c.scene, c.raster.width, c.raster.height).edges, 0);
}

}  // namespace
}  // namespace illum
