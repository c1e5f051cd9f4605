// RayTracer against a brute-force double-precision Möller–Trumbore reference on random
// triangle soups, plus the surface description interaction() builds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include <tbb/parallel_for.h>
#include <glm/gtc/matrix_transform.hpp>

#include "illum/core/error.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

using dvec3 = glm::dvec3;

// Float32 carries ~6e-8 relative error per operation; Embree's intersection takes a few
// dozen operations, so its t and barycentrics agree with a double reference to a few 1e-6
// on well-conditioned hits. kRel leaves a margin of ~10× over that; kEdge is the band of
// barycentric distance to an edge (or t difference for near-ties) inside which float and
// double may legitimately choose differently.
constexpr double kRel = 2e-5;
constexpr double kEdge = 1e-4;
constexpr double kTie = 1e-5;

struct RefHit {
  double t = std::numeric_limits<double>::infinity();
  int instance = -1;
  int primitive = -1;
  double b1 = 0, b2 = 0;
  double min_bary = 0;  // distance (in barycentrics) to the nearest edge
  bool valid() const { return primitive >= 0; }
};

struct WorldTriangle {
  dvec3 a, b, c;
  int instance, primitive;
  bool degenerate;
};

// Möller–Trumbore in double, with a barycentric slack (negative: shrink the triangle).
bool ref_intersect(const WorldTriangle& tri, const dvec3& o, const dvec3& d, double tmin,
                   double tmax, double slack, RefHit* out) {
  if (tri.degenerate) return false;
  const dvec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
  const dvec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0) return false;
  const double inv = 1.0 / det;
  const dvec3 s = o - tri.a;
  const double u = glm::dot(s, p) * inv;
  const dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) * inv;
  if (u < -slack || v < -slack || u + v > 1.0 + slack) return false;
  const double t = glm::dot(e2, q) * inv;
  if (t < tmin || t > tmax) return false;
  out->t = t;
  out->instance = tri.instance;
  out->primitive = tri.primitive;
  out->b1 = u;
  out->b2 = v;
  out->min_bary = std::min({u, v, 1.0 - u - v});
  return true;
}

RefHit ref_closest(const std::vector<WorldTriangle>& tris, const Ray& ray) {
  RefHit best;
  const dvec3 o(ray.origin), d(ray.direction);
  for (const WorldTriangle& tri : tris) {
    RefHit h;
    if (ref_intersect(tri, o, d, ray.tmin, std::min<double>(ray.tmax, best.t), 0.0, &h)) best = h;
  }
  return best;
}

std::vector<WorldTriangle> world_triangles(const Scene& scene) {
  std::vector<WorldTriangle> out;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    const glm::dmat4 m(inst.transform);
    for (size_t f = 0; f < mesh.triangle_count(); ++f) {
      WorldTriangle t;
      dvec3* v[3] = {&t.a, &t.b, &t.c};
      for (int k = 0; k < 3; ++k)
        *v[k] = dvec3(m * glm::dvec4(dvec3(mesh.positions[mesh.indices[3 * f + k]]), 1.0));
      t.instance = static_cast<int>(i);
      t.primitive = static_cast<int>(f);
      t.degenerate = glm::length(glm::cross(t.b - t.a, t.c - t.a)) == 0.0;
      out.push_back(t);
    }
  }
  return out;
}

struct Rng {
  std::mt19937_64 engine;
  explicit Rng(uint64_t seed) : engine(seed) {}
  float uniform(float lo = 0.0f, float hi = 1.0f) {
    // Built from raw bits so the sequence does not depend on the standard library.
    const double u = static_cast<double>(engine() >> 11) * 0x1.0p-53;
    return static_cast<float>(lo + (hi - lo) * u);
  }
  vec3 in_box(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
  vec3 on_sphere() {
    const float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 2.0f * kPi);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
};

// Random triangle soup in [0,1]^3: small triangles around uniform centres.
Mesh random_soup(Rng& rng, int count, float size) {
  Mesh mesh;
  mesh.name = "soup";
  for (int i = 0; i < count; ++i) {
    const vec3 c = rng.in_box(0.0f, 1.0f);
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(c + rng.in_box(-size, size));
      mesh.indices.push_back(static_cast<uint32_t>(mesh.positions.size() - 1));
    }
  }
  return mesh;
}

