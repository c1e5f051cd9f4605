// The generic progressive-refinement loop (bake/progressive_shooting.h) on patches made by
// hand, without a scene or a ray tracer: a closed unit cube whose faces are m×m patches
// (convex from inside, so every pair of patches sees each other and visibility is always
// true).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "illum/bake/progressive_shooting.h"
#include "illum/bake/shooting_clusters.h"
#include "illum/core/color.h"
#include "illum/core/parallel.h"

namespace illum::bake {
namespace {

// Six faces of the unit cube, normals inward; face f occupies grid cells
// [f·(m+2), f·(m+2)+m) × [0, m) so groups never cross a face (and surface = face anyway).
ShootingPatches cube_patches(int m) {
  ShootingPatches set;
  set.grid_width = 6 * (m + 2);
  set.grid_height = m;
  set.patch_at.assign(size_t(set.grid_width) * size_t(m), -1);
  set.surface_count = 6;
  const float h = 1.0f / float(m);
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const float side = (f % 2 == 0) ? 0.0f : 1.0f;
    for (int v = 0; v < m; ++v)
      for (int u = 0; u < m; ++u) {
        vec3 p(0.0f), n(0.0f);
        p[axis] = side;
        p[(axis + 1) % 3] = (float(u) + 0.5f) * h;
        p[(axis + 2) % 3] = (float(v) + 0.5f) * h;
        n[axis] = side == 0.0f ? 1.0f : -1.0f;
        ShootingPatch patch{p, n, h * h, f * (m + 2) + u, v, f};
        set.patch_at[size_t(v) * size_t(set.grid_width) + size_t(patch.x)] =
            int32_t(set.patches.size());
        set.patches.push_back(patch);
      }
  }
  return set;
}

struct ClosedCube {
  float albedo = 0.5f;
  bool conserve = true;
  double magnitude(const Color& c) const { return double(c.x) + double(c.y) + double(c.z); }
  Color reflect(int, const Color& arriving) const { return arriving * albedo; }
  bool visible(const ShotSource&, int) const { return true; }
  double reach(const ShotSource&) const { return conserve ? 1.0 : -1.0; }
};

struct Solution {
  std::vector<Color> total;
  ShootingStats stats;
};

Solution solve(const ShootingPatches& set, const ClosedCube& cube, double threshold, float exitance,
               float cluster_ratio = 0.0f) {
  Solution s;
  s.total.assign(set.patches.size(), Color(0.0f));
  std::vector<Color> unshot(set.patches.size(), Color(exitance));
  ShootingOptions options;
  options.threshold = threshold;
  options.cluster_ratio = cluster_ratio;
  options.progress = false;
  s.stats = shoot_progressively(set, s.total, unshot, cube, options);
  return s;
}

double area_mean(const ShootingPatches& set, const std::vector<Color>& v) {
  double sum = 0.0, area = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    sum += double(v[i].x) * set.patches[i].area;
    area += set.patches[i].area;
  }
  return sum / area;
}

// Conservation makes the furnace's area mean exact up to what is left unshot: with every
// shot handing out all its power P (receivers get P, re-emit ρP), T + U/(1−ρ) is invariant,
// so the mean irradiance is (E − U/A)/(1−ρ): its relative shortfall is U/U₀ ≤ threshold.
TEST(ProgressiveShooting, ClosedCubeMeanIsExactWithinTheThreshold) {
  const ShootingPatches set = cube_patches(8);
  const ClosedCube cube;
  const float exitance = 2.0f;
  for (const double threshold : {1e-2, 1e-4}) {
    const Solution s = solve(set, cube, threshold, exitance);
    EXPECT_TRUE(s.stats.converged);
    const double exact = exitance / (1.0 - cube.albedo);
    const double mean = area_mean(set, s.total);
    EXPECT_LE(mean, exact * (1.0 + 1e-5)) << "threshold " << threshold;
    // float sums over 384 patches and thousands of shots: 1e-5 relative
    EXPECT_GE(mean, exact * (1.0 - threshold - 1e-5)) << "threshold " << threshold;
    EXPECT_NEAR(s.stats.remaining_power / s.stats.initial_power, (exact - mean) / exact, 1e-5);
  }
}

