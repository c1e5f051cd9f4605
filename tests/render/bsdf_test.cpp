// BSDFs: energy conservation (white furnace per material), reciprocity, sampling that
// agrees with evaluation, Fresnel limits. Statistical checks use z-scores from the sample
// variance (kZ standard errors: a false failure rate below 1e-6 per check).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numeric>
#include <random>
#include <vector>

#include "../core/chi_square.h"
#include "illum/core/sampling.h"
#include "illum/render/bsdf.h"
#include "running_stat.h"

namespace illum {
namespace {

using test::kZ;
using Stat = test::RunningStat;

Material make(MaterialType type, float albedo, float specular, float exponent) {
  Material m;
  m.type = type;
  m.albedo = Color(albedo);
  m.specular = Color(specular);
  m.exponent = exponent;
  return m;
}

struct Case {
  const char* name;
  Material m;
};

std::vector<Case> glossy_cases() {
  return {
      {"lambert-white", make(MaterialType::kLambert, 1.0f, 0.0f, 1.0f)},
      {"lambert-grey", make(MaterialType::kLambert, 0.5f, 0.0f, 1.0f)},
      {"phong-mixed-n10", make(MaterialType::kPhong, 0.3f, 0.7f, 10.0f)},
      {"phong-pure-n1", make(MaterialType::kPhong, 0.0f, 1.0f, 1.0f)},
      {"phong-pure-n50", make(MaterialType::kPhong, 0.0f, 1.0f, 50.0f)},
      {"blinn-mixed-n10", make(MaterialType::kBlinn, 0.3f, 0.7f, 10.0f)},
      {"blinn-pure-n4", make(MaterialType::kBlinn, 0.0f, 1.0f, 4.0f)},
      {"blinn-pure-n50", make(MaterialType::kBlinn, 0.0f, 1.0f, 50.0f)},
  };
}

const Frame kFrame = Frame::from_normal(glm::normalize(vec3(0.3f, 0.9f, -0.2f)));

vec3 direction_at(float theta) {  // world direction at polar angle θ from the normal
  return kFrame.to_world(vec3(std::sin(theta), 0.0f, std::cos(theta)));
}

TEST(Bsdf, WhiteFurnaceAndSamplingAgreeWithEvaluation) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kN = 200000;
  for (const Case& c : glossy_cases()) {
    const Bsdf bsdf(c.m, c.m.albedo, kFrame, kFrame.n);
    for (const float theta : {0.0f, 0.6f, 1.2f, 1.5f}) {
      const vec3 wo = direction_at(theta);
      // ∫ f cos dωi by uniform hemisphere sampling (independent of the BSDF's sampler).
      Stat uniform, sampled;
      for (int i = 0; i < kN; ++i) {
        const vec3 wi = kFrame.to_world(sample_uniform_hemisphere({u01(gen), u01(gen)}));
        const float cos_i = glm::dot(wi, kFrame.n);
        uniform.add(bsdf.eval(wo, wi).g * cos_i / pdf_uniform_hemisphere());
      }
      for (int i = 0; i < kN; ++i) {
        const auto s = bsdf.sample(wo, u01(gen), {u01(gen), u01(gen)});
        if (!s) {
          sampled.add(0.0);
          continue;
        }
        // The sample's pdf and value agree with pdf() and eval(): the same quantity along two
        // float code paths, whose cosines differ by δ ≈ 1e-6; cos^n α turns that into a
        // relative n·δ/cos α (n ≤ 50 here). Measured ≤ 5.1e-4 over these samples.
        ASSERT_NEAR(bsdf.pdf(wo, s->wi), s->pdf, 1e-3f * s->pdf + 1e-6f) << c.name;
        ASSERT_NEAR(bsdf.eval(wo, s->wi).g, s->f.g, 1e-3f * s->f.g + 1e-6f) << c.name;
        ASSERT_FALSE(s->delta);
        sampled.add(s->weight.g);
      }
      const double tol = kZ * std::hypot(uniform.standard_error(), sampled.standard_error());
      EXPECT_NEAR(uniform.mean(), sampled.mean(), tol) << c.name << " θ=" << theta;
      // Energy conservation: albedo ≤ 1 (up to noise).
      EXPECT_LE(uniform.mean(), 1.0 + kZ * uniform.standard_error()) << c.name << " θ=" << theta;
      if (c.m.type == MaterialType::kLambert) {
        EXPECT_NEAR(uniform.mean(), c.m.albedo.g, kZ * uniform.standard_error()) << c.name;
        EXPECT_NEAR(sampled.mean(), c.m.albedo.g, 1e-4) << c.name;  // exact importance sampling
      }
    }
  }
}

TEST(Bsdf, PdfIntegratesToAtMostOne) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (const Case& c : glossy_cases()) {
    const Bsdf bsdf(c.m, c.m.albedo, kFrame, kFrame.n);
    const vec3 wo = direction_at(0.7f);
    Stat s;
    for (int i = 0; i < 200000; ++i) {
      const vec3 wi = sample_uniform_sphere({u01(gen), u01(gen)});
      s.add(bsdf.pdf(wo, wi) / pdf_uniform_sphere());
    }
    EXPECT_LE(s.mean(), 1.0 + kZ * s.standard_error()) << c.name;
    if (c.m.type == MaterialType::kLambert) {
      EXPECT_NEAR(s.mean(), 1.0, kZ * s.standard_error());
    }
  }
}