std::vector<Ray> random_rays(Rng& rng, int count, float lo, float hi) {
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    r.origin = rng.in_box(lo, hi);
    r.direction = rng.on_sphere();
  }
  return rays;
}

Scene single_instance_scene(Mesh mesh) {
  Scene scene;
  scene.name = "test";
  scene.meshes.push_back(std::move(mesh));
  scene.materials.push_back(Material{});
  Instance inst;
  inst.name = "inst0";
  scene.instances.push_back(inst);
  return scene;
}

// Compares one Embree answer with the reference. Returns "" when they agree, else why not.
// `exempt` counts legitimate float/double disagreements (near-edge, near-tie).
std::string compare(const std::vector<WorldTriangle>& tris, const Ray& ray, const RefHit& ref,
                    bool hit_found, const Hit& hit, int* exempt) {
  const dvec3 o(ray.origin), d(ray.direction);
  auto find = [&](uint32_t inst, uint32_t prim) -> const WorldTriangle* {
    for (const WorldTriangle& t : tris)
      if (t.instance == static_cast<int>(inst) && t.primitive == static_cast<int>(prim)) return &t;
    return nullptr;
  };
  if (!ref.valid() && !hit_found) return "";
  if (ref.valid() && !hit_found) {
    if (ref.min_bary < kEdge) return ++*exempt, "";
    return "reference hit, tracer missed";
  }
  const WorldTriangle* tri = find(hit.instance, hit.primitive);
  if (!tri) return "hit an unknown primitive";
  if (tri->degenerate) return "hit a degenerate triangle";
  // What the reference says about the primitive the tracer reported (with edge slack).
  RefHit at;
  if (!ref_intersect(*tri, o, d, ray.tmin, ray.tmax * (1 + kRel), kEdge, &at))
    return "tracer hit a primitive the reference does not hit";
  if (!ref.valid()) return ++*exempt, "";  // edge-grazing hit the reference just missed
  const double scale = std::max(1.0, ref.t);
  if (tri->instance != ref.instance || tri->primitive != ref.primitive) {
    if (std::abs(at.t - ref.t) <= kTie * scale) return ++*exempt, "";
    return "different primitive, not a near-tie";
  }
  if (std::abs(hit.t - ref.t) > kRel * scale) return "t differs";
  if (std::abs(hit.barycentric.x - ref.b1) > kEdge || std::abs(hit.barycentric.y - ref.b2) > kEdge)
    return "barycentrics differ";
  return "";
}

// Exemptions must stay rare: they cover rays within kEdge of an edge, a band whose share of
// random hits is ~ 3·2·kEdge (three edges, both sides); 1% bounds that with a wide margin.
void expect_rare(int exempt, size_t rays) {
  EXPECT_LE(exempt, static_cast<int>(0.01 * rays)) << "too many near-edge/near-tie exemptions";
}

