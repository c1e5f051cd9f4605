// Irradiance probes (bake/probe_baker.h, baked/probe_file.h, bake/probe_lookup.h): irradiance
// at a probe against the path tracer's own radiance integrated independently, a leak test
// across a thin wall, the validity test inside a closed box, SH-L2 ↔ ambient cube consistency,
// the folder's round trip and checks, bake identity, determinism, bad options.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "../render/render_test_scenes.h"
#include "illum/bake/probe_baker.h"
#include "illum/bake/probe_lookup.h"
#include "illum/baked/probe_file.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/render/light_sampler.h"
#include "illum/render/path_radiance.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"

namespace illum::bake {
namespace {

namespace fs = std::filesystem;
using test::add_material;
using test::add_triangles;
using test::inward_box;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

int lambert(Scene& s, float albedo) {
  Material m;
  m.albedo = Color(albedo);
  return add_material(s, m);
}

Light point_light(const vec3& p, float intensity) {
  Light l;
  l.type = LightType::kPoint;
  l.position = p;
  l.intensity = Color(intensity);
  return l;
}

// Reference estimates at (p, n) from the path tracer's radiance along rays leaving p
// (PathRadiance::camera: no next-event estimation at p, another sampling than the bake's):
//   full   E(n) = ∫_H L cos, cosine-weighted hemisphere directions, each sample π·L;
//   band   E₂(n) = ∫_S² L k₂(n·ω), the SH-L2 band-limited irradiance, uniform sphere
//          directions, k₂(t) = ¼ + t/2 + (5/16)(3t² − 1)/2 the clamped cosine's first 3 bands;
//   bound  B(n) = ∫_S² L |max(t, 0) − k₂(t)|, same samples: since L ≥ 0, |E − E₂| ≤ B.
// Standard errors s/√N (independent-sample formula: an upper estimate for Sobol' points).
struct Reference {
  Color full, band, bound, full_se, band_se, bound_se;
};
Reference reference_irradiance(const Scene& scene, const RayTracer& tracer, const vec3& p,
                               const vec3& n, int samples, uint64_t seed) {
  const LightSampler lights(scene);
  const PathRadiance transport(tracer, lights, PathRadianceOptions{});
  const Frame frame = Frame::from_normal(n);
  glm::dvec3 s[3] = {}, s2[3] = {};
  int64_t rays = 0;
  SobolSampler sampler(hash_mix(seed, 0x726566));
  for (int k = 0; k < samples; ++k) {
    sampler.start_sample(uint32_t(k));
    const vec3 wc = glm::normalize(frame.to_world(sample_cosine_hemisphere(sampler.next_2d())));
    const vec3 wu = sample_uniform_sphere(sampler.next_2d());
    const glm::dvec3 lc(transport.camera(Ray{p, wc}, sampler, &rays));
    const glm::dvec3 lu(transport.camera(Ray{p, wu}, sampler, &rays));
    const double t = glm::dot(n, wu);
    const double k2 = 0.25 + 0.5 * t + 5.0 / 32.0 * (3.0 * t * t - 1.0);
    const glm::dvec3 x[3] = {double(kPi) * lc, 4.0 * kPi * k2 * lu,
                             4.0 * kPi * std::abs(std::max(t, 0.0) - k2) * lu};
    for (int i = 0; i < 3; ++i) {
      s[i] += x[i];
      s2[i] += x[i] * x[i];
    }
  }
  Color mean[3], se[3];
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 m = s[i] / double(samples);
    const glm::dvec3 var = (s2[i] / double(samples) - m * m) * (double(samples) / (samples - 1));
    mean[i] = Color(m);
    se[i] = Color(glm::sqrt(glm::max(var, glm::dvec3(0.0)) / double(samples)));
  }
  return {mean[0], mean[1], mean[2], se[0], se[1], se[2]};
}

// An upper bound on the standard error of E(n) = Σ_i E_i Y_i(n) from the coefficients' own
// standard errors, whatever their correlation: σ(Σ a_i X_i) ≤ Σ |a_i| σ_i.
Color probe_error(const float* se, const vec3& n) {
  float y[kProbeCoefficients];
  sh::evaluate<float>(kProbeBands, n, std::span<float>(y, kProbeCoefficients));
  Color e(0.0f);
  for (int i = 0; i < kProbeCoefficients; ++i)
    e += std::abs(y[i]) * Color(se[3 * i], se[3 * i + 1], se[3 * i + 2]);
  return e;
}

constexpr float kZ = 4.0f;  // standard deviations allowed in a statistical comparison

TEST(Probes, IrradianceAtAProbeMatchesThePathTracer) {
  const Scene scene = load_scene("cornell");
  const RayTracer tracer(scene);
  const Bounds3 b = tracer.bounds();
  const vec3 size = b.max - b.min;
  // The middle of the room, and low near the floor in front of the boxes.
  const std::vector<vec3> points = {b.center(), b.min + size * vec3(0.5f, 0.15f, 0.12f)};
  ProbeBakeOptions options;
  options.spp = 4096;
  options.progress = false;
  options.seed = 3;
  std::vector<float> se;
  const std::vector<ProbeRecord> probes = bake_probes_at(scene, tracer, points, options, &se);
  const vec3 normals[] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}};
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(probes[i].weight, 1.0f);
    for (const vec3& n : normals) {
      const Reference ref = reference_irradiance(scene, tracer, points[i], n, 16384, 11 + i);
      const Color e = irradiance_from_sh(probes[i].irradiance, n);
      const Color sp = probe_error(&se[i * 27], n);
      for (int c = 0; c < 3; ++c) {
        // The same band-limited quantity: agreement within the estimators' noise.
        const float tol_band = kZ * std::sqrt(sp[c] * sp[c] + ref.band_se[c] * ref.band_se[c]);
        EXPECT_NEAR(e[c], ref.band[c], tol_band)
            << "probe " << i << " n " << n.x << "," << n.y << "," << n.z << " channel " << c;
        // The true irradiance: within the band-limiting bound B plus the noise of all three.
        const float tol_full =
            ref.bound[c] + kZ * std::sqrt(sp[c] * sp[c] + ref.full_se[c] * ref.full_se[c] +
                                          ref.bound_se[c] * ref.bound_se[c]);
        EXPECT_NEAR(e[c], ref.full[c], tol_full)
            << "probe " << i << " n " << n.x << "," << n.y << "," << n.z << " channel " << c;
      }
      std::printf(
          "probe %zu n (%g,%g,%g): E_probe %.4f, E2 ref %.4f ± %.4f, E ref %.4f ± %.4f, "
          "bound %.4f (green)\n",
          i, n.x, n.y, n.z, e.y, ref.band.y, ref.band_se.y, ref.full.y, ref.full_se.y, ref.bound.y);
    }
  }
}

