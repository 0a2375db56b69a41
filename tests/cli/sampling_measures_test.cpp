// The efficiency ceiling of `btf bench sampling` (tools/cli/support/sampling_measures.h): the variance of
// a sampler exactly proportional to f cos, estimated from another sampler's draws, and the
// timings it is made of.
#include <gtest/gtest.h>

#include <memory>

#include "btf/core/math.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/sampling/sampler_choice.h"
#include "sampling_measures.h"

namespace {

TEST(EfficiencyCeiling, AProportionalOwnSamplerIsItsOwnVarianceFloor) {
  // Lambert's own sampler draws cosine-weighted: exactly proportional to f cos, so the estimated
  // proportional variance is its own, to round-off (50,000 draws, theta_o 30 deg).
  const btf::Lambert lambert(btf::Rgb(0.6f));
  const glm::vec3 wo = btf::sphericalDirection(btf::kPi / 6.0f, 0.0f);
  const btf::cli::EfficiencyCeiling c = btf::cli::efficiencyCeiling(lambert, wo, 50'000, 1, 1);
  EXPECT_NEAR(c.variance_ratio, 1.0, 1e-6);
  EXPECT_GT(c.own_seconds, 0.0);
  EXPECT_GT(c.eval_env_seconds, 0.0);
  EXPECT_GT(c.eval_many_seconds, 0.0);
}

TEST(EfficiencyCeiling, AnUnproportionalSamplerLiesAboveTheFloor) {
  // The same Lambert drawn uniformly over the hemisphere: its weight 2 cos varies, and the ratio
  // of its variance to the proportional one is well above 1 (about 1.5 for this environment).
  const auto lambert = std::make_shared<btf::Lambert>(btf::Rgb(0.6f));
  const auto uniform = btf::withSampler(btf::SamplerChoice::Uniform, lambert, {});
  const glm::vec3 wo = btf::sphericalDirection(btf::kPi / 6.0f, 0.0f);
  const btf::cli::EfficiencyCeiling c = btf::cli::efficiencyCeiling(*uniform, wo, 50'000, 1, 1);
  EXPECT_GT(c.variance_ratio, 1.2);
  // And a glossy GGX under cosine draws, further from proportional still.
  const auto ggx = std::make_shared<btf::Ggx>(btf::Rgb(0.0f), btf::Rgb(0.9f), 0.1f, 0.1f);
  const auto cosine = btf::withSampler(btf::SamplerChoice::Cosine, ggx, {});
  EXPECT_GT(btf::cli::efficiencyCeiling(*cosine, wo, 50'000, 1, 1).variance_ratio, 3.0);
}

}  // namespace