// Without the conservation scaling the form factors' quadrature error shows in the mean:
// the check above is not satisfied by any shooting loop.
TEST(ProgressiveShooting, WithoutConservationTheMeanMissesByTheQuadratureError) {
  const ShootingPatches set = cube_patches(8);
  ClosedCube cube;
  cube.conserve = false;
  const Solution s = solve(set, cube, 1e-4, 2.0f);
  const double exact = 2.0 / (1.0 - cube.albedo);
  EXPECT_GT(std::abs(area_mean(set, s.total) - exact), 1e-3 * exact);
}

TEST(ProgressiveShooting, SameResultForOneTwoAndFourThreads) {
  const ShootingPatches set = cube_patches(6);
  const ClosedCube cube;
  std::vector<std::vector<Color>> results;
  for (int threads : {1, 2, 4}) {
    ThreadLimit limit(threads);
    results.push_back(solve(set, cube, 1e-3, 1.0f).total);
  }
  for (size_t r = 1; r < results.size(); ++r)
    for (size_t i = 0; i < results[0].size(); ++i)
      ASSERT_EQ(std::memcmp(&results[0][i], &results[r][i], sizeof(Color)), 0) << r << " " << i;
}

// Receiver clusters (shooting_clusters.h) only share visibility; every receiver keeps its own
// form factor. Where everything sees everything (the inside of a cube) the clustered loop is
// therefore the unclustered one exactly, bit for bit, while casting far fewer rays.
TEST(ProgressiveShooting, ClustersChangeNothingWhereNothingIsOccluded) {
  const ShootingPatches set = cube_patches(16);
  const ClosedCube cube;
  const Solution plain = solve(set, cube, 1e-3, 1.0f, 0.0f);
  const Solution clustered = solve(set, cube, 1e-3, 1.0f, 0.3f);
  EXPECT_EQ(plain.stats.shots, clustered.stats.shots);
  EXPECT_EQ(plain.stats.shared_clusters, 0);
  EXPECT_GT(clustered.stats.shared_clusters, 0);
  std::printf("cube 16²×6: %lld rays without clusters, %lld with (%lld shared clusters)\n",
              (long long)plain.stats.visibility_tests, (long long)clustered.stats.visibility_tests,
              (long long)clustered.stats.shared_clusters);
  EXPECT_LT(clustered.stats.visibility_tests, plain.stats.visibility_tests);
  for (size_t i = 0; i < plain.total.size(); ++i)
    ASSERT_EQ(std::memcmp(&plain.total[i], &clustered.total[i], sizeof(Color)), 0) << i;
}

// A shadow edge across a receiver cluster: its probes are its facing members farthest along
// the box's diagonals, i.e. the corners of a rectangular block of receivers, and a linear
// function's extremes over a rectangle lie at its corners. So a straight edge that cuts the
// block leaves probes on both sides and the cluster is refined, down to leaves where every
// receiver gets its own ray: for straight edges across an axis-aligned grid (every cluster of
// a 64×64 grid is a rectangle: median splits of powers of two) the shared visibility is
// exact, whatever the edge's angle. Derived bound 0, checked for four edges at the largest
// ratio allowed (0.5).
TEST(ProgressiveShooting, AStraightShadowEdgeIsRefinedToEveryReceiver) {
  constexpr int kSide = 64;
  std::vector<vec3> positions;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      positions.push_back(vec3((float(x) + 0.5f) / kSide, (float(y) + 0.5f) / kSide, 0.0f));
  const ReceiverClusters tree = build_receiver_clusters(positions);
  const vec3 source(0.5f, 0.5f, 1.5f), down(0.0f, 0.0f, -1.0f);
  auto unoccluded = [&](int32_t i) {
    return shooting_form_factor(source, down, 1e-4f, positions[size_t(i)], vec3(0, 0, 1));
  };
  for (const vec3 edge : {vec3(1.0f, 0.0f, -0.3f), vec3(1.0f, 0.37f, -0.55f),
                          vec3(-0.6f, 1.0f, -0.1f), vec3(1.0f, 1.0f, -1.21f)}) {
    // lit where edge·(x, y, 1) ≥ 0
    auto visible = [&](int32_t i) {
      return glm::dot(edge, vec3(positions[size_t(i)].x, positions[size_t(i)].y, 1.0f)) >= 0.0f;
    };
    auto per_receiver = [&](int32_t i, int64_t* rays) {
      ++*rays;
      return visible(i) ? unoccluded(i) : 0.0f;
    };
    std::vector<float> factor(positions.size(), -1.0f);
    int64_t shared = 0, rays = 0;
    for (const int32_t task : tree.tasks)
      rays += cluster_factors(tree, task, source, down, 0.5f, 0.0f, per_receiver, unoccluded,
                              visible, factor.data(), &shared);
    EXPECT_GT(shared, 0);
    EXPECT_LT(rays, int64_t(positions.size()));
    for (size_t i = 0; i < positions.size(); ++i) {
      int64_t unused = 0;
      ASSERT_EQ(factor[i], per_receiver(int32_t(i), &unused)) << i << " edge " << edge.x;
    }
  }
}