// Two rooms [−2, 0] and [0, 2] (x) × [0, 2] × [−1, 1] separated by a closed wall 5 cm thick,
// a point light in the room at x > 0.
Scene two_rooms() {
  Scene s;
  s.name = "two-rooms";
  const int mat = lambert(s, 0.5f);
  add_triangles(s, inward_box(vec3(-2.0f, 0.0f, -1.0f), vec3(2.0f, 2.0f, 1.0f)), mat, "room");
  add_triangles(s, inward_box(vec3(-0.025f, 0.0f, -1.0f), vec3(0.025f, 2.0f, 1.0f), false), mat,
                "wall");
  s.lights.push_back(point_light(vec3(0.6f, 1.2f, 0.1f), 5.0f));
  return s;
}

baked::ProbeSet bake_set(const Scene& scene, const RayTracer& tracer, float spacing, int spp) {
  ProbeBakeOptions options;
  options.spacing = spacing;
  options.spp = spp;
  options.progress = false;
  ProbeBake baked = bake_probes(scene, tracer, options);
  baked::ProbeSet set;
  set.grid = baked.grid;
  set.probes = std::move(baked.probes);
  set.scene = scene.name;
  set.scene_triangles = scene.triangle_count();
  set.scene_hash = geometry_hash_hex(scene);
  return set;
}