TEST(RayTracer, ClosestHitMatchesBruteForceOnSoup) {
  Rng rng(1);
  const Scene scene = single_instance_scene(random_soup(rng, 500, 0.1f));
  const RayTracer tracer(scene);
  const auto tris = world_triangles(scene);
  const auto rays = random_rays(rng, 10000, -0.2f, 1.2f);
  int exempt = 0, hits = 0, failures = 0;
  for (const Ray& ray : rays) {
    const RefHit ref = ref_closest(tris, ray);
    Hit hit;
    const bool found = tracer.intersect(ray, &hit);
    EXPECT_EQ(found, hit.valid());
    hits += found;
    const std::string why = compare(tris, ray, ref, found, hit, &exempt);
    if (!why.empty() && ++failures <= 5) ADD_FAILURE() << why;
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(hits, 1000);  // the soup is dense enough that the test means something
  expect_rare(exempt, rays.size());
}

TEST(RayTracer, RespectsTminAndTmax) {
  Rng rng(2);
  const Scene scene = single_instance_scene(random_soup(rng, 500, 0.1f));
  const RayTracer tracer(scene);
  const auto tris = world_triangles(scene);
  int exempt = 0, failures = 0, checked = 0;
  for (Ray ray : random_rays(rng, 3000, -0.2f, 1.2f)) {
    const RefHit first = ref_closest(tris, ray);
    if (!first.valid() || first.min_bary < kEdge) continue;
    ++checked;
    // Just short of the first hit: nothing in the segment.
    Ray shorter = ray;
    shorter.tmax = static_cast<float>(first.t * (1.0 - 1e-3));
    Hit hit;
    const bool short_hit = tracer.intersect(shorter, &hit);
    const RefHit ref_short = ref_closest(tris, shorter);
    std::string why = compare(tris, shorter, ref_short, short_hit, hit, &exempt);
    // Just past the first hit: the next one.
    Ray later = ray;
    later.tmin = static_cast<float>(first.t * (1.0 + 1e-3));
    const bool later_hit = tracer.intersect(later, &hit);
    if (why.empty()) why = compare(tris, later, ref_closest(tris, later), later_hit, hit, &exempt);
    if (!why.empty() && ++failures <= 5) ADD_FAILURE() << why;
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(checked, 300);
  expect_rare(exempt, 2 * checked);
}

TEST(RayTracer, OccludedConsistentWithIntersect) {
  Rng rng(3);
  const Scene scene = single_instance_scene(random_soup(rng, 500, 0.1f));
  const RayTracer tracer(scene);
  int blocked = 0, short_blocked = 0;
  for (const Ray& ray : random_rays(rng, 10000, -0.2f, 1.2f)) {
    Hit hit;
    const bool found = tracer.intersect(ray, &hit);
    EXPECT_EQ(tracer.occluded(ray), found);
    blocked += found;
    if (found) {
      // A shadow ray that stops just before the closest hit is unblocked, one that reaches
      // just past it is blocked.
      Ray before = ray, past = ray;
      before.tmax = hit.t * (1.0f - 1e-4f);
      past.tmax = hit.t * (1.0f + 1e-4f);
      short_blocked += tracer.occluded(before);
      EXPECT_TRUE(tracer.occluded(past));
    }
  }
  EXPECT_GT(blocked, 1000);
  EXPECT_EQ(short_blocked, 0);
}

TEST(RayTracer, BatchMatchesSingleRays) {
  Rng rng(4);
  const Scene scene = single_instance_scene(random_soup(rng, 500, 0.1f));
  const RayTracer tracer(scene);
  // Not a multiple of the stream chunk, so the tail path runs too.
  auto rays = random_rays(rng, 1000 + 37, -0.2f, 1.2f);
  for (size_t i = 0; i < rays.size(); i += 7) rays[i].tmax = 0.3f;  // mixed extents
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> blocked(rays.size());
  tracer.intersect(std::span<const Ray>(rays), std::span<Hit>(hits));
  tracer.occluded(std::span<const Ray>(rays), std::span<uint8_t>(blocked));
  int found_count = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    const bool found = tracer.intersect(rays[i], &single);
    found_count += found;
    ASSERT_EQ(hits[i].valid(), found) << "ray " << i;
    EXPECT_EQ(blocked[i] != 0, tracer.occluded(rays[i])) << "ray " << i;
    if (!found) continue;
    EXPECT_EQ(hits[i].instance, single.instance);
    EXPECT_EQ(hits[i].primitive, single.primitive);
    EXPECT_EQ(hits[i].t, single.t);
    EXPECT_EQ(hits[i].barycentric, single.barycentric);
  }
  EXPECT_GT(found_count, 100);
}

TEST(RayTracer, ConcurrentQueriesMatchSequential) {
  Rng rng(8);
  const Scene scene = single_instance_scene(random_soup(rng, 500, 0.1f));
  const RayTracer tracer(scene);
  const auto rays = random_rays(rng, 20000, -0.2f, 1.2f);
  std::vector<Hit> expected(rays.size()), got(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) tracer.intersect(rays[i], &expected[i]);
  std::vector<uint8_t> blocked(rays.size());
  std::vector<vec3> points(rays.size());
  tbb::parallel_for(size_t{0}, rays.size(), [&](size_t i) {
    tracer.intersect(rays[i], &got[i]);
    blocked[i] = tracer.occluded(rays[i]);
    if (got[i].valid()) points[i] = tracer.interaction(rays[i], got[i]).p;
  });
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(got[i].primitive, expected[i].primitive) << i;
    ASSERT_EQ(got[i].t, expected[i].t) << i;
    ASSERT_EQ(blocked[i] != 0, expected[i].valid()) << i;
    if (expected[i].valid()) {
      ASSERT_EQ(points[i], tracer.interaction(rays[i], expected[i]).p);
    }
  }
}