TEST(Bsdf, Reciprocity) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (const Case& c : glossy_cases()) {
    const Bsdf bsdf(c.m, c.m.albedo, kFrame, kFrame.n);
    for (int i = 0; i < 1000; ++i) {
      const vec3 a = kFrame.to_world(sample_uniform_hemisphere({u01(gen), u01(gen)}));
      const vec3 b = kFrame.to_world(sample_uniform_hemisphere({u01(gen), u01(gen)}));
      const float fab = bsdf.eval(a, b).g, fba = bsdf.eval(b, a).g;
      ASSERT_NEAR(fab, fba, 1e-4f * std::max(fab, 1.0f)) << c.name;
    }
  }
}

TEST(Bsdf, OpaqueIsTwoSidedAndNeverTransmits) {
  const Material m = make(MaterialType::kLambert, 0.8f, 0.0f, 1.0f);
  const Bsdf bsdf(m, m.albedo, kFrame, kFrame.n);
  const vec3 up = direction_at(0.3f), up2 = direction_at(-0.5f);
  EXPECT_GT(bsdf.eval(up, up2).g, 0.0f);
  EXPECT_NEAR(bsdf.eval(-up, -up2).g, bsdf.eval(up, up2).g, 1e-6f);  // back side reflects too
  EXPECT_EQ(bsdf.eval(up, -up2).g, 0.0f);                            // no transmission
  const auto s = bsdf.sample(-up, 0.5f, {0.3f, 0.6f});
  ASSERT_TRUE(s.has_value());
  EXPECT_LT(glm::dot(s->wi, kFrame.n), 0.0f);  // stays on wo's side
}

