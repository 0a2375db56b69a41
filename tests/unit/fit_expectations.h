// Expectations shared by the fit tests: a GGX fit that found the parameters of its data.
#pragma once

#include <gtest/gtest.h>

#include "btf/core/rgb.h"
#include "btf/fit/analytic_fit.h"

namespace btf::test {

// alpha, kd and f0 each within `tolerance` of their value, relatively.
inline void expectGgxRecovered(const AnalyticParameters& p, const Rgb& kd, const Rgb& f0, float alpha, float tolerance) {
  EXPECT_NEAR(p.alpha, alpha, tolerance * alpha);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(p.diffuse[c], kd[c], tolerance * kd[c]) << "kd, channel " << c;
    EXPECT_NEAR(p.specular[c], f0[c], tolerance * f0[c]) << "f0, channel " << c;
  }
}

}  // namespace btf::test