TEST(RayTracer, InstancesWithTransforms) {
  Rng rng(5);
  Scene scene;
  scene.name = "instances";
  scene.meshes.push_back(random_soup(rng, 200, 0.1f));
  scene.materials.push_back(Material{});
  Instance a, b;
  a.name = "rotated";
  a.transform = glm::translate(mat4(1.0f), vec3(0.3f, -0.2f, 0.1f)) *
                glm::rotate(mat4(1.0f), 0.7f, glm::normalize(vec3(1.0f, 2.0f, 0.5f))) *
                glm::scale(mat4(1.0f), vec3(1.3f, 0.8f, 1.1f));
  b.name = "scaled";
  b.transform = glm::translate(mat4(1.0f), vec3(-0.2f, 0.4f, 0.3f)) *
                glm::rotate(mat4(1.0f), -1.9f, vec3(0.0f, 1.0f, 0.0f)) *
                glm::scale(mat4(1.0f), vec3(0.7f, 1.4f, -0.9f));  // mirroring
  scene.instances = {a, b};
  const RayTracer tracer(scene);
  const auto tris = world_triangles(scene);
  int exempt = 0, failures = 0, per_instance[2] = {0, 0};
  const auto rays = random_rays(rng, 10000, -0.6f, 1.6f);
  for (const Ray& ray : rays) {
    Hit hit;
    const bool found = tracer.intersect(ray, &hit);
    if (found && hit.instance < 2) ++per_instance[hit.instance];
    const std::string why = compare(tris, ray, ref_closest(tris, ray), found, hit, &exempt);
    if (!why.empty() && ++failures <= 5) ADD_FAILURE() << why;
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(per_instance[0], 200);
  EXPECT_GT(per_instance[1], 200);
  expect_rare(exempt, rays.size());
  // The tracer's bounds enclose every world-space vertex.
  const Bounds3 bounds = tracer.bounds();
  for (const WorldTriangle& t : tris)
    for (const dvec3& v : {t.a, t.b, t.c})
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(bounds.min[k], v[k] + 1e-6);
        EXPECT_GE(bounds.max[k], v[k] - 1e-6);
      }
}

TEST(RayTracer, DegenerateTrianglesAreNeverHit) {
  Rng rng(6);
  Mesh mesh = random_soup(rng, 300, 0.1f);
  std::vector<uint32_t> degenerate;
  auto add = [&](vec3 a, vec3 b, vec3 c, bool shared) {
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {a, b, c});
    degenerate.push_back(static_cast<uint32_t>(mesh.triangle_count()));
    if (shared)  // zero area through repeated indices rather than repeated positions
      mesh.indices.insert(mesh.indices.end(), {base, base, base + 2});
    else
      mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
  };
  std::vector<vec3> targets;
  for (int i = 0; i < 60; ++i) {
    // Points on a 1/64 grid and steps of 1/16 keep collinear points exactly collinear in
    // float.
    const vec3 a = glm::round(64.0f * rng.in_box(0.1f, 0.9f)) / 64.0f;
    const vec3 step(0.125f, 0.0625f, -0.25f);
    switch (i % 4) {
      case 0:
        add(a, a, a, false);
        break;  // a point
      case 1:
        add(a, a, a + step, false);
        break;  // repeated vertex
      case 2:
        add(a, a + step, a + 2.0f * step, false);
        break;  // collinear
      case 3:
        add(a, a + step, a + 0.5f * step, true);
        break;  // repeated index
    }
    targets.push_back(a);
    targets.push_back(a + 0.5f * step);
  }
  const Scene scene = single_instance_scene(std::move(mesh));
  const RayTracer tracer(scene);
  const auto tris = world_triangles(scene);
  for (uint32_t p : degenerate) ASSERT_TRUE(tris[p].degenerate) << p;
  // Random rays plus rays aimed straight at the degenerate triangles.
  auto rays = random_rays(rng, 5000, -0.2f, 1.2f);
  for (const vec3& target : targets)
    for (int k = 0; k < 20; ++k) {
      Ray r;
      r.origin = rng.in_box(-0.2f, 1.2f);
      r.direction = glm::normalize(target - r.origin);
      rays.push_back(r);
    }
  int exempt = 0, failures = 0;
  for (const Ray& ray : rays) {
    Hit hit;
    const bool found = tracer.intersect(ray, &hit);
    if (found) {
      EXPECT_FALSE(std::binary_search(degenerate.begin(), degenerate.end(), hit.primitive))
          << "hit degenerate primitive " << hit.primitive;
    }
    const std::string why = compare(tris, ray, ref_closest(tris, ray), found, hit, &exempt);
    if (!why.empty() && ++failures <= 5) ADD_FAILURE() << why;
  }
  EXPECT_EQ(failures, 0);
  expect_rare(exempt, rays.size());
}