// The form factor's square-root-free point-to-disk form is exact for a receiver point on
// the axis of a disk source facing it: F = R²/(R² + r²) (a disk of radius R at distance r),
// which the seed's point-to-point form A/(πr²) exceeds without bound as r → 0.
TEST(ProgressiveShooting, FormFactorIsExactOnTheAxisOfADisk) {
  const float radius = 0.1f, area = kPi * radius * radius;
  for (const float r : {0.01f, 0.05f, 0.1f, 0.3f, 1.0f, 10.0f}) {
    const float k =
        shooting_form_factor(vec3(0.0f), vec3(0, 0, 1), area, vec3(0, 0, r), vec3(0, 0, -1));
    const double exact = double(radius) * radius / (double(radius) * radius + double(r) * r);
    EXPECT_NEAR(double(k) * area, exact, 1e-6 * exact) << "r = " << r;
  }
}

TEST(ProgressiveShooting, CtrlCStopsTheLoop) {
  const ShootingPatches set = cube_patches(4);
  std::vector<Color> total(set.patches.size()), unshot(set.patches.size(), Color(1.0f));
  ShootingOptions options;
  options.progress = false;
  request_interrupt();
  EXPECT_THROW(shoot_progressively(set, total, unshot, ClosedCube{}, options), Interrupted);
  clear_interrupt();
}

TEST(ProgressiveShooting, RefusesABadThreshold) {
  const ShootingPatches set = cube_patches(2);
  std::vector<Color> total(set.patches.size()), unshot(set.patches.size(), Color(1.0f));
  ShootingOptions options;
  options.progress = false;
  for (double bad : {-1.0, std::nan("")}) {
    options.threshold = bad;
    EXPECT_THROW(shoot_progressively(set, total, unshot, ClosedCube{}, options), Error);
  }
  options.threshold = 1e-3;
  for (double bad : {0.0, 1.5, std::nan("")}) {
    options.relative_threshold = bad;
    EXPECT_THROW(shoot_progressively(set, total, unshot, ClosedCube{}, options), Error);
  }
}

// Two closed unit cubes of albedo a far apart, the second's emission 10⁴× dimmer (the PRT
// DimRoom test's scene, tests/bake/prt_baker_test.cpp). Each cube on its own is the furnace
// above: its exact mean irradiance is E/(1−a). Patches see only their own cube.
ShootingPatches two_cubes(int m, int* first_of_dim) {
  ShootingPatches bright = cube_patches(m), dim = cube_patches(m);
  *first_of_dim = int(bright.patches.size());
  ShootingPatches set = bright;
  set.grid_width = 2 * bright.grid_width;
  set.patch_at.assign(size_t(set.grid_width) * size_t(set.grid_height), -1);
  set.surface_count = 2 * bright.surface_count;
  for (ShootingPatch p : dim.patches) {
    p.position += vec3(100.0f, 0.0f, 0.0f);
    p.x += bright.grid_width;
    p.surface += bright.surface_count;
    set.patches.push_back(p);
  }
  for (size_t i = 0; i < set.patches.size(); ++i)
    set.patch_at[size_t(set.patches[i].y) * size_t(set.grid_width) + size_t(set.patches[i].x)] =
        int32_t(i);
  return set;
}