TEST(Bsdf, FresnelLimits) {
  for (const float eta : {1.33f, 1.5f, 2.4f}) {
    const float r0 = (eta - 1.0f) / (eta + 1.0f);
    EXPECT_NEAR(fresnel_dielectric(1.0f, eta), r0 * r0, 1e-6f);
    EXPECT_NEAR(fresnel_dielectric(-1.0f, eta), r0 * r0, 1e-6f);  // symmetric at normal incidence
    // Grazing: 1 − F ≈ 2 cos θ (1 + η²)/√(η² − 1) (the closed form's linear term), at most
    // 6.3e-4 at cos θ = 1e-4 for these η.
    EXPECT_NEAR(fresnel_dielectric(1e-4f, eta), 1.0f, 1e-3f);
    // Total internal reflection beyond the critical angle, from inside.
    const float cos_c = std::sqrt(1.0f - 1.0f / (eta * eta));
    EXPECT_EQ(fresnel_dielectric(-(cos_c - 0.01f), eta), 1.0f);
    EXPECT_LT(fresnel_dielectric(-(cos_c + 0.01f), eta), 1.0f);
    // A conductor with k = 0 is a dielectric seen from outside.
    for (const float c : {1.0f, 0.7f, 0.3f, 0.05f}) {
      EXPECT_NEAR(fresnel_conductor(c, Color(eta), Color(0.0f)).g, fresnel_dielectric(c, eta),
                  1e-5f);
    }
  }
  // Gold-like conductor: reflectance in [0, 1] everywhere, rising to 1 at grazing, and equal
  // to the textbook complex-index formula, evaluated here in double with std::complex
  // (tolerance: the float evaluation's rounding, a few dozen operations of 6e-8).
  const Material gold;
  const auto reference = [](double c, std::complex<double> n) {
    const std::complex<double> ct = std::sqrt(1.0 - (1.0 - c * c) / (n * n));
    const double rs = std::norm((c - n * ct) / (c + n * ct));
    const double rp = std::norm((n * c - ct) / (n * c + ct));
    return 0.5 * (rs + rp);
  };
  for (float c = 0.0f; c <= 1.0f; c += 0.05f) {
    const Color f = fresnel_conductor(c, gold.eta, gold.k);
    EXPECT_TRUE(f.r >= 0.0f && f.r <= 1.0f && f.g >= 0.0f && f.g <= 1.0f && f.b <= 1.0f);
  }
  for (const float c : {1.0f, 0.7f, 0.3f, 0.05f, 1e-4f})
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(fresnel_conductor(c, gold.eta, gold.k)[ch],
                  reference(c, std::complex<double>(gold.eta[ch], gold.k[ch])), 1e-5)
          << "cos θ " << c << " channel " << ch;
  EXPECT_GT(fresnel_conductor(1e-4f, gold.eta, gold.k).g, 0.999f);
}

TEST(Bsdf, DeltaLobesConserveEnergyAndObeySnell) {
  Material glass;
  glass.type = MaterialType::kDielectric;
  glass.ior = 1.5f;
  const Bsdf bsdf(glass, Color(1.0f), kFrame, kFrame.n);
  for (const float theta : {0.0f, 0.4f, 0.9f, 1.3f}) {
    for (const bool outside : {true, false}) {
      vec3 wo = direction_at(theta);
      if (!outside) wo = -wo;
      const auto r = bsdf.sample(wo, 0.0f, {0.5f, 0.5f}, TransportMode::kImportance);
      const auto t = bsdf.sample(wo, 0.99999f, {0.5f, 0.5f}, TransportMode::kImportance);
      ASSERT_TRUE(r && t);
      EXPECT_TRUE(r->delta && t->delta);
      // Reflection mirrors about the normal.
      EXPECT_NEAR(glm::dot(r->wi, kFrame.n), glm::dot(wo, kFrame.n), 1e-5f);
      const float fr = fresnel_dielectric(glm::dot(wo, kFrame.n), 1.5f);
      if (fr >= 1.0f) {  // TIR: the "refraction" branch also reflects
        EXPECT_FALSE(t->transmission);
        continue;
      }
      // Flux is conserved: F + (1 − F)·T = 1 with T = 1.
      EXPECT_NEAR(r->pdf * r->weight.g + t->pdf * t->weight.g, 1.0f, 1e-5f);
      ASSERT_TRUE(t->transmission);
      EXPECT_LT(glm::dot(t->wi, kFrame.n) * glm::dot(wo, kFrame.n), 0.0f);
      const float sin_o =
          std::sqrt(std::max(0.0f, 1.0f - glm::dot(wo, kFrame.n) * glm::dot(wo, kFrame.n)));
      const float sin_t =
          std::sqrt(std::max(0.0f, 1.0f - glm::dot(t->wi, kFrame.n) * glm::dot(t->wi, kFrame.n)));
      const float eta_o = outside ? 1.0f : 1.5f, eta_t = outside ? 1.5f : 1.0f;
      EXPECT_NEAR(eta_o * sin_o, eta_t * sin_t, 1e-4f);
      // Radiance mode scales by (η_o/η_t)².
      const auto tr = bsdf.sample(wo, 0.99999f, {0.5f, 0.5f}, TransportMode::kRadiance);
      EXPECT_NEAR(tr->weight.g, (eta_o * eta_o) / (eta_t * eta_t), 1e-5f);
    }
  }
  Material mirror;
  mirror.type = MaterialType::kMirror;
  mirror.specular = Color(0.9f);
  const Bsdf m(mirror, Color(1.0f), kFrame, kFrame.n);
  const auto s = m.sample(direction_at(0.5f), 0.3f, {0.1f, 0.2f});
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->weight.g, 0.9f, 1e-6f);
  EXPECT_EQ(m.eval(direction_at(0.5f), s->wi).g, 0.0f);  // delta: eval is zero
}