TEST(RayTracer, EmptySceneMissesEverything) {
  Scene scene;
  scene.name = "empty";
  const RayTracer tracer(scene);
  Ray ray;
  Hit hit;
  EXPECT_FALSE(tracer.intersect(ray, &hit));
  EXPECT_FALSE(hit.valid());
  EXPECT_FALSE(tracer.occluded(ray));
  EXPECT_TRUE(tracer.bounds().empty());
}

TEST(RayTracer, BadMeshThrowsNamingIt) {
  Mesh mesh;
  mesh.name = "broken_mesh";
  mesh.positions = {vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f)};
  mesh.indices = {0, 1, 7};
  const Scene scene = single_instance_scene(mesh);
  try {
    const RayTracer tracer(scene);
    FAIL() << "expected illum::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken_mesh"), std::string::npos) << e.what();
  }
}

TEST(RayTracer, EmbreeDeviceErrorBecomesIllumError) {
  // An Embree configuration it rejects (threads must be a number) makes device creation
  // fail; that must surface as illum::Error naming the setting, not a crash.
  ::setenv("ILLUM_EMBREE_CONFIG", "threads=not-a-number", 1);
  Scene scene;
  scene.name = "config";
  std::string message;
  try {
    const RayTracer tracer(scene);
  } catch (const Error& e) {
    message = e.what();
  }
  ::unsetenv("ILLUM_EMBREE_CONFIG");
  EXPECT_NE(message.find("ILLUM_EMBREE_CONFIG"), std::string::npos) << message;
  EXPECT_NE(message.find("RTC_ERROR"), std::string::npos) << message;
}

// --- interaction() --------------------------------------------------------------------

// An n×n grid on y = 0 over [0,1]², wound counter-clockwise seen from +y, with affine uv
// layouts and smoothly varying vertex normals.
vec2 uv0_of(const vec3& p) {
  return {2.0f * p.x + 0.5f * p.z + 0.1f, -0.3f * p.x + 1.5f * p.z + 0.2f};
}
vec2 uv1_of(const vec3& p) {
  return {0.25f * p.x + 0.5f, 0.75f * p.z - 0.125f};
}
vec3 normal_of(const vec3& p) {
  return glm::normalize(vec3(0.3f * (p.x - 0.5f), 1.0f, 0.2f * p.z));
}

Mesh grid_mesh(int n) {
  Mesh mesh;
  mesh.name = "grid";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const vec3 p(static_cast<float>(i) / n, 0.0f, static_cast<float>(j) / n);
      mesh.positions.push_back(p);
      mesh.normals.push_back(normal_of(p));
      mesh.uv0.push_back(uv0_of(p));
      mesh.uv1.push_back(uv1_of(p));
    }
  auto id = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // (x, z) → (x+1, z) → (x, z+1) turns from +x to +z: counter-clockwise seen from −y
      // under a right-handed frame, so list them the other way round for +y.
      mesh.indices.insert(mesh.indices.end(), {id(i, j), id(i, j + 1), id(i + 1, j)});
      mesh.indices.insert(mesh.indices.end(), {id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  return mesh;
}

void expect_unit(const vec3& v, const char* what) {
  EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f) << what;
}