// The dark room has no light path to the light (the wall is closed, every shadow ray from it
// is blocked), so its true irradiance is exactly 0 and every dark probe's estimate is a sum
// of exact zeros. A lookup in the dark room must then be exactly 0 too: the bound is 0. The
// probes on the lit side of a cell that straddles the wall are what would leak; the
// visibility test in lookup_probes drops them. Without it (occluders = nullptr) the same
// lookups leak, which the test also checks, so the scene does exercise the leak.
TEST(Probes, NoLightLeaksThroughAThinWall) {
  const Scene scene = two_rooms();
  const RayTracer tracer(scene);
  const baked::ProbeSet set = bake_set(scene, tracer, 0.25f, 64);
  ASSERT_EQ(set.grid.size, glm::ivec3(16, 8, 8));
  EXPECT_NEAR(set.grid.position(7, 0, 0).x, -0.125f, 1e-5f);  // a cell straddles the wall
  double lit_max = 0.0;  // the lit probes next to the wall (x = 0.125), facing it
  for (int64_t i = 0; i < set.grid.count(); ++i) {
    const vec3 p = set.grid.position(i);
    const ProbeRecord& r = set.probes[size_t(i)];
    EXPECT_EQ(r.weight, 1.0f) << "probe at " << p.x << "," << p.y << "," << p.z;
    if (p.x < 0.0f) {
      for (float v : r.irradiance) ASSERT_EQ(v, 0.0f) << "dark probe " << i;
    } else if (p.x < 0.25f) {
      lit_max = std::max(lit_max, double(irradiance_from_sh(r.irradiance, vec3(-1, 0, 0)).y));
    }
  }
  ASSERT_GT(lit_max, 0.1);  // the lit side facing the wall is lit
  double leak_without_visibility = 0.0;
  const vec3 normals[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (float x : {-0.03f, -0.05f, -0.1f, -0.2f, -0.6f, -1.9f})
    for (float y : {0.05f, 0.7f, 1.2f, 1.95f})
      for (float z : {-0.9f, 0.1f, 0.8f}) {
        const vec3 p(x, y, z);
        for (const vec3& n : normals) {
          const Color e = lookup_irradiance(set, p, n, &tracer);
          EXPECT_EQ(max_component(glm::abs(e)), 0.0f) << "leak at " << x << "," << y << "," << z;
          leak_without_visibility =
              std::max(leak_without_visibility, double(lookup_irradiance(set, p, n).y));
        }
        EXPECT_GT(lookup_probes(set, p, &tracer).weight, 0.0f);  // dark probes remain
      }
  // Plain trilinear weights (validity only) do leak: the cell across the wall mixes sides.
  std::printf(
      "lit probes beside the wall: max E %.4f; dark side max E without visibility %.4f, with 0\n",
      lit_max, leak_without_visibility);
  EXPECT_GT(leak_without_visibility, 0.1 * lit_max);
  // The lit side still reads its light.
  EXPECT_GT(lookup_irradiance(set, vec3(0.2f, 1.2f, 0.1f), vec3(1, 0, 0), &tracer).y, 0.0f);
}

// A closed solid box inside a lit room: probes inside it see only its back faces (share 1)
// and are invalid; probes outside see only front faces (share 0) and are valid.
TEST(Probes, ValidityRejectsProbesInsideAClosedBox) {
  Scene s;
  s.name = "box-in-room";
  const int mat = lambert(s, 0.5f);
  add_triangles(s, inward_box(vec3(-1.0f), vec3(1.0f)), mat, "room");
  add_triangles(s, inward_box(vec3(-0.35f), vec3(0.35f), false), mat, "box");
  s.lights.push_back(point_light(vec3(0.0f, 0.8f, 0.6f), 1.0f));
  const RayTracer tracer(s);
  const baked::ProbeSet set = bake_set(s, tracer, 0.2f, 64);
  ASSERT_EQ(set.grid.size, glm::ivec3(10));
  int inside = 0;
  for (int64_t i = 0; i < set.grid.count(); ++i) {
    const vec3 p = set.grid.position(i);
    const bool in = glm::all(glm::lessThan(glm::abs(p), vec3(0.35f)));
    const ProbeRecord& r = set.probes[size_t(i)];
    inside += in;
    EXPECT_EQ(r.weight, in ? 0.0f : 1.0f) << p.x << "," << p.y << "," << p.z;
    EXPECT_EQ(r.backface_fraction, in ? 1.0f : 0.0f) << p.x << "," << p.y << "," << p.z;
  }
  EXPECT_EQ(inside, 64);
  // A lookup beside the box renormalises over the valid corners: it reads what the valid
  // probes hold, not a mean darkened by the invalid ones.
  const vec3 p(0.32f, 0.05f, 0.05f);  // in the cell x ∈ [0.3, 0.5]: half its corners inside
  const ProbeSample sample = lookup_probes(set, p);
  EXPECT_GT(sample.weight, 0.0f);
  EXPECT_LT(sample.weight, 0.5f);
  const int x1 = 7;  // x = 0.5
  Color expected(0.0f);
  float total = 0.0f;
  for (int y : {4, 5})
    for (int z : {4, 5}) {
      const float w = (y == 5 ? 0.75f : 0.25f) * (z == 5 ? 0.75f : 0.25f);
      const ProbeRecord& r = set.probes[size_t((z * 10 + y) * 10 + x1)];
      expected += w * irradiance_from_sh(r.irradiance, vec3(1, 0, 0));
      total += w;
    }
  const Color got = irradiance_from_sh(sample.irradiance, vec3(1, 0, 0));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c] / total, 1e-5f * expected[c] / total);
}

