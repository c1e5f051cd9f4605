// The conservative texel raster (atlas/texel_raster.h) against independent geometry:
// coverage equals an exact triangle/square overlap test (separating axes), the texel's
// triangle is the one holding its centre or else the largest overlap (areas by clipping
// the square against the triangle, the opposite of what the raster does), sample points
// are the nearest points of that triangle, world-space frames follow the instance
// transform and the shaders' tangent rule, and dilate() fills exactly one ring per pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bake_test_scenes.h"
#include "illum/atlas/texel_raster.h"
#include "illum/core/error.h"
#include "illum/core/rng.h"

namespace illum {
namespace {

using atlas::TexelRaster;
using atlas::TexelSample;

struct Tri {
  glm::dvec2 p[3];  // texel units
};

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Separating axis test: does the triangle overlap the open square (x, x+1) × (y, y+1)
// with positive area? Touching along an edge or at a corner is not overlap.
bool overlaps(const Tri& t, int x, int y) {
  const glm::dvec2 sq[4] = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}};
  auto separated = [&](const glm::dvec2& axis) {
    double tmin = 1e300, tmax = -1e300, smin = 1e300, smax = -1e300;
    for (const auto& p : t.p) {
      tmin = std::min(tmin, glm::dot(p, axis));
      tmax = std::max(tmax, glm::dot(p, axis));
    }
    for (const auto& p : sq) {
      smin = std::min(smin, glm::dot(p, axis));
      smax = std::max(smax, glm::dot(p, axis));
    }
    return tmax <= smin || smax <= tmin;
  };
  if (separated({1, 0}) || separated({0, 1})) return false;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec2 e = t.p[(i + 1) % 3] - t.p[i];
    if (separated({-e.y, e.x})) return false;
  }
  return true;
}