TEST(Bsdf, SampledDirectionsFollowPdfChiSquare) {
  // Pearson's test of BSDF-sampled directions against pdf() integrated over a (cos θ, φ)
  // grid (solid angle = d cos θ dφ, so pdf needs no Jacobian); failed samples (directions
  // below the surface) get their own cell with the remaining probability 1 − ∫pdf.
  const Frame frame;  // local = world
  const test::Grid grid{16, 32, 0.0, 1.0, -std::numbers::pi, std::numbers::pi};
  std::mt19937 gen(23);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const std::vector<Case> cases = {
      {"lambert", make(MaterialType::kLambert, 0.8f, 0.0f, 1.0f)},
      {"phong-mixed-n8", make(MaterialType::kPhong, 0.4f, 0.5f, 8.0f)},
      {"phong-pure-n3", make(MaterialType::kPhong, 0.0f, 1.0f, 3.0f)},
      {"blinn-mixed-n8", make(MaterialType::kBlinn, 0.4f, 0.5f, 8.0f)},
      {"blinn-pure-n3", make(MaterialType::kBlinn, 0.0f, 1.0f, 3.0f)},
  };
  constexpr int kN = 200000;
  for (const Case& c : cases) {
    const Bsdf bsdf(c.m, c.m.albedo, frame, frame.n);
    const vec3 wo = glm::normalize(vec3(0.6f, 0.1f, 0.8f));
    std::vector<double> observed(static_cast<size_t>(grid.cell_count()) + 1, 0.0);
    for (int i = 0; i < kN; ++i) {
      const auto smp = bsdf.sample(wo, u01(gen), {u01(gen), u01(gen)});
      if (!smp) {
        observed.back() += 1.0;
        continue;
      }
      const int cell = grid.cell(smp->wi.z, std::atan2(smp->wi.y, smp->wi.x));
      ASSERT_GE(cell, 0) << c.name;
      observed[static_cast<size_t>(cell)] += 1.0;
    }
    std::vector<double> expected = test::expected_counts(
        grid,
        [&](double cos_t, double phi) {
          const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
          const vec3 wi(static_cast<float>(sin_t * std::cos(phi)),
                        static_cast<float>(sin_t * std::sin(phi)), static_cast<float>(cos_t));
          return static_cast<double>(bsdf.pdf(wo, wi));
        },
        kN, 8);
    const double total = std::accumulate(expected.begin(), expected.end(), 0.0);
    expected.push_back(std::max(0.0, kN - total));
    const test::ChiSquareResult r = test::chi_square_test(observed, expected);
    EXPECT_GT(r.p_value, test::kSignificance)
        << c.name << ": chi² " << r.statistic << " dof " << r.dof;
  }
}

}  // namespace
}  // namespace illum
