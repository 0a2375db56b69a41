// The warps of sampling/warp.h: each draws directions with exactly the density it reports.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "btf/sampling/chi2.h"
#include "btf/core/warp.h"

namespace {

// Midpoint rule over (theta, phi) with dw = sin(theta) dtheta dphi; independent of the chi-square
// harness's own quadrature so that the two check each other.
double integrateOverSphere(const std::function<double(const glm::vec3&)>& pdf, int theta_steps = 4000,
                           int phi_steps = 64) {
  const double dtheta = std::numbers::pi / theta_steps, dphi = 2.0 * std::numbers::pi / phi_steps;
  double sum = 0.0;
  for (int i = 0; i < theta_steps; ++i) {
    const double theta = (i + 0.5) * dtheta;
    for (int j = 0; j < phi_steps; ++j) {
      const double phi = (j + 0.5) * dphi;
      const glm::vec3 w{static_cast<float>(std::sin(theta) * std::cos(phi)),
                        static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta))};
      sum += pdf(w) * std::sin(theta) * dtheta * dphi;
    }
  }
  return sum;
}

// Every chi-square test here: 1e6 draws, 20 x 40 cells, significance 0.01, fixed seed 1 (so the
// outcome is deterministic; a chance failure would show up at once and for good, not as a flake).
btf::Chi2Result runChi2(const btf::DirectionSampler& sampler, const btf::DirectionPdf& pdf) {
  return btf::chi2Test(sampler, pdf, btf::Chi2Options{});
}

}  // namespace

TEST(Warp, CosineHemispherePassesChi2AndIntegratesToOne) {
  const auto r = runChi2([](glm::vec2 u) { return std::optional(btf::squareToCosineHemisphere(u)); },
                         [](const glm::vec3& w) { return double(btf::cosineHemispherePdf(w)); });
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_NEAR(integrateOverSphere([](const glm::vec3& w) { return btf::cosineHemispherePdf(w); }), 1.0, 1e-5);
}

TEST(Warp, UniformHemispherePassesChi2AndIntegratesToOne) {
  const auto r = runChi2([](glm::vec2 u) { return std::optional(btf::squareToUniformHemisphere(u)); },
                         [](const glm::vec3& w) { return double(btf::uniformHemispherePdf(w)); });
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_NEAR(integrateOverSphere([](const glm::vec3& w) { return btf::uniformHemispherePdf(w); }), 1.0, 1e-5);
}

TEST(Warp, UniformSpherePassesChi2AndIntegratesToOne) {
  const auto r = runChi2([](glm::vec2 u) { return std::optional(btf::squareToUniformSphere(u)); },
                         [](const glm::vec3&) { return double(btf::uniformSpherePdf()); });
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_NEAR(integrateOverSphere([](const glm::vec3&) { return btf::uniformSpherePdf(); }), 1.0, 1e-5);
}

TEST(Warp, CosinePowerLobePassesChi2AndIntegratesToOne) {
  for (const float exponent : {0.0f, 1.0f, 20.0f, 500.0f}) {
    const auto r = runChi2(
        [exponent](glm::vec2 u) { return std::optional(btf::squareToCosinePowerHemisphere(u, exponent)); },
        [exponent](const glm::vec3& w) { return double(btf::cosinePowerHemispherePdf(w, exponent)); });
    EXPECT_TRUE(r.accepted) << "exponent " << exponent << ": " << r.message << " (1e6 draws, alpha = 0.01)";
    EXPECT_NEAR(integrateOverSphere([exponent](const glm::vec3& w) { return btf::cosinePowerHemispherePdf(w, exponent); }),
                1.0, 1e-4)
        << "exponent " << exponent;
  }
}

TEST(Warp, ConcentricDiskStaysInsideTheUnitDisk) {
  for (int i = 0; i <= 64; ++i)
    for (int j = 0; j <= 64; ++j) {
      const glm::vec2 d = btf::squareToConcentricDisk({i / 64.0f, j / 64.0f});
      EXPECT_LE(glm::length(d), 1.0f + 1e-6f) << i << "," << j;
    }
  EXPECT_EQ(btf::squareToConcentricDisk({0.5f, 0.5f}), glm::vec2(0.0f));
}