// How high the mirror direction of wo about shading normal n leaves the geometric
// surface (on wo's side), and the least rise the tracer guarantees: min(0.9·cos θg, 0.01).
float reflection_rise(const vec3& n, const vec3& ng, const vec3& wo) {
  const vec3 g = glm::dot(wo, ng) < 0.0f ? -ng : ng;
  return glm::dot(g, 2.0f * glm::dot(n, wo) * n - wo);
}
float reflection_threshold(const vec3& ng, const vec3& wo) {
  return std::min(0.9f * std::abs(glm::dot(wo, ng)), 0.01f);
}

TEST(RayTracer, InteractionGeometryOnTransformedGrid) {
  Scene scene;
  scene.name = "grid";
  scene.meshes.push_back(grid_mesh(8));
  scene.meshes[0].material = 1;
  scene.materials.resize(2);
  Instance inst;
  inst.name = "grid";
  inst.transform = glm::translate(mat4(1.0f), vec3(0.2f, 0.5f, -0.3f)) *
                   glm::rotate(mat4(1.0f), 0.6f, glm::normalize(vec3(1.0f, 0.3f, -0.4f))) *
                   glm::scale(mat4(1.0f), vec3(2.0f, 1.0f, 0.5f));
  scene.instances.push_back(inst);
  const RayTracer tracer(scene);
  const mat4 to_object = glm::inverse(inst.transform);
  const vec3 plane_normal =
      glm::normalize(glm::transpose(glm::inverse(mat3(inst.transform))) * vec3(0.0f, 1.0f, 0.0f));
  Rng rng(7);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    // Aim at a random point of the grid from either side.
    const vec3 target_obj(rng.uniform(0.02f, 0.98f), 0.0f, rng.uniform(0.02f, 0.98f));
    const vec3 target = vec3(inst.transform * vec4(target_obj, 1.0f));
    Ray ray;
    ray.origin = target + 3.0f * rng.on_sphere();
    ray.direction = 1.7f * (target - ray.origin);  // not unit on purpose
    Hit hit;
    if (!tracer.intersect(ray, &hit)) continue;
    ++hits;
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    expect_unit(si.ng, "ng");
    expect_unit(si.ns, "ns");
    expect_unit(si.wo, "wo");
    expect_unit(si.shading.t, "shading.t");
    expect_unit(si.shading.b, "shading.b");
    EXPECT_NEAR(glm::dot(si.shading.t, si.ns), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(si.shading.b, si.ns), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(si.shading.t, si.shading.b), 0.0f, 1e-5f);
    EXPECT_EQ(si.shading.n, si.ns);
    // Winding CCW seen from +y in object space → ng is the transformed +y.
    EXPECT_NEAR(glm::dot(si.ng, plane_normal), 1.0f, 1e-5f);
    EXPECT_GE(glm::dot(si.ns, si.ng), 0.0f);
    // The point lies on the ray and on the plane; uv is the affine function of it.
    // On the ray: its distance from the ray's line is float rounding of the coordinates
    // involved (~1e-7 relative to the largest; 1e-5 leaves a margin), amplified by the
    // conditioning of a ray–plane intersection, 1/|cos θ|.
    const vec3 along = glm::normalize(ray.direction);
    const float scale =
        std::max({1.0f, max_component(glm::abs(ray.origin)), hit.t * glm::length(ray.direction)}) /
        std::abs(glm::dot(along, si.ng));
    EXPECT_LE(glm::length(glm::cross(si.p - ray.origin, along)), 1e-5f * scale);
    const vec3 p_obj = vec3(to_object * vec4(si.p, 1.0f));
    EXPECT_NEAR(p_obj.y, 0.0f, 1e-5f);
    EXPECT_LE(glm::length(si.uv0 - uv0_of(p_obj)), 1e-5f);
    EXPECT_LE(glm::length(si.uv1 - uv1_of(p_obj)), 1e-5f);
    // Shading normal: interpolated object normal through the normal matrix.
    const Mesh& mesh = scene.meshes[0];
    const uint32_t* idx = &mesh.indices[3 * hit.primitive];
    const float b1 = hit.barycentric.x, b2 = hit.barycentric.y;
    const vec3 n_obj = (1.0f - b1 - b2) * mesh.normals[idx[0]] + b1 * mesh.normals[idx[1]] +
                       b2 * mesh.normals[idx[2]];
    vec3 expected_ns = glm::normalize(glm::transpose(glm::inverse(mat3(inst.transform))) * n_obj);
    if (glm::dot(expected_ns, si.ng) < 0.0f) expected_ns = -expected_ns;
    // Unless it would hide wo (then bent: ShadingNormalBentWhereItHidesTheViewer).
    if (reflection_rise(expected_ns, si.ng, si.wo) >= reflection_threshold(si.ng, si.wo)) {
      EXPECT_NEAR(glm::dot(si.ns, expected_ns), 1.0f, 1e-5f);
    }
    EXPECT_LE(glm::length(si.wo + glm::normalize(ray.direction)), 1e-6f);
    EXPECT_EQ(si.material, 1);
    EXPECT_EQ(si.light, -1);
    EXPECT_EQ(si.instance, 0u);
    EXPECT_EQ(si.t, hit.t);
  }
  EXPECT_GT(hits, 1900);
}