// Area of triangle ∩ square, clipping the square by the triangle's three half-planes.
double overlap_area(const Tri& t, int x, int y) {
  std::vector<glm::dvec2> poly = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}};
  const double orient = cross2(t.p[1] - t.p[0], t.p[2] - t.p[0]) > 0 ? 1.0 : -1.0;
  for (int i = 0; i < 3 && !poly.empty(); ++i) {
    const glm::dvec2 a = t.p[i], e = t.p[(i + 1) % 3] - t.p[i];
    auto side = [&](const glm::dvec2& q) { return orient * cross2(e, q - a); };
    std::vector<glm::dvec2> out;
    for (size_t k = 0; k < poly.size(); ++k) {
      const glm::dvec2 p = poly[k], q = poly[(k + 1) % poly.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    poly.swap(out);
  }
  double a2 = 0;
  for (size_t k = 0; k < poly.size(); ++k) a2 += cross2(poly[k], poly[(k + 1) % poly.size()]);
  return 0.5 * std::abs(a2);
}

bool contains(const Tri& t, const glm::dvec2& c) {
  const double d0 = cross2(t.p[1] - t.p[0], c - t.p[0]);
  const double d1 = cross2(t.p[2] - t.p[1], c - t.p[1]);
  const double d2 = cross2(t.p[0] - t.p[2], c - t.p[2]);
  return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

// Brute-force distance from c to the triangle (dense points on the edges + containment):
// never below the true distance, at most half a step above it.
double distance_to(const Tri& t, const glm::dvec2& c) {
  if (contains(t, c)) return 0.0;
  double best = 1e300;
  const int n = 2000;  // step ≤ longest edge (≤ 20 texels here) / 2000 = 0.01
  for (int e = 0; e < 3; ++e) {
    for (int k = 0; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      best = std::min(best, glm::length(t.p[e] + s * (t.p[(e + 1) % 3] - t.p[e]) - c));
    }
  }
  return best;
}

glm::dvec2 sample_uv(const Tri& t, const TexelSample& s) {
  const double b1 = s.barycentric.x, b2 = s.barycentric.y;
  return (1.0 - b1 - b2) * t.p[0] + b1 * t.p[1] + b2 * t.p[2];
}

TEST(TexelRaster, CoverageIsExactlyTheOverlappingTexels) {
  // Random triangles of every size (sub-texel slivers to a third of the map), overlapping
  // each other, on a non-square map so width and height cannot be swapped unnoticed.
  const int width = 37, height = 23, count = 120;
  Rng rng(7);
  Scene scene;
  Mesh mesh;
  mesh.name = "random";
  std::vector<Tri> tris;
  for (int i = 0; i < count; ++i) {
    const float scale = i % 3 == 0 ? 0.03f : (i % 3 == 1 ? 0.12f : 0.35f);
    const vec2 c(rng.next_float(), rng.next_float());
    Tri t;
    for (int k = 0; k < 3; ++k) {
      vec2 uv = c + scale * vec2(rng.next_float() - 0.5f, rng.next_float() - 0.5f);
      uv = glm::clamp(uv, vec2(0.0f), vec2(1.0f));
      mesh.positions.push_back(vec3(uv.x, uv.y, 0.1f * static_cast<float>(i)));
      mesh.uv1.push_back(uv);
      mesh.indices.push_back(static_cast<uint32_t>(mesh.indices.size()));
      t.p[k] = glm::dvec2(static_cast<double>(uv.x) * width, static_cast<double>(uv.y) * height);
    }
    tris.push_back(t);
  }
  test::add_instance(scene, mesh);
  const TexelRaster raster = atlas::rasterize_texels(scene, width, height);
  ASSERT_EQ(raster.width, width);
  ASSERT_EQ(raster.height, height);
  ASSERT_EQ(raster.sample_of.size(), static_cast<size_t>(width * height));

  int covered = 0, outside_centres = 0;
  int64_t previous = -1;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      int first_containing = -1;
      double best_area = 0.0;
      bool any = false;
      const glm::dvec2 centre(x + 0.5, y + 0.5);
      for (int i = 0; i < count; ++i) {
        if (!overlaps(tris[i], x, y)) continue;
        any = true;
        if (first_containing < 0 && contains(tris[i], centre)) first_containing = i;
        best_area = std::max(best_area, overlap_area(tris[i], x, y));
      }
      const int32_t index = raster.at(x, y);
      ASSERT_EQ(index >= 0, any) << "texel " << x << "," << y;
      if (!any) continue;
      ++covered;
      // Row-major order.
      const int64_t linear = static_cast<int64_t>(y) * width + x;
      EXPECT_GT(linear, previous);
      previous = linear;
      const TexelSample& s = raster.samples[static_cast<size_t>(index)];
      ASSERT_EQ(s.x, x);
      ASSERT_EQ(s.y, y);
      ASSERT_EQ(s.instance, 0);
      ASSERT_GE(s.triangle, 0);
      ASSERT_LT(s.triangle, count);
      const Tri& chosen = tris[static_cast<size_t>(s.triangle)];
      EXPECT_TRUE(overlaps(chosen, x, y));
      EXPECT_GE(s.barycentric.x, -1e-6f);
      EXPECT_GE(s.barycentric.y, -1e-6f);
      EXPECT_LE(s.barycentric.x + s.barycentric.y, 1.0f + 1e-6f);
      const glm::dvec2 uv = sample_uv(chosen, s);
      if (first_containing >= 0) {
        // The first triangle (in mesh order) holding the centre, sampled at the centre.
        EXPECT_TRUE(s.centre_inside);
        EXPECT_EQ(s.triangle, first_containing) << "texel " << x << "," << y;
        EXPECT_NEAR(uv.x, centre.x, 1e-4);
        EXPECT_NEAR(uv.y, centre.y, 1e-4);
      } else {
        ++outside_centres;
        // The largest overlap (up to float rounding of the stored area), sampled at its
        // nearest point to the centre (brute-force distance, within half a step = 0.005).
        EXPECT_FALSE(s.centre_inside);
        EXPECT_GE(overlap_area(chosen, x, y), best_area * (1.0 - 1e-5))
            << "texel " << x << "," << y;
        const double d = glm::length(uv - centre);
        EXPECT_LE(d, distance_to(chosen, centre) + 1e-6);
        EXPECT_GE(d, distance_to(chosen, centre) - 0.005);
      }
      // World position = object position at the barycentrics (identity transform here).
      EXPECT_NEAR(s.position.x, uv.x / width, 1e-5);
      EXPECT_NEAR(s.position.y, uv.y / height, 1e-5);
    }
  }
  EXPECT_EQ(static_cast<size_t>(covered), raster.covered());
  EXPECT_GT(outside_centres, 20);  // the border rule was exercised
}

TEST(TexelRaster, GrazingTriangleCoversTheTexelsItTouches) {
  // A thin sliver between texel centres: an ordinary (centre-sampling) raster would cover
  // nothing; the conservative one covers every texel the sliver passes through.
  Scene scene;
  Mesh m;
  m.name = "sliver";
  const float w = 8.0f;
  m.uv1 = {{0.6f / w, 2.1f / w}, {7.4f / w, 2.3f / w}, {7.4f / w, 2.35f / w}};
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0.01f, 0}};
  m.indices = {0, 1, 2};
  test::add_instance(scene, m);
  const TexelRaster raster = atlas::rasterize_texels(scene, 8, 8);
  EXPECT_EQ(raster.covered(), 8u);  // x = 0..7 of row 2
  for (int x = 0; x < 8; ++x) {
    ASSERT_GE(raster.at(x, 2), 0) << x;
    EXPECT_FALSE(raster.samples[static_cast<size_t>(raster.at(x, 2))].centre_inside);
  }
}