// Irradiance SH with E ≥ 0 at the axes: a constant plus random bands 1 and 2.
std::vector<float> random_irradiance(uint64_t seed) {
  Rng rng(seed);
  std::vector<float> e(27);
  for (int i = 0; i < 27; ++i) e[size_t(i)] = (rng.next_float() - 0.5f) * (i < 3 ? 0.0f : 0.6f);
  for (int c = 0; c < 3; ++c) e[size_t(c)] = 3.0f + rng.next_float();
  return e;
}

TEST(Probes, AmbientCubeAgreesWithTheShOnTheAxesAndWithinItsBound) {
  const vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  Rng rng(7);
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const std::vector<float> e = random_irradiance(seed);
    float cube[18];
    ambient_cube_from_sh(e.data(), cube);
    for (const vec3& a : axes) {
      const Color sh = irradiance_from_sh(e.data(), a), cb = kPi * evaluate_ambient_cube(cube, a);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(cb[c], sh[c], 1e-5f * sh[c]);
    }
    const Color bound = ambient_cube_error_bound(e.data());
    float worst = 0.0f;
    for (int k = 0; k < 2000; ++k) {
      const vec3 n = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
      const Color d =
          glm::abs(kPi * evaluate_ambient_cube(cube, n) - irradiance_from_sh(e.data(), n));
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(d[c], bound[c] + 1e-5f) << "seed " << seed;
        worst = std::max(worst, d[c] / bound[c]);
      }
    }
    EXPECT_GT(worst, 0.5f);  // the bound is not loose by more than 2×
  }
  // What the cube's basis holds exactly: a constant plus Q's diagonal (Y00, Y20, Y22).
  std::vector<float> e(27, 0.0f);
  for (int c = 0; c < 3; ++c) {
    e[size_t(c)] = 2.0f + float(c);
    e[size_t(3 * 6 + c)] = 0.4f;
    e[size_t(3 * 8 + c)] = -0.3f * float(c);
  }
  float cube[18];
  ambient_cube_from_sh(e.data(), cube);
  for (int k = 0; k < 500; ++k) {
    const vec3 n = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
    const Color sh = irradiance_from_sh(e.data(), n), cb = kPi * evaluate_ambient_cube(cube, n);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(cb[c], sh[c], 1e-5f * sh[c]);
  }
}

class ProbeFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("illum_probes_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ProbeFolder, RoundTripsAndChecksWhatItReads) {
  const Scene scene = two_rooms();
  const RayTracer tracer(scene);
  baked::ProbeSet set = bake_set(scene, tracer, 0.5f, 8);
  set.bake = {{"spp", 8}};
  const fs::path folder = dir_ / "probes";
  baked::save_probe_set(folder, set);
  const baked::ProbeSet back = baked::load_probe_set_for(folder, scene);
  EXPECT_EQ(back.grid.size, set.grid.size);
  EXPECT_EQ(back.grid.origin, set.grid.origin);
  EXPECT_EQ(back.grid.spacing, set.grid.spacing);
  EXPECT_EQ(back.scene_hash, set.scene_hash);
  ASSERT_EQ(back.probes.size(), set.probes.size());
  EXPECT_EQ(
      std::memcmp(back.probes.data(), set.probes.data(), set.probes.size() * sizeof(ProbeRecord)),
      0);
  // Replacing an earlier probe folder works; an unrelated folder is refused.
  baked::save_probe_set(folder, set);
  fs::create_directories(dir_ / "other");
  EXPECT_NE(
      error_of([&] { baked::save_probe_set(dir_ / "other", set); }).find("not a probe folder"),
      std::string::npos);
  // Damaged data: truncated, trailing bytes, a NaN, a weight that is not 0 or 1.
  const fs::path bin = folder / "probes.bin";
  const auto bytes = fs::file_size(bin);
  auto damaged = [&](const std::function<void()>& damage, const std::string& needle) {
    baked::save_probe_set(folder, set);
    damage();
    const std::string e = error_of([&] { baked::load_probe_set(folder); });
    EXPECT_NE(e.find(needle), std::string::npos) << e;
  };
  damaged([&] { fs::resize_file(bin, bytes - 4); }, "truncated");
  damaged([&] { std::ofstream(bin, std::ios::app) << "x"; }, "trailing data");
  auto poke = [&](size_t float_index, float value) {
    std::fstream f(bin, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(24 + float_index * 4));
    f.write(reinterpret_cast<const char*>(&value), 4);
  };
  damaged([&] { poke(5, std::nanf("")); }, "not finite");
  damaged([&] { poke(46, 0.5f); }, "weight 0.5");
  damaged([&] { fs::remove(bin); }, "cannot open");
  EXPECT_NE(error_of([&] { baked::load_probe_set(dir_ / "missing"); }).find("does not exist"),
            std::string::npos);
}