TEST(RayTracer, ShadingNormalKeptOnGeometricSide) {
  Mesh mesh = grid_mesh(2);
  for (vec3& n : mesh.normals) n = -n;  // vertex normals against the winding
  const Scene scene = single_instance_scene(std::move(mesh));
  const RayTracer tracer(scene);
  Ray ray;
  ray.origin = vec3(0.3f, 1.0f, 0.6f);
  ray.direction = vec3(0.0f, -1.0f, 0.0f);
  Hit hit;
  ASSERT_TRUE(tracer.intersect(ray, &hit));
  const SurfaceInteraction si = tracer.interaction(ray, hit);
  EXPECT_NEAR(si.ng.y, 1.0f, 1e-6f);
  EXPECT_GT(glm::dot(si.ns, si.ng), 0.9f);
}

// A smoothed normal tilted 60° off a flat triangle, seen at a grazing angle from the side
// it leans away from: the interpolated normal hides the viewer (wo·ns < 0) while the
// triangle faces it, which made every BSDF return black (Sibenik's capitals). The tracer
// bends it towards ng just enough that wo's mirror direction rises from the surface, and
// leaves it alone wherever it was valid.
TEST(RayTracer, ShadingNormalBentWhereItHidesTheViewer) {
  Mesh mesh = grid_mesh(2);
  const vec3 tilted = glm::normalize(vec3(std::sin(1.047f), std::cos(1.047f), 0.0f));
  for (vec3& n : mesh.normals) n = tilted;
  const Scene scene = single_instance_scene(std::move(mesh));
  const RayTracer tracer(scene);
  int bent = 0, kept = 0;
  for (int k = 0; k < 64; ++k) {
    const float elevation = 0.02f + 1.5f * float(k) / 64.0f;  // radians above the plane
    for (const float azimuth_sign : {-1.0f, 1.0f}) {
      const vec3 towards_eye(azimuth_sign * std::cos(elevation), std::sin(elevation), 0.0f);
      Ray ray;
      ray.origin = vec3(0.5f, 0.0f, 0.5f) + 2.0f * towards_eye;
      ray.direction = -towards_eye;
      Hit hit;
      ASSERT_TRUE(tracer.intersect(ray, &hit));
      const SurfaceInteraction si = tracer.interaction(ray, hit);
      expect_unit(si.ns, "ns");
      EXPECT_GT(glm::dot(si.ns, si.wo), 0.0f) << "elevation " << elevation;
      EXPECT_GE(reflection_rise(si.ns, si.ng, si.wo), reflection_threshold(si.ng, si.wo) - 1e-4f)
          << "elevation " << elevation;
      EXPECT_NEAR(glm::dot(si.shading.n, si.ns), 1.0f, 1e-6f);
      if (reflection_rise(tilted, si.ng, si.wo) >= reflection_threshold(si.ng, si.wo)) {
        EXPECT_NEAR(glm::dot(si.ns, tilted), 1.0f, 1e-6f) << "a valid normal is left alone";
        ++kept;
      } else {
        // Bent within the plane of ns and ng, no further than needed: still tilted the
        // original way, and closer to ng than the smoothed normal was.
        EXPECT_GT(si.ns.x * tilted.x, 0.0f);
        EXPECT_GT(si.ns.y, tilted.y);
        EXPECT_NEAR(si.ns.z, 0.0f, 1e-6f);
        ++bent;
      }
    }
  }
  EXPECT_GT(bent, 10) << "the grazing views on the far side must need bending";
  EXPECT_GT(kept, 10) << "views whose mirror direction already rises must not";
}