TEST(TexelRaster, WorldFramesFollowTheInstanceTransform) {
  // A slanted-normal quad under rotation + non-uniform scale (normals need the inverse
  // transpose) and a mirrored copy (negative determinant: the winding flips).
  Scene scene;
  Mesh m;
  m.name = "quad";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals = {glm::normalize(vec3(0.3f, 0, 1)), glm::normalize(vec3(0.3f, 0.2f, 1)),
               glm::normalize(vec3(-0.2f, 0.1f, 1)), vec3(0, 0, 1)};
  m.tangents = {vec4(1, 0.1f, 0, 1), vec4(1, 0, 0.2f, 1), vec4(1, -0.1f, 0, 1), vec4(1, 0, 0, 1)};
  m.uv1 = {{0.0f, 0.0f}, {0.5f, 0.0f}, {0.5f, 1.0f}, {0.0f, 1.0f}};
  m.indices = {0, 1, 2, 0, 2, 3};
  Mesh mirrored = m;
  mirrored.name = "mirrored";
  for (auto& t : mirrored.tangents) t.w = -1.0f;
  for (auto& uv : mirrored.uv1) uv.x += 0.5f;
  const mat4 a = glm::scale(glm::rotate(glm::translate(mat4(1.0f), vec3(2, 1, -3)), 0.7f,
                                        glm::normalize(vec3(1, 2, 0.5f))),
                            vec3(3.0f, 0.5f, 1.5f));
  const mat4 b = glm::scale(glm::translate(mat4(1.0f), vec3(0, 5, 0)), vec3(-2.0f, 1.0f, 1.0f));
  test::add_instance(scene, m, a);
  test::add_instance(scene, mirrored, b);
  const TexelRaster raster = atlas::rasterize_texels(scene, 16, 8);
  ASSERT_EQ(raster.covered(), 16u * 8u);
  int mirrored_count = 0;
  for (const TexelSample& s : raster.samples) {
    const Instance& inst = scene.instances[static_cast<size_t>(s.instance)];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(s.triangle)];
    const float b1 = s.barycentric.x, b2 = s.barycentric.y, b0 = 1 - b1 - b2;
    auto lerp3 = [&](const std::vector<vec3>& v) {
      return b0 * v[idx[0]] + b1 * v[idx[1]] + b2 * v[idx[2]];
    };
    const vec3 p = vec3(inst.transform * vec4(lerp3(mesh.positions), 1.0f));
    EXPECT_NEAR(glm::distance(p, s.position), 0.0f, 1e-5f);
    const mat3 linear(inst.transform);
    const vec3 w0 = vec3(inst.transform * vec4(mesh.positions[idx[0]], 1.0f));
    const vec3 w1 = vec3(inst.transform * vec4(mesh.positions[idx[1]], 1.0f));
    const vec3 w2 = vec3(inst.transform * vec4(mesh.positions[idx[2]], 1.0f));
    const vec3 ng = glm::normalize(glm::cross(w1 - w0, w2 - w0));
    EXPECT_NEAR(glm::distance(ng, s.geometric_normal), 0.0f, 1e-5f);
    vec3 n = glm::normalize(glm::transpose(glm::inverse(linear)) * lerp3(mesh.normals));
    if (glm::dot(n, ng) < 0) n = -n;
    EXPECT_NEAR(glm::distance(n, s.normal), 0.0f, 1e-5f);
    EXPECT_GT(glm::dot(s.normal, s.geometric_normal), 0.0f);
    // lighting.glsl load_surface: t = normalize(T − n (n·T)), T = model · tangent.xyz.
    const vec4 t4 =
        b0 * mesh.tangents[idx[0]] + b1 * mesh.tangents[idx[1]] + b2 * mesh.tangents[idx[2]];
    const vec3 tw = linear * vec3(t4);
    const vec3 t = glm::normalize(tw - n * glm::dot(n, tw));
    EXPECT_NEAR(glm::distance(t, s.tangent), 0.0f, 1e-5f);
    EXPECT_EQ(s.tangent_sign, t4.w < 0 ? -1.0f : 1.0f);
    if (s.instance == 1) ++mirrored_count;
  }
  EXPECT_EQ(mirrored_count, 8 * 8);
  // The naive normal transform differs for this transform: the check above has teeth.
  const vec3 naive = glm::normalize(mat3(a) * m.normals[0]);
  const vec3 right = glm::normalize(glm::transpose(glm::inverse(mat3(a))) * m.normals[0]);
  EXPECT_GT(glm::distance(naive, right), 0.05f);
}

