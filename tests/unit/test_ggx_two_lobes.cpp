// GgxTwoLobes (material/ggx_two_lobes.h): f is the sum of its two Ggx lobes; its sampler's pdf is
// the density of its draws (chi-square, 200,000 draws per view at significance 0.01, fixed seeds);
// the registry and the fit file build it.
#include <gtest/gtest.h>

#include <memory>

#include "btf/core/math.h"
#include "btf/material/albedo.h"
#include "btf/material/ggx.h"
#include "btf/material/ggx_two_lobes.h"
#include "btf/material/registry.h"
#include "btf/sampling/chi2.h"

namespace {

using btf::Rgb;

TEST(GgxTwoLobes, IsTheSumOfItsLobes) {
  const btf::GgxTwoLobes two(Rgb(0.2f, 0.1f, 0.05f), Rgb(0.04f), 0.4f, Rgb(0.6f, 0.5f, 0.3f), 0.03f);
  const btf::Ggx base(Rgb(0.2f, 0.1f, 0.05f), Rgb(0.04f), 0.4f, 0.4f), coat(Rgb(0.0f), Rgb(0.6f, 0.5f, 0.3f), 0.03f, 0.03f);
  for (const float t : {0.0f, 0.4f, 1.1f}) {
    const glm::vec3 wo = btf::sphericalDirection(t, 0.3f), wi = btf::sphericalDirection(0.5f, 3.0f);
    const Rgb f = two.eval(wi, wo), g = base.eval(wi, wo) + coat.eval(wi, wo);
    EXPECT_FLOAT_EQ(f.r, g.r);
    EXPECT_FLOAT_EQ(f.b, g.b);
  }
}

TEST(GgxTwoLobes, SamplesItsPdfAndKeepsItsEnergyBelowOne) {
  const btf::GgxTwoLobes two(Rgb(0.2f, 0.1f, 0.05f), Rgb(0.04f), 0.4f, Rgb(0.6f, 0.5f, 0.3f), 0.05f);
  btf::Chi2Options options;
  options.sample_count = 200'000;
  for (const float theta : {0.0f, 40.0f, 75.0f}) {
    const glm::vec3 wo = btf::sphericalDirection(glm::radians(theta), 0.7f);
    const btf::Chi2Result r = btf::chi2TestMaterial(two, wo, {}, options);
    EXPECT_GT(r.p_value, options.significance) << "theta_o " << theta;
    const Rgb a = btf::integrateAlbedoHalfVector(two, glm::radians(theta));
    EXPECT_LT(a.r, 1.0f);
    EXPECT_GT(a.r, 0.3f);
  }
}

TEST(GgxTwoLobes, TheRegistryBuildsIt) {
  const auto m = btf::createMaterial(btf::MaterialParams::parse(
      R"({"type": "ggx2", "diffuse": 0.1, "f0": 0.04, "alpha": 0.3, "f0_2": [0.9, 0.8, 0.7], "alpha_2": 0.02})", "test"));
  EXPECT_NE(m->name().find("ggx2"), std::string::npos);
}

}  // namespace