TEST(RayTracer, AreaLightIndexForEmissiveInstance) {
  Scene scene;
  scene.name = "lights";
  scene.meshes.push_back(grid_mesh(2));
  scene.materials.resize(2);
  scene.materials[1].emission = Color(5.0f);
  Mesh emitter = grid_mesh(2);
  emitter.material = 1;
  scene.meshes.push_back(emitter);
  for (int i = 0; i < 3; ++i) {
    Instance inst;
    inst.name = "slab" + std::to_string(i);
    inst.mesh = i == 2 ? 1 : 0;
    inst.transform = glm::translate(mat4(1.0f), vec3(2.0f * i, 0.0f, 0.0f));
    scene.instances.push_back(inst);
  }
  Light point;
  point.type = LightType::kPoint;
  Light area;
  area.type = LightType::kArea;
  area.instance = 2;
  scene.lights = {point, area};
  const RayTracer tracer(scene);
  for (int i = 0; i < 3; ++i) {
    Ray ray;
    ray.origin = vec3(2.0f * i + 0.5f, 1.0f, 0.5f);
    ray.direction = vec3(0.0f, -1.0f, 0.0f);
    Hit hit;
    ASSERT_TRUE(tracer.intersect(ray, &hit));
    ASSERT_EQ(hit.instance, static_cast<uint32_t>(i));
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    EXPECT_EQ(si.light, i == 2 ? 1 : -1);
    EXPECT_EQ(si.material, i == 2 ? 1 : 0);
  }
}

TEST(RayTracer, NormalMapTiltsShadingNormalAlongTangent) {
  // A constant normal map whose texel decodes to m = (0.6, 0, 0.8): the shading normal
  // must become 0.6·t + 0.8·n with t the mesh tangent (+x on the grid).
  Scene scene;
  scene.name = "normal-map";
  Mesh mesh = grid_mesh(2);
  // uv0 = 0.1·(x, z): ∂p/∂u is +x, ∂p/∂v is +z.
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    mesh.uv0[i] = 0.1f * vec2(mesh.positions[i].x, mesh.positions[i].z);
  for (vec3& n : mesh.normals) n = vec3(0.0f, 1.0f, 0.0f);
  scene.meshes.push_back(mesh);
  Texture texture;
  texture.path = "constant";
  texture.srgb = false;
  texture.image = Image(4, 4, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) texture.image.set_rgb(x, y, Color(0.8f, 0.5f, 0.9f));
  scene.textures.push_back(texture);
  Material material;
  material.normal_texture = 0;
  scene.materials.push_back(material);
  Instance inst;
  scene.instances.push_back(inst);
  for (bool with_tangents : {true, false}) {
    SCOPED_TRACE(with_tangents ? "mesh tangents" : "tangents from uv");
    Mesh& m = scene.meshes[0];
    m.tangents.assign(with_tangents ? m.positions.size() : 0, vec4(1.0f, 0.0f, 0.0f, 1.0f));
    const RayTracer tracer(scene);
    Ray ray;
    ray.origin = vec3(0.4f, 1.0f, 0.7f);
    ray.direction = vec3(0.0f, -1.0f, 0.0f);
    Hit hit;
    ASSERT_TRUE(tracer.intersect(ray, &hit));
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    const vec3 expected =
        glm::normalize(0.6f * vec3(1.0f, 0.0f, 0.0f) + 0.8f * vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(glm::dot(si.ns, expected), 1.0f, 1e-5f)
        << si.ns.x << " " << si.ns.y << " " << si.ns.z;
    EXPECT_NEAR(glm::dot(si.shading.t, si.ns), 0.0f, 1e-5f);
    EXPECT_NEAR(si.ng.y, 1.0f, 1e-6f);
  }
}

}  // namespace
}  // namespace illum