TEST(TexelRaster, FrameWithoutTangentsIsOrthonormal) {
  Scene scene;
  Mesh m = test::uv_plane(1.0f, 0);
  m.tangents.clear();
  m.normals.assign(4, glm::normalize(vec3(0.2f, 1.0f, -0.1f)));
  test::add_instance(scene, m);
  const TexelRaster raster = atlas::rasterize_texels(scene, 4, 4);
  ASSERT_EQ(raster.covered(), 16u);
  for (const TexelSample& s : raster.samples) {
    EXPECT_NEAR(glm::length(s.tangent), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(s.tangent, s.normal), 0.0f, 1e-5f);
    EXPECT_EQ(s.tangent_sign, 1.0f);
    EXPECT_NEAR(glm::distance(s.normal, glm::normalize(vec3(0.2f, 1.0f, -0.1f))), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(s.geometric_normal, vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_TRUE(s.centre_inside);
  }
}

TEST(TexelRaster, MeshesWithoutUv1AreSkipped) {
  Scene scene;
  Mesh lit = test::uv_plane(1.0f, 0, vec4(1, 0, 0, 1), vec2(0.0f), vec2(0.5f));
  Mesh unlit = test::uv_plane(1.0f, 0);
  unlit.uv1.clear();
  test::add_instance(scene, unlit);
  test::add_instance(scene, lit);
  const TexelRaster raster = atlas::rasterize_texels(scene, 8, 8);
  EXPECT_EQ(raster.covered(), 16u);
  for (const TexelSample& s : raster.samples) EXPECT_EQ(s.instance, 1);
}

TEST(TexelRaster, BadInputThrows) {
  Scene scene;
  test::add_instance(scene, test::uv_plane(1.0f, 0));
  EXPECT_THROW(atlas::rasterize_texels(scene, 0, 8), Error);
  EXPECT_THROW(atlas::rasterize_texels(scene, 8, -1), Error);
  EXPECT_THROW(atlas::rasterize_texels(scene, 8, 100000), Error);
  EXPECT_NO_THROW(atlas::rasterize_texels(scene, 8, 8));

  Scene outside = scene;
  outside.meshes[0].uv1[1].x = 1.01f;
  EXPECT_THROW(atlas::rasterize_texels(outside, 8, 8), Error);
  outside.meshes[0].uv1[1].x = -0.001f;
  EXPECT_THROW(atlas::rasterize_texels(outside, 8, 8), Error);
  // Rounding past the border (a float ulp near 1) is accepted.
  outside.meshes[0].uv1[1].x = std::nextafter(1.0f, 2.0f);
  EXPECT_NO_THROW(atlas::rasterize_texels(outside, 8, 8));
  outside.meshes[0].uv1[1].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(atlas::rasterize_texels(outside, 8, 8), Error);

  Scene short_uv = scene;
  short_uv.meshes[0].uv1.pop_back();
  EXPECT_THROW(atlas::rasterize_texels(short_uv, 8, 8), Error);

  Scene bad_index = scene;
  bad_index.meshes[0].indices[4] = 9;
  EXPECT_THROW(atlas::rasterize_texels(bad_index, 8, 8), Error);

  // Two instances of one light-mapped mesh would write the same texels.
  Scene shared = scene;
  shared.instances.push_back(shared.instances[0]);
  EXPECT_THROW(atlas::rasterize_texels(shared, 8, 8), Error);

  try {
    atlas::rasterize_texels(outside, 8, 8);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plane"), std::string::npos) << e.what();
  }
}

// texel_overlap_area (the raster's largest-overlap rule and the bakers' texel areas) against
// the opposite clipping above: the square clipped by the triangle's half-planes.
TEST(TexelRaster, OverlapAreaAgreesWithClippingTheSquare) {
  const glm::dvec2 whole[3] = {{-1, -1}, {4, -1}, {-1, 4}};  // contains the square at (0, 0)
  EXPECT_DOUBLE_EQ(atlas::texel_overlap_area(whole, 0, 0), 1.0);
  EXPECT_EQ(atlas::texel_overlap_area(whole, 5, 5), 0.0);
  const glm::dvec2 half[3] = {{2, 3}, {3, 3}, {2, 4}};  // half of the square at (2, 3)
  EXPECT_DOUBLE_EQ(atlas::texel_overlap_area(half, 2, 3), 0.5);
  EXPECT_EQ(atlas::texel_overlap_area(half, 3, 3), 0.0);  // touches along an edge only
  Rng rng(11);
  for (int i = 0; i < 2000; ++i) {
    Tri t;
    for (glm::dvec2& p : t.p) p = glm::dvec2(6.0 * rng.next_float(), 6.0 * rng.next_float());
    const glm::dvec2 reversed[3] = {t.p[2], t.p[1], t.p[0]};
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x) {
        const double expected = overlap_area(t, x, y);
        EXPECT_NEAR(atlas::texel_overlap_area(t.p, x, y), expected, 1e-9);
        EXPECT_NEAR(atlas::texel_overlap_area(reversed, x, y), expected, 1e-9);
      }
  }
}

// check_texel_raster (every baker's input check) accepts a raster of its scene and refuses
// a malformed one, samples outside it and samples of triangles the scene does not have.
TEST(TexelRaster, CheckRefusesRastersOfAnotherScene) {
  Scene scene;
  test::add_instance(scene, test::uv_plane(1.0f, 0));
  const TexelRaster raster = atlas::rasterize_texels(scene, 8, 8);
  ASSERT_GT(raster.covered(), 0u);
  EXPECT_NO_THROW(atlas::check_texel_raster(scene, raster, "test"));
  const auto refused = [&](const TexelRaster& r, const char* what) {
    try {
      atlas::check_texel_raster(scene, r, "test");
      ADD_FAILURE() << what << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("test: ", 0), 0u) << e.what();
    }
  };
  TexelRaster r = raster;
  r.sample_of.pop_back();
  refused(r, "short sample_of");
  r = raster;
  r.width = 0;
  refused(r, "zero width");
  r = raster;
  r.samples[0].x = 8;
  refused(r, "sample outside");
  r = raster;
  r.samples[0].instance = 1;
  refused(r, "unknown instance");
  r = raster;
  r.samples[0].triangle = 2;
  refused(r, "unknown triangle");
}