TEST_F(ProbeFolder, IsRefusedForAnotherSceneButNotForMovedDynamicObjects) {
  Scene scene = two_rooms();
  // A dynamic object: left out of the bake and the hash.
  const int mat = lambert(scene, 0.8f);
  const int ball = add_triangles(scene, inward_box(vec3(0.5f), vec3(0.7f), false), mat, "ball");
  scene.instances[size_t(ball)].dynamic = true;
  const Scene statics = static_part(scene);
  EXPECT_EQ(statics.instances.size(), 2u);
  const RayTracer tracer(statics);
  baked::ProbeSet set = bake_set(statics, tracer, 0.5f, 4);
  const fs::path folder = dir_ / "probes";
  baked::save_probe_set(folder, set);
  EXPECT_NO_THROW(baked::load_probe_set_for(folder, scene));
  scene.instances[size_t(ball)].transform = glm::translate(mat4(1.0f), vec3(-1.0f, 0.0f, 0.0f));
  EXPECT_NO_THROW(baked::load_probe_set_for(folder, scene));  // moved: still the same static scene
  const std::vector<InstanceCube> cubes = dynamic_instance_cubes(set, scene, &tracer);
  ASSERT_EQ(cubes.size(), 1u);
  EXPECT_GT(cubes[0].weight, 0.0f);
  // Another scene: the wall moved by 1 cm.
  Scene other = two_rooms();
  for (vec3& p : other.meshes[1].positions) p.x += 0.01f;
  const std::string e = error_of([&] { baked::load_probe_set_for(folder, other); });
  EXPECT_NE(e.find("baked for scene 'two-rooms'"), std::string::npos) << e;
  EXPECT_NE(e.find("bake it again"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  EXPECT_FALSE(error_of([&] { dynamic_instance_cubes(set, other); }).empty());
}

TEST(Probes, SameProbesWhateverTheThreadCount) {
  const Scene scene = load_scene("cornell");
  const RayTracer tracer(scene);
  ProbeBakeOptions options;
  options.spacing = 0.1f;
  options.spp = 16;
  options.progress = false;
  options.threads = 1;
  const ProbeBake one = bake_probes(scene, tracer, options);
  options.threads = 2;
  const ProbeBake two = bake_probes(scene, tracer, options);
  ASSERT_EQ(one.probes.size(), two.probes.size());
  EXPECT_EQ(
      std::memcmp(one.probes.data(), two.probes.data(), one.probes.size() * sizeof(ProbeRecord)),
      0);
}

TEST(Probes, GridFitsTheBoundsAndRefusesBadSpacings) {
  Bounds3 b;
  b.extend(vec3(0.0f));
  b.extend(vec3(4.0f, 1.0f, 2.3f));
  const ProbeGrid g = make_probe_grid(b, 0.5f);
  EXPECT_EQ(g.size, glm::ivec3(8, 2, 5));  // round(8), round(2), round(4.6)
  for (int a = 0; a < 3; ++a) {
    const float inset = g.origin[a] - b.min[a];
    EXPECT_GE(inset, 0.25f * 0.5f - 1e-5f);
    EXPECT_LE(inset, 0.75f * 0.5f + 1e-5f);
  }
  EXPECT_EQ(make_probe_grid(b, 0.0f).size.x, kDefaultProbesAlongLongestSide);
  for (float bad : {-1.0f, std::nanf(""), INFINITY})
    EXPECT_NE(error_of([&] { make_probe_grid(b, bad); }).find("spacing"), std::string::npos);
  const std::string e = error_of([&] { make_probe_grid(b, 1e-3f); });
  EXPECT_NE(e.find("9.2e+09 probes"), std::string::npos) << e;  // 4000 × 1000 × 2300
  EXPECT_NE(e.find("bytes"), std::string::npos) << e;
}

TEST(Probes, RefusesBadOptionsAndUnlitScenes) {
  Scene scene = two_rooms();
  const RayTracer tracer(scene);
  ProbeBakeOptions options;
  options.progress = false;
  options.spp = 0;
  EXPECT_NE(error_of([&] { bake_probes(scene, tracer, options); }).find("spp = 0"),
            std::string::npos);
  options.spp = 4;
  options.spacing = -0.5f;
  EXPECT_NE(error_of([&] { bake_probes(scene, tracer, options); }).find("spacing"),
            std::string::npos);
  options.spacing = 0.5f;
  options.backface_threshold = 1.5f;
  EXPECT_NE(error_of([&] { bake_probes(scene, tracer, options); }).find("backface_threshold"),
            std::string::npos);
  options.backface_threshold = 0.25f;
  scene.lights.clear();
  const RayTracer unlit(scene);
  EXPECT_NE(error_of([&] { bake_probes(scene, unlit, options); }).find("has no light"),
            std::string::npos);
}

}  // namespace
}  // namespace illum::bake
