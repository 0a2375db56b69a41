// Directional albedo: the Monte Carlo estimator and the half-vector quadrature agree with each
// other and with the exact value of a Lambertian surface.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <memory>
#include <vector>

#include "support/tier.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/material/albedo.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/ward.h"

using btf::Rgb;

TEST(Albedo, LambertIsItsAlbedoExactly) {
  const Rgb albedo(0.8f, 0.5f, 0.2f);
  const btf::Lambert lambert(albedo);
  for (const float degrees : {0.0f, 45.0f, 85.0f}) {
    const glm::vec3 wo = btf::sphericalDirection(glm::radians(degrees), 0.0f);
    // Cosine sampling makes every weight equal to the albedo: no variance at all.
    const btf::AlbedoEstimate mc = btf::estimateAlbedo(lambert, wo, 10'000, 1);
    const Rgb quadrature = btf::integrateAlbedoHalfVector(lambert, glm::radians(degrees));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(mc.value[c], albedo[c], 1e-6f * albedo[c]);
      EXPECT_NEAR(mc.standard_error[c], 0.0f, 1e-6f);
      EXPECT_NEAR(quadrature[c], albedo[c], 1e-4f * albedo[c]) << degrees << " degrees";
    }
  }
}

BTF_STATISTICAL_TEST(Albedo, QuadratureMatchesMonteCarloFromDiffuseToNearMirror) {
  // 400,000 importance-sampled draws (seed 2) against the default 256 x 512 quadrature. The
  // quadrature must be within 0.5% of the estimate, and the estimate itself must be tighter than
  // 0.2% (one standard error), so that a 1% quadrature error would stand out by 5 standard errors.
  std::vector<std::unique_ptr<btf::Material>> materials;
  materials.push_back(std::make_unique<btf::Phong>(Rgb(0.2f), Rgb(0.7f), 8.0f));
  materials.push_back(std::make_unique<btf::Phong>(Rgb(0.0f), Rgb(0.9f), 800.0f));
  materials.push_back(std::make_unique<btf::Lafortune>(
      Rgb(0.0923f, 0.0625f, 0.0311f),
      std::vector<btf::LafortuneLobe>{{Rgb(0.322f, 0.193f, 0.105f), {-0.579f, -0.579f, 0.574f}, 630.0f}}));
  materials.push_back(std::make_unique<btf::Ggx>(Rgb(0.5f), Rgb(0.04f), 0.5f, 0.5f));
  materials.push_back(std::make_unique<btf::Ggx>(Rgb(0.0f), Rgb(0.9f, 0.6f, 0.3f), 0.1f, 0.1f));
  materials.push_back(std::make_unique<btf::Ggx>(Rgb(0.0f), Rgb(0.95f), 0.02f, 0.02f));
  materials.push_back(std::make_unique<btf::Ward>(Rgb(0.1f), Rgb(0.8f), 0.02f, 0.02f));
  for (const auto& m : materials)
    for (const float degrees : {0.0f, 30.0f, 60.0f, 80.0f}) {
      const glm::vec3 wo = btf::sphericalDirection(glm::radians(degrees), 0.0f);
      const btf::AlbedoEstimate mc = btf::estimateAlbedo(*m, wo, 400'000, 2);
      const Rgb quadrature = btf::integrateAlbedoHalfVector(*m, glm::radians(degrees));
      for (int c = 0; c < 3; ++c) {
        EXPECT_LT(mc.standard_error[c], 2e-3f * mc.value[c]) << m->name() << " at " << degrees << " degrees";
        EXPECT_NEAR(quadrature[c], mc.value[c], 5e-3f * mc.value[c])
            << m->name() << " at " << degrees << " degrees, channel " << c << ": Monte Carlo " << mc.value[c]
            << " +- " << mc.standard_error[c] << " (400,000 draws)";
      }
    }
}

TEST(Albedo, EstimateIsDeterministicForASeed) {
  const btf::Ggx ggx(Rgb(0.3f), Rgb(0.04f), 0.2f, 0.2f);
  const glm::vec3 wo = btf::sphericalDirection(glm::radians(50.0f), 0.0f);
  const btf::AlbedoEstimate a = btf::estimateAlbedo(ggx, wo, 50'000, 9);
  const btf::AlbedoEstimate b = btf::estimateAlbedo(ggx, wo, 50'000, 9);
  const btf::AlbedoEstimate c = btf::estimateAlbedo(ggx, wo, 50'000, 10);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.standard_error, b.standard_error);
  EXPECT_NE(a.value, c.value);
}

TEST(Albedo, EstimateDoesNotDependOnTheThreadCount) {
  const btf::Ggx ggx(Rgb(0.3f), Rgb(0.04f), 0.2f, 0.2f);
  const glm::vec3 wo = btf::sphericalDirection(glm::radians(50.0f), 0.0f);
  btf::AlbedoEstimate one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = btf::estimateAlbedo(ggx, wo, 200'000, 9);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = btf::estimateAlbedo(ggx, wo, 200'000, 9);
  }
  EXPECT_EQ(one.value, two.value);
  EXPECT_EQ(one.standard_error, two.standard_error);
}

TEST(Albedo, RejectsInvalidArguments) {
  const btf::Lambert lambert(Rgb(0.5f));
  const btf::Ggx anisotropic(Rgb(0.5f), Rgb(0.04f), 0.1f, 0.3f);
  EXPECT_THROW(btf::estimateAlbedo(lambert, {0, 0, 1}, 1), btf::Error);
  EXPECT_THROW(btf::integrateAlbedoHalfVector(anisotropic, 0.3f), btf::Error);
  EXPECT_THROW(btf::integrateAlbedoHalfVector(lambert, 2.0f), btf::Error);
  EXPECT_THROW(btf::integrateAlbedoHalfVector(lambert, 0.3f, 0, 10), btf::Error);
}
