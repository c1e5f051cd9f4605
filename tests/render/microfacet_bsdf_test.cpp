// Rough (GGX) conductor and dielectric, and the named metals: white furnace, reciprocity,
// sampling against evaluation (pdf and value per sample, a chi-square test of the sampled
// directions), α → 0 against the smooth materials, normal-incidence reflectance of the metals.
// Statistical checks use z-scores from the sample variance (kZ standard errors).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "../core/chi_square.h"
#include "illum/core/sampling.h"
#include "illum/render/bsdf.h"
#include "illum/scene/metals.h"
#include "running_stat.h"

namespace illum {
namespace {

using test::kZ;
using Stat = test::RunningStat;

const Frame kFrame = Frame::from_normal(glm::normalize(vec3(0.3f, 0.9f, -0.2f)));

vec3 direction_at(float theta, float phi = 0.0f) {  // world direction at polar angle θ
  return kFrame.to_world(
      vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
}

// A conductor that reflects everything at every angle: η = 0 (purely imaginary index).
Material white_conductor(float alpha) {
  Material m;
  m.type = MaterialType::kConductor;
  m.eta = Color(0.0f);
  m.k = Color(1.0f);
  m.alpha = alpha;
  return m;
}

Material rough_glass(float alpha, float ior = 1.5f) {
  Material m;
  m.type = MaterialType::kDielectric;
  m.ior = ior;
  m.alpha = alpha;
  return m;
}

// Directional albedo of a GGX surface with F = 1 and Smith height-correlated G2, by midpoint
// quadrature over the half-vector hemisphere in double precision — written here from the
// formulas, independent of bsdf.cpp: E(o) = ∫ D(m) G2(o,i) / (4 cos θo) · ... with
// dωi = 4 |o·m| dωm, so E = ∫ D(m) G2 |o·m| / cos θo dωm over m with o·m > 0 and i.z > 0.
double reference_albedo(double alpha, double theta_o) {
  const double a2 = alpha * alpha;
  const double ox = std::sin(theta_o), oz = std::cos(theta_o);
  auto lambda = [&](double cz) {
    const double t2 = (1.0 - cz * cz) / (cz * cz);
    return 0.5 * (std::sqrt(1.0 + a2 * t2) - 1.0);
  };
  constexpr int kT = 2000, kP = 400;
  double sum = 0.0;
  for (int a = 0; a < kT; ++a) {
    // Substitute cos θm = 1 − s², dense near the pole where narrow lobes live.
    const double s = (a + 0.5) / kT, cm = 1.0 - s * s, dcm = 2.0 * s / kT;
    const double sm = std::sqrt(std::max(0.0, 1.0 - cm * cm));
    const double t = cm * cm * (a2 - 1.0) + 1.0, d = a2 / (std::numbers::pi * t * t);
    for (int b = 0; b < kP; ++b) {
      const double phi = 2.0 * std::numbers::pi * (b + 0.5) / kP;
      const double mx = sm * std::cos(phi), mz = cm;
      const double om = ox * mx + oz * mz;
      if (om <= 0.0) continue;
      const double iz = 2.0 * om * mz - oz;
      if (iz <= 0.0) continue;
      const double g2 = 1.0 / (1.0 + lambda(oz) + lambda(iz));
      sum += d * g2 * om / oz * dcm * (2.0 * std::numbers::pi / kP);
    }
  }
  return sum;
}

TEST(MicrofacetBsdf, NamedMetalsReflectTheirMeasuredColourAtNormalIncidence) {
  // F0 = ((n−1)² + κ²)/((n+1)² + κ²) per channel, computed here in double, against the
  // exact complex Fresnel the smooth conductor uses (its sample weight at normal incidence).
  struct Expect {
    const char* name;
    Color lo, hi;  // the published colour ranges: gold ≈ (1, 0.78, 0.34), silver ≥ 0.9, ...
  };
  const Expect metals[] = {
      {"gold", {0.9f, 0.72f, 0.3f}, {1.0f, 0.85f, 0.45f}},
      {"copper", {0.9f, 0.6f, 0.5f}, {1.0f, 0.72f, 0.6f}},
      {"silver", {0.95f, 0.95f, 0.9f}, {1.0f, 1.0f, 1.0f}},
      {"aluminium", {0.9f, 0.9f, 0.9f}, {0.93f, 0.93f, 0.93f}},
  };
  for (const Expect& e : metals) {
    const auto metal = named_metal(e.name);
    ASSERT_TRUE(metal) << e.name;
    Material m;
    m.type = MaterialType::kConductor;
    m.eta = metal->eta;
    m.k = metal->k;
    const Bsdf smooth(m, Color(1.0f), kFrame, kFrame.n);
    const auto s = smooth.sample(kFrame.n, 0.5f, {0.5f, 0.5f});
    ASSERT_TRUE(s && s->delta) << e.name;
    for (int c = 0; c < 3; ++c) {
      const double n = metal->eta[c], k = metal->k[c];
      const double f0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
      EXPECT_NEAR(s->weight[c], f0, 1e-5) << e.name << " channel " << c;
      EXPECT_GE(f0, e.lo[c]) << e.name << " channel " << c;
      EXPECT_LE(f0, e.hi[c]) << e.name << " channel " << c;
    }
  }
  EXPECT_FALSE(named_metal("unobtainium"));
}

TEST(MicrofacetBsdf, WhiteFurnaceConductorLosesOnlySingleScatteringEnergy) {
  // F = 1: the albedo is what masking-shadowing leaves, ≤ 1, equal to the quadrature of
  // D·G2 above; close to 1 for small α (the known single-scattering loss of GGX grows from
  // under 1 % at α = 0.1 to tens of percent at α = 1 and grazing angles).
  std::mt19937 gen(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kN = 200000;
  for (int c = 0; c < 3; ++c)
    for (const float cos_o : {1.0f, 0.5f, 0.05f})
      ASSERT_NEAR(fresnel_conductor(cos_o, white_conductor(0.5f).eta, white_conductor(0.5f).k)[c],
                  1.0f, 1e-6f);
  for (const float alpha : {0.1f, 0.3f, 0.6f, 1.0f}) {
    const Material m = white_conductor(alpha);
    const Bsdf bsdf(m, Color(1.0f), kFrame, kFrame.n);
    ASSERT_FALSE(bsdf.is_delta());
    for (const float theta : {0.0f, 0.7f, 1.3f, 1.5f}) {
      const vec3 wo = direction_at(theta, 0.4f);
      Stat sampled, uniform;
      for (int i = 0; i < kN; ++i) {
        const auto s = bsdf.sample(wo, u01(gen), {u01(gen), u01(gen)});
        sampled.add(s ? s->weight.g : 0.0f);
      }
      for (int i = 0; i < kN; ++i) {
        const vec3 wi = kFrame.to_world(sample_cosine_hemisphere({u01(gen), u01(gen)}));
        uniform.add(bsdf.eval(wo, wi).g * kPi);  // f cos / (cos/π)
      }
      const double ref = reference_albedo(alpha, theta);
      EXPECT_LE(sampled.mean(), 1.0 + kZ * sampled.standard_error()) << "α " << alpha;
      EXPECT_NEAR(sampled.mean(), ref, kZ * sampled.standard_error() + 2e-3)
          << "α " << alpha << " θ " << theta;
      // Cosine sampling cannot resolve α = 0.1's narrow lobe well; its error bar says so.
      EXPECT_NEAR(uniform.mean(), ref, kZ * uniform.standard_error() + 2e-3)
          << "α " << alpha << " θ " << theta;
      if (alpha <= 0.1f && theta < 1.0f) {
        EXPECT_GT(ref, 0.98) << "θ " << theta;
      }
    }
  }
  // The loss itself where it is large: α = 1 loses a fifth of the energy or more.
  EXPECT_LT(reference_albedo(1.0, 0.0), 0.85);
  EXPECT_LT(reference_albedo(1.0, 1.5), 0.85);
}

TEST(MicrofacetBsdf, RoughDielectricReflectsAndTransmitsAtMostAllTheFlux) {
  // Importance mode (flux, no 1/η² radiance scaling): R + T ≤ 1 from either side, and near 1
  // for small α where few microfacets mask each other.
  std::mt19937 gen(29);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kN = 200000;
  for (const float alpha : {0.05f, 0.3f, 0.7f}) {
    const Material m = rough_glass(alpha);
    const Bsdf bsdf(m, Color(1.0f), kFrame, kFrame.n);
    for (const float theta : {0.0f, 0.8f, 1.4f}) {
      for (const bool outside : {true, false}) {
        const vec3 wo = outside ? direction_at(theta) : -direction_at(theta);
        Stat sampled, uniform;
        for (int i = 0; i < kN; ++i) {
          const auto s =
              bsdf.sample(wo, u01(gen), {u01(gen), u01(gen)}, TransportMode::kImportance);
          sampled.add(s ? s->weight.g : 0.0f);
        }
        for (int i = 0; i < kN; ++i) {
          const vec3 wi = sample_uniform_sphere({u01(gen), u01(gen)});
          uniform.add(bsdf.eval(wo, wi, TransportMode::kImportance).g *
                      std::abs(glm::dot(wi, kFrame.n)) / pdf_uniform_sphere());
        }
        const std::string where = "α " + std::to_string(alpha) + " θ " + std::to_string(theta) +
                                  (outside ? " outside" : " inside");
        EXPECT_LE(sampled.mean(), 1.0 + kZ * sampled.standard_error()) << where;
        EXPECT_NEAR(sampled.mean(), uniform.mean(),
                    kZ * std::hypot(sampled.standard_error(), uniform.standard_error()))
            << where;
        if (alpha <= 0.05f && theta < 1.0f) {
          EXPECT_GT(sampled.mean(), 0.98) << where;
        }
      }
    }
  }
}

TEST(MicrofacetBsdf, Reciprocity) {
  // Conductor f(a,b) = f(b,a). Dielectric: reflection the same; transmission in radiance
  // mode f(o,i)/η_o² = f(i,o)/η_i² (η_x the index on x's side), and the importance-mode
  // BSDF is the radiance-mode one with its arguments swapped (the adjoint).
  std::mt19937 gen(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const Material metal = white_conductor(0.35f);
  const Bsdf conductor(metal, Color(1.0f), kFrame, kFrame.n);
  const Material m = rough_glass(0.35f, 1.5f);
  const Bsdf glass(m, Color(1.0f), kFrame, kFrame.n);
  int transmissions = 0;
  for (int i = 0; i < 4000; ++i) {
    const vec3 a = sample_uniform_sphere({u01(gen), u01(gen)});
    const vec3 b = sample_uniform_sphere({u01(gen), u01(gen)});
    const float cab = conductor.eval(a, b).g, cba = conductor.eval(b, a).g;
    ASSERT_NEAR(cab, cba, 1e-4f * std::max(cab, 1.0f));
    const float fab = glass.eval(a, b).g, fba = glass.eval(b, a).g;
    const float eta_a = glm::dot(a, kFrame.n) > 0.0f ? 1.0f : 1.5f;
    const float eta_b = glm::dot(b, kFrame.n) > 0.0f ? 1.0f : 1.5f;
    ASSERT_NEAR(fab / (eta_a * eta_a), fba / (eta_b * eta_b), 1e-4f * std::max(fab, 1.0f));
    const float iab = glass.eval(a, b, TransportMode::kImportance).g;
    ASSERT_NEAR(iab, fba, 1e-4f * std::max(fba, 1.0f));
    if (eta_a != eta_b && fab > 0.0f) ++transmissions;
  }
  EXPECT_GT(transmissions, 200);  // the pairs exercised refraction, not only reflection
}

TEST(MicrofacetBsdf, SamplesAgreeWithPdfAndEval) {
  std::mt19937 gen(31);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (const Material& m : {white_conductor(0.2f), white_conductor(0.8f), rough_glass(0.2f),
                            rough_glass(0.6f, 1.33f)}) {
    const Bsdf bsdf(m, Color(1.0f), kFrame, kFrame.n);
    for (const float theta : {0.1f, 0.9f, 1.45f}) {
      for (const float side : {1.0f, -1.0f}) {
        const vec3 wo = side * direction_at(theta, 1.0f);
        int samples = 0;
        for (int i = 0; i < 20000; ++i) {
          const auto s = bsdf.sample(wo, u01(gen), {u01(gen), u01(gen)});
          if (!s) continue;
          ++samples;
          ASSERT_FALSE(s->delta);
          // The same quantity through two float code paths (the half vector rebuilt from
          // wi): a relative 1e-3 covers it at these α.
          ASSERT_NEAR(bsdf.pdf(wo, s->wi), s->pdf, 2e-3f * s->pdf + 1e-6f);
          ASSERT_NEAR(bsdf.eval(wo, s->wi).g, s->f.g, 2e-3f * s->f.g + 1e-6f);
          ASSERT_EQ(s->transmission, glm::dot(s->wi, kFrame.n) * glm::dot(wo, kFrame.n) < 0.0f);
        }
        // Rough conductors lose samples below the horizon (up to a third at α = 0.8).
        EXPECT_GT(samples, 10000) << to_string(m.type) << " α " << m.alpha << " θ " << theta;
      }
    }
  }
}

TEST(MicrofacetBsdf, SampledDirectionsFollowPdfChiSquare) {
  // Pearson's test of sampled directions against pdf() integrated over a (cos θ, φ) grid over
  // the whole sphere; failed samples get their own cell with probability 1 − ∫pdf.
  const Frame frame;  // local = world
  const test::Grid grid{40, 32, -1.0, 1.0, -std::numbers::pi, std::numbers::pi};
  std::mt19937 gen(37);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kN = 400000;
  struct Case {
    Material m;
    vec3 wo;
  };
  const Case cases[] = {
      {white_conductor(0.4f), glm::normalize(vec3(0.6f, 0.1f, 0.8f))},
      {white_conductor(0.8f), glm::normalize(vec3(0.9f, 0.0f, 0.2f))},
      {rough_glass(0.4f), glm::normalize(vec3(0.6f, 0.1f, 0.8f))},
      {rough_glass(0.5f), glm::normalize(vec3(0.5f, -0.2f, -0.7f))},  // from inside
  };
  for (const Case& c : cases) {
    const Bsdf bsdf(c.m, Color(1.0f), frame, frame.n);
    std::vector<double> observed(static_cast<size_t>(grid.cell_count()) + 1, 0.0);
    for (int i = 0; i < kN; ++i) {
      const auto s = bsdf.sample(c.wo, u01(gen), {u01(gen), u01(gen)});
      if (!s) {
        observed.back() += 1.0;
        continue;
      }
      const int cell = grid.cell(s->wi.z, std::atan2(s->wi.y, s->wi.x));
      ASSERT_GE(cell, 0);
      observed[static_cast<size_t>(cell)] += 1.0;
    }
    std::vector<double> expected = test::expected_counts(
        grid,
        [&](double cos_t, double phi) {
          const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
          const vec3 wi(static_cast<float>(sin_t * std::cos(phi)),
                        static_cast<float>(sin_t * std::sin(phi)), static_cast<float>(cos_t));
          return static_cast<double>(bsdf.pdf(c.wo, wi));
        },
        kN, 8);
    const double total = std::accumulate(expected.begin(), expected.end(), 0.0);
    expected.push_back(std::max(0.0, kN - total));
    const test::ChiSquareResult r = test::chi_square_test(observed, expected);
    EXPECT_GT(r.p_value, test::kSignificance) << to_string(c.m.type) << " α " << c.m.alpha
                                              << ": chi² " << r.statistic << " dof " << r.dof;
  }
}

TEST(MicrofacetBsdf, SmallAlphaApproachesTheSmoothMaterial) {
  // α = 0.002: 99 % of the samples lie within 0.1 rad of the smooth material's direction
  // (GGX's tail puts P(θm > 0.05) = α²/(α² + 0.05²) ≈ 0.2 % of the normals outside), the
  // conductor's weight is the smooth Fresnel, and the glass reflects with the smooth F.
  std::mt19937 gen(41);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  Material gold;  // the default conductor
  gold.type = MaterialType::kConductor;
  Material rough_gold = gold;
  rough_gold.alpha = 0.002f;
  const Bsdf smooth(gold, Color(1.0f), kFrame, kFrame.n);
  const Bsdf rough(rough_gold, Color(1.0f), kFrame, kFrame.n);
  ASSERT_TRUE(smooth.is_delta());
  ASSERT_FALSE(rough.is_delta());
  const Material smooth_glass_m = rough_glass(0.0f), rough_glass_m = rough_glass(0.002f);
  const Bsdf smooth_glass(smooth_glass_m, Color(1.0f), kFrame, kFrame.n);
  const Bsdf glass(rough_glass_m, Color(1.0f), kFrame, kFrame.n);
  ASSERT_TRUE(smooth_glass.is_delta());
  for (const float theta : {0.2f, 0.8f, 1.2f}) {
    const vec3 wo = direction_at(theta, 0.3f);
    const auto ref = smooth.sample(wo, 0.5f, {0.5f, 0.5f});
    ASSERT_TRUE(ref);
    Stat weight, inside;
    for (int i = 0; i < 20000; ++i) {
      const auto s = rough.sample(wo, u01(gen), {u01(gen), u01(gen)});
      weight.add(s ? s->weight.b : 0.0f);
      inside.add(s && glm::dot(s->wi, ref->wi) > std::cos(0.1f) ? 1.0 : 0.0);
    }
    EXPECT_GT(inside.mean(), 0.99) << "θ " << theta;
    EXPECT_NEAR(weight.mean(), ref->weight.b, 2e-3);
    const auto r = smooth_glass.sample(wo, 0.0f, {0.5f, 0.5f});
    const auto t = smooth_glass.sample(wo, 0.99999f, {0.5f, 0.5f});
    ASSERT_TRUE(r && t);
    Stat reflected, near;
    for (int i = 0; i < 20000; ++i) {
      const auto s = glass.sample(wo, u01(gen), {u01(gen), u01(gen)});
      near.add(s && glm::dot(s->wi, s->transmission ? t->wi : r->wi) > std::cos(0.1f) ? 1.0 : 0.0);
      reflected.add(s && !s->transmission ? 1.0 : 0.0);
    }
    EXPECT_GT(near.mean(), 0.99) << "θ " << theta;
    EXPECT_NEAR(reflected.mean(), r->pdf, kZ * std::sqrt(r->pdf * (1 - r->pdf) / 20000) + 1e-3);
  }
}

}  // namespace
}  // namespace illum