struct TwoClosedCubes : ClosedCube {
  int first_of_dim = 0;
  const ShootingPatches* set = nullptr;
  bool visible(const ShotSource& s, int receiver) const {
    return (s.centre >= first_of_dim) == (receiver >= first_of_dim);
  }
};

// Measured with the total rule alone (threshold 1e-3): 442 shots, the bright cube's mean
// 0.99911 of exact, the dim cube's 0 (its emission, 10⁻⁴ of the power, is never shot).
//
// Bound with the relative rule τ: the mean relative unshot over both cubes (equal areas) is
// ≤ τ, so the dim cube's is ≤ 2τ. Its patches' unshot U_i = r_i·S_i with S_i (all they were
// given to shoot) ≤ B∞_max, the converged discrete exitance's largest value; with the
// conservation scaling every unit of unshot power adds 1/(1−a) of arrived power once shot,
// so the dim cube's mean irradiance lacks ΔH ≤ 2τ·B∞_max/(1−a). The loop is deterministic
// (exact visibility, conserving form factors): no sampling noise, only float sums (1e-5
// relative, as ClosedCubeMeanIsExactWithinTheThreshold). B∞_max is taken from one cube
// solved to 1e-6.
TEST(ProgressiveShooting, DimRoomBesideABrightOneConvergesToo) {
  int first_of_dim = 0;
  const ShootingPatches set = two_cubes(8, &first_of_dim);
  TwoClosedCubes cubes;
  cubes.first_of_dim = first_of_dim;
  const float bright = 1.0f, dim = 1e-4f;
  std::vector<Color> total(set.patches.size(), Color(0.0f)), unshot(set.patches.size());
  for (size_t i = 0; i < unshot.size(); ++i)
    unshot[i] = Color(int(i) >= first_of_dim ? dim : bright);
  ShootingOptions options;
  options.threshold = 1e-3;
  options.relative_threshold = 0.01;
  options.progress = false;
  const ShootingStats stats = shoot_progressively(set, total, unshot, cubes, options);
  EXPECT_TRUE(stats.converged);
  EXPECT_LE(stats.relative_unshot, options.relative_threshold);
  double sum[2] = {0, 0}, area[2] = {0, 0};
  for (size_t i = 0; i < total.size(); ++i) {
    const int box = int(i) >= first_of_dim;
    sum[box] += double(total[i].x) * set.patches[i].area;
    area[box] += set.patches[i].area;
  }
  const double exact_bright = bright / (1.0 - cubes.albedo), exact_dim = dim / (1.0 - cubes.albedo);
  const double bright_ratio = sum[0] / area[0] / exact_bright;
  const double dim_ratio = sum[1] / area[1] / exact_dim;
  std::printf(
      "shots %lld (%lld by relative unshot), remaining %.3g of initial, relative unshot %.4f; "
      "bright mean/exact %.6f, dim mean/exact %.6f\n",
      (long long)stats.shots, (long long)stats.relative_shots,
      stats.remaining_power / stats.initial_power, stats.relative_unshot, bright_ratio, dim_ratio);

  const Solution reference = solve(cube_patches(8), ClosedCube{}, 1e-6, 1.0f);
  double converged_max = 0.0;  // B∞_max / E
  for (const Color& h : reference.total)
    converged_max = std::max(converged_max, 1.0 + double(cubes.albedo) * double(h.x));
  const double bound = 2.0 * options.relative_threshold * converged_max;  // ΔH / exact
  std::printf("dim cube's derived bound: mean/exact ≥ %.4f (B∞_max/E = %.4f)\n", 1.0 - bound,
              converged_max);
  EXPECT_LE(bright_ratio, 1.0 + 1e-5);
  EXPECT_GE(bright_ratio, 1.0 - options.threshold - 1e-5);
  EXPECT_LE(dim_ratio, 1.0 + 1e-5);
  EXPECT_GE(dim_ratio, 1.0 - bound - 1e-5) << "bound " << bound;
}

}  // namespace
}  // namespace illum::bake
