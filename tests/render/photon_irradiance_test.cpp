// Precomputed irradiance (photon_irradiance.h) against uniform photon densities with known
// answers: the value stored at a photon, and the side a lookup reads on a two-sided wall.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "illum/render/photon_irradiance.h"

namespace illum {
namespace {

// n photons uniform on the unit square y = 0, arriving from +y with power `from_above`
// in all, and as many from −y with `from_below` in all (0: none).
std::vector<Photon> uniform_square(size_t n, float from_above, float from_below, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Photon> photons;
  for (const auto& [total, wi] :
       {std::pair{from_above, vec3(0, 1, 0)}, std::pair{from_below, vec3(0, -1, 0)}}) {
    if (total <= 0.0f) continue;
    for (size_t i = 0; i < n; ++i) {
      Photon p;
      p.position = vec3(u(gen), 0.0f, u(gen));
      p.wi = wi;
      p.power = Color(total / static_cast<float>(n));
      p.normal = vec3(0, 1, 0);
      photons.push_back(p);
    }
  }
  return photons;
}

TEST(PrecomputedIrradiance, UniformDensityWithTheKnnBiasOfKMinusOnePhotons) {
  // E = Φ/A = 50 W/m² from above. Each stored value is a k-NN estimate at a photon that
  // leaves that photon out: by Slivnyak's theorem the others are a Poisson process as seen
  // from any point, so the expected value is E·(1 + w(r)/(norm·(k'−1))) with k' = k − 1
  // (PhotonEstimate.UniformDensityAllFilters). Points whose discs are disjoint are
  // independent; their relative spread is ≈ 1.5/√k' per point (as in that test), so the
  // mean over m of them is within 4·1.5/√(k'm) of the expectation.
  const float total = 50.0f;
  const int k = 100;
  FilterSettings cone;
  const PhotonMap map(uniform_square(80000, total, 0.0f, 3));
  const PhotonMap points = precompute_irradiance(map, 4, k, 1.0f, cone);
  ASSERT_EQ(points.size(), 20000u);
  // The k-NN disc holds k photons: radius √(k/(πn)) ≈ 0.02; keep points ≥ 0.05 from the
  // border and from each other (greedy), so the discs are inside and disjoint.
  std::vector<vec3> kept;
  double sum = 0.0;
  for (const Photon& p : points.photons()) {
    if (p.position.x < 0.05f || p.position.x > 0.95f || p.position.z < 0.05f ||
        p.position.z > 0.95f)
      continue;
    bool far = true;
    for (const vec3& q : kept) far = far && glm::distance(q, p.position) >= 0.05f;
    if (!far) continue;
    kept.push_back(p.position);
    EXPECT_EQ(p.wi, vec3(0, 1, 0));
    sum += p.power.g;
  }
  ASSERT_GE(kept.size(), 200u);
  const int kp = k - 1;
  const double expected =
      total * (1.0 + filter_weight(cone, 1.0f, 1.0f) / (filter_normalization(cone) * (kp - 1)));
  const double m = static_cast<double>(kept.size());
  EXPECT_NEAR(sum / m / expected, 1.0, 4.0 * 1.5 / std::sqrt(kp * m))
      << "mean stored irradiance " << sum / m << " over " << m << " points, expected " << expected;
}

TEST(PrecomputedIrradiance, LookupReadsTheSideFacingTheViewer) {
  // A wall lit from both sides, 40 W/m² from above and 10 W/m² from below: a lookup with wo
  // above the wall reads ≈ 40, below ≈ 10 (each within 4·1.5/√k relative, one point's
  // spread); a surface facing a different way finds nothing.
  const int k = 100;
  const PhotonMap map(uniform_square(40000, 40.0f, 10.0f, 5));
  const PhotonMap points = precompute_irradiance(map, 4, k, 1.0f, FilterSettings{});
  std::vector<PhotonNeighbor> scratch;
  const vec3 p(0.5f, 0.0f, 0.5f), up(0, 1, 0);
  const double tol = 4.0 * 1.5 / std::sqrt(k - 1.0);
  const std::optional<Color> above = lookup_irradiance(points, p, up, up, 0.2f, &scratch);
  const std::optional<Color> below = lookup_irradiance(points, p, up, -up, 0.2f, &scratch);
  ASSERT_TRUE(above && below);
  EXPECT_NEAR(above->g / 40.0, 1.0, tol) << above->g;
  EXPECT_NEAR(below->g / 10.0, 1.0, tol) << below->g;
  // Tilted 73° from the wall, viewed from the side the upper photons came from: only the
  // normal agreement (cos ≥ 0.7) rejects the points.
  const vec3 tilted = glm::normalize(vec3(1.0f, 0.3f, 0.0f));
  EXPECT_FALSE(lookup_irradiance(points, p, tilted, tilted, 0.2f, &scratch));
}

}  // namespace
}  // namespace illum
