// Photon map: kd-tree queries against brute force, and the density estimate on photon
// sets with a known density.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "illum/core/error.h"
#include "illum/render/photon_map.h"

namespace illum {
namespace {

std::vector<Photon> random_photons(size_t n, uint32_t seed, bool clustered) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> g(0.0f, 0.05f);
  std::vector<Photon> photons(n);
  for (size_t i = 0; i < n; ++i) {
    Photon& p = photons[i];
    // Clustered sets put half the points in tight blobs (caustic-like) and duplicate a few,
    // which exercises ties and degenerate splits.
    if (clustered && i % 2 == 0) {
      const float c = static_cast<float>((i / 2) % 3) * 0.3f;
      p.position = vec3(c + g(gen), c + g(gen), 0.5f + g(gen));
    } else if (clustered && i % 7 == 1 && i > 1) {
      p.position = photons[i - 1].position;
    } else {
      p.position = vec3(u(gen), u(gen), u(gen));
    }
    p.power = Color(static_cast<float>(i));
  }
  return photons;
}

std::vector<float> brute_distances(const std::vector<Photon>& photons, const vec3& q, float r) {
  std::vector<float> d;
  for (const Photon& p : photons) {
    const vec3 v = p.position - q;
    const float d2 = glm::dot(v, v);
    if (d2 <= r * r) d.push_back(d2);
  }
  std::sort(d.begin(), d.end());
  return d;
}

class PhotonMapQueries : public ::testing::TestWithParam<std::tuple<size_t, bool>> {};

TEST_P(PhotonMapQueries, KnnMatchesBruteForce) {
  const auto [n, clustered] = GetParam();
  const std::vector<Photon> photons = random_photons(n, 7, clustered);
  const PhotonMap map(photons);
  ASSERT_EQ(map.size(), n);
  std::mt19937 gen(11);
  std::uniform_real_distribution<float> u(-0.1f, 1.1f);
  std::vector<PhotonNeighbor> found;
  for (int trial = 0; trial < 200; ++trial) {
    const vec3 q(u(gen), u(gen), u(gen));
    const int k = 1 + trial % 50;
    const float max_r = trial % 3 == 0 ? 0.1f : 10.0f;
    const std::vector<float> truth = brute_distances(photons, q, max_r);
    const float far2 = map.knn(q, k, max_r, &found);
    const size_t expect = std::min(truth.size(), static_cast<size_t>(k));
    ASSERT_EQ(found.size(), expect) << "trial " << trial;
    for (size_t i = 0; i < expect; ++i) {
      // Distances must agree exactly (ties may swap indices, never distances).
      EXPECT_FLOAT_EQ(found[i].distance2, truth[i]) << "trial " << trial << " i " << i;
      const vec3 v = map.photon(found[i].index).position - q;
      EXPECT_FLOAT_EQ(glm::dot(v, v), found[i].distance2);
    }
    if (expect > 0) {
      EXPECT_FLOAT_EQ(far2, truth[expect - 1]);
    }
  }
}

TEST_P(PhotonMapQueries, RadiusMatchesBruteForce) {
  const auto [n, clustered] = GetParam();
  const std::vector<Photon> photons = random_photons(n, 3, clustered);
  const PhotonMap map(photons);
  std::mt19937 gen(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<PhotonNeighbor> found;
  for (int trial = 0; trial < 200; ++trial) {
    const vec3 q(u(gen), u(gen), u(gen));
    const float r = 0.01f + 0.2f * u(gen);
    const std::vector<float> truth = brute_distances(photons, q, r);
    map.radius_search(q, r, &found);
    std::vector<float> got;
    for (const PhotonNeighbor& nb : found) got.push_back(nb.distance2);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, truth) << "trial " << trial;
  }
}

TEST_P(PhotonMapQueries, KeepsEveryPhotonOnce) {
  const auto [n, clustered] = GetParam();
  const PhotonMap map(random_photons(n, 9, clustered));
  std::vector<int> seen(n, 0);
  for (const Photon& p : map.photons()) seen[static_cast<size_t>(p.power.r)]++;
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
}

INSTANTIATE_TEST_SUITE_P(Sizes, PhotonMapQueries,
                         ::testing::Combine(::testing::Values(size_t{0}, size_t{1}, size_t{2},
                                                              size_t{3}, size_t{17}, size_t{1000},
                                                              size_t{20000}),
                                            ::testing::Bool()));

// Photons of power φ uniformly spread on the unit square of a plane (density ρ = N/A): the
// estimate of f·E with f = 1 should give Φ/A. Fixed radius: unbiased. k-NN: the radius is the
// k-th neighbour's distance, so k − 1 photons lie uniformly inside the disc (their weighted
// sum has expectation (k−1)·norm) and one on the rim with weight w(r); since π r² ρ is
// Gamma(k, 1), E[1/(π r²)] = ρ/(k − 1) and E[estimate] = Φ/A · (1 + w(r)/(norm·(k−1))).
// Noise: one estimate's relative standard deviation is √(E[w²])/E[w]/√(photons in disc),
// ≤ 1.5/√n for the three kernels (1, 1.14, 1.2); the mean over M query points with
// (almost) disjoint discs divides that by √M; we accept 4σ (two-sided, p ≈ 6e-5).
TEST(PhotonEstimate, UniformDensityAllFilters) {
  const size_t n = 200000;
  const float total_power = 50.0f;
  std::mt19937 gen(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Photon> photons(n);
  for (Photon& p : photons) {
    p.position = vec3(u(gen), 0.0f, u(gen));
    p.power = Color(total_power / static_cast<float>(n));
    p.normal = vec3(0, 1, 0);
  }
  const PhotonMap map(std::move(photons));
  const float expected = total_power;  // Φ/A with A = 1 m²
  const int k = 100;
  const int m = 400;
  for (PhotonFilter type : {PhotonFilter::kNone, PhotonFilter::kCone, PhotonFilter::kGaussian}) {
    FilterSettings filter;
    filter.type = type;
    std::vector<PhotonNeighbor> scratch;
    double sum = 0.0, sum_fixed = 0.0;
    const float fixed_r = 0.03f;
    for (int i = 0; i < m; ++i) {
      // Query points away from the border so every disc lies inside the square.
      const vec3 q(0.2f + 0.6f * u(gen), 0.0f, 0.2f + 0.6f * u(gen));
      const auto one = [](const Photon&) { return Color(1.0f); };
      sum += estimate_radiance(map, q, k, 1.0f, filter, one, &scratch).g;
      sum_fixed += estimate_radiance(map, q, 0, fixed_r, filter, one, &scratch).g;
    }
    const double knn_mean = sum / m;
    const double fixed_mean = sum_fixed / m;
    const double sigma_knn = 1.5 / std::sqrt(double(k) * m);
    const double n_disc = double(n) * kPi * fixed_r * fixed_r;
    const double sigma_fixed = 1.5 / std::sqrt(n_disc * m);
    const double knn_bias =
        1.0 + filter_weight(filter, 1.0f, 1.0f) / (filter_normalization(filter) * (k - 1));
    EXPECT_NEAR(knn_mean / expected, knn_bias, 4.0 * sigma_knn)
        << "filter " << static_cast<int>(type);
    EXPECT_NEAR(fixed_mean / expected, 1.0, 4.0 * sigma_fixed)
        << "filter " << static_cast<int>(type);
  }
}

TEST(PhotonEstimate, FilterNormalizationIntegratesToOne) {
  for (PhotonFilter type : {PhotonFilter::kNone, PhotonFilter::kCone, PhotonFilter::kGaussian}) {
    FilterSettings filter;
    filter.type = type;
    // Midpoint rule in x = d²/r², where dA/(πr²) = dx.
    const int steps = 100000;
    double integral = 0.0;
    for (int i = 0; i < steps; ++i) {
      const float x = (static_cast<float>(i) + 0.5f) / steps;
      integral += filter_weight(filter, x, 1.0f) / steps;
    }
    EXPECT_NEAR(integral / filter_normalization(filter), 1.0, 1e-4);
    // docs/photon-mapping.md: Jensen's Gaussian constants (α = 0.918, β = 1.953) integrate to
    // 0.531 over the disc, not 1 — the reason the estimate divides by the integral. The
    // midpoint sum above is accurate to far better than the quoted three digits.
    if (type == PhotonFilter::kCone) {
      EXPECT_EQ(filter.cone_k, 1.1f);  // the page's k_c
    }
    if (type == PhotonFilter::kGaussian) {
      EXPECT_EQ(filter.gauss_alpha, 0.918f);
      EXPECT_EQ(filter.gauss_beta, 1.953f);
      EXPECT_NEAR(integral, 0.531, 0.0005);
    }
  }
}

TEST(PhotonEstimate, UnknownFilterIsAnError) {
  EXPECT_THROW(parse_photon_filter("box"), Error);
  EXPECT_EQ(parse_photon_filter("gaussian"), PhotonFilter::kGaussian);
}

}  // namespace
}  // namespace illum