TEST(TexelRaster, DilateFillsOneRingPerIteration) {
  // A 2×2-texel square in the middle of an 8×8 map (uv on texel borders, exact binary
  // fractions); covered texels hold distinct values.
  Scene scene;
  test::add_instance(scene, test::uv_plane(1.0f, 0, vec4(1, 0, 0, 1), vec2(0.375f), vec2(0.625f)));
  const TexelRaster raster = atlas::rasterize_texels(scene, 8, 8);
  ASSERT_EQ(raster.covered(), 4u);
  Image image(8, 8, 3, 0.0f);
  for (const TexelSample& s : raster.samples)
    image.set_rgb(s.x, s.y, Color(static_cast<float>(s.x + 10 * s.y), 1.0f, -2.0f));
  const Image original = image;

  auto covered = [&](int x, int y) { return raster.at(x, y) >= 0; };
  Image once = image;
  atlas::dilate(once, raster, 1);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      Color sum(0.0f);
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx || dy) && nx >= 0 && nx < 8 && ny >= 0 && ny < 8 && covered(nx, ny)) {
            sum += original.rgb(nx, ny);
            ++n;
          }
        }
      const Color expected =
          covered(x, y) ? original.rgb(x, y) : (n > 0 ? sum / static_cast<float>(n) : Color(0.0f));
      EXPECT_NEAR(glm::distance(once.rgb(x, y), expected), 0.0f, 1e-5f) << x << "," << y;
    }
  }
  // Two passes reach two rings (the 6×6 block around the 2×2 square), nothing beyond.
  Image twice = image;
  atlas::dilate(twice, raster, 2);
  int filled = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) filled += twice.rgb(x, y).g != 0.0f ? 1 : 0;
  EXPECT_EQ(filled, 36);
  // The second ring reads the first ring's values: (1,1)-offset corner of the block.
  EXPECT_NEAR(twice.rgb(1, 1).r, once.rgb(2, 2).r, 1e-5f);

  Image zero = image;
  atlas::dilate(zero, raster, 0);
  EXPECT_EQ(zero.data(), original.data());
  Image wrong(9, 8, 3);
  EXPECT_THROW(atlas::dilate(wrong, raster, 1), Error);
  EXPECT_THROW(atlas::dilate(image, raster, -1), Error);
}

}  // namespace
}  // namespace illum
