// Stored precision of VQ codes (src/compress/vq_impl.h): scales and level-1 values are rounded to
// the coarsest power-of-two step whose rounding stays within epsilon / 16, with the full 16 bits
// at epsilon 0, where files decode as they always did.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "btf/core/rng.h"
#include "compress/vq_impl.h"

namespace {

constexpr float kEpsilons[] = {0.0f, 0.001f, 0.005f, 0.01f, 0.02f, 0.05f, 0.1f, 0.2f, 0.3f, 0.5f, 0.9f};

// The rounding a level may add (vq_btf.h): epsilon / 16, or the 16-bit codes' own when finer.
double allowedScaleRounding(float epsilon) { return std::max(double(epsilon) / 16.0, 0.00034); }
double allowedValueRounding(float epsilon) { return std::max(double(epsilon) / 16.0, std::sqrt(24.0) * 0.5 / 65535.0 + 1e-7); }

}  // namespace

TEST(VqPrecision, ScaleRoundingStaysWithinASixteenthOfTheTolerance) {
  btf::Rng rng(5);
  for (float epsilon : kEpsilons) {
    SCOPED_TRACE("epsilon " + std::to_string(epsilon));
    const int shift = btf::vqPrecisionFor(epsilon, btf::BtfRingLayout::ubo2003().maxSize()).scale_shift;
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      const float s = float(std::exp2(rng.uniformDouble() * 40.0 - 20.0));
      const std::uint16_t q = btf::encodeVqScale(s, shift);
      EXPECT_EQ(q % (1u << shift), 0u);
      worst = std::max(worst, std::abs(double(btf::decodeVqScale(q)) / s - 1.0));
    }
    EXPECT_LE(worst, allowedScaleRounding(epsilon) * (1.0 + 1e-5));
    // Coarse enough to matter: half the allowance or more is used (the next shift would exceed it).
    if (shift < 10) {
      EXPECT_GT(worst, 0.25 * allowedScaleRounding(epsilon));
    }
  }
}

TEST(VqPrecision, LevelOneEntryRoundingStaysWithinASixteenthOfTheTolerance) {
  btf::Rng rng(6);
  for (float epsilon : kEpsilons) {
    SCOPED_TRACE("epsilon " + std::to_string(epsilon));
    const int shift = btf::vqPrecisionFor(epsilon, btf::BtfRingLayout::ubo2003().maxSize()).value_shift;
    double worst = 0;
    for (int i = 0; i < 5000; ++i) {
      // A unit vector of 24 non-negative values, the largest ring's.
      std::vector<double> u(24);
      double len = 0;
      for (double& x : u) {
        x = rng.uniformDouble();
        len += x * x;
      }
      double err = 0;
      for (double& x : u) {
        x /= std::sqrt(len);
        const std::uint16_t q = btf::encodeVqEntryValue(float(x), shift);
        if (q != 65535) {
          EXPECT_EQ(q % (1u << shift), 0u);
        }
        const double d = double(btf::decodeVqEntryValue(q)) - x;
        err += d * d;
      }
      worst = std::max(worst, std::sqrt(err));
    }
    EXPECT_LE(worst, allowedValueRounding(epsilon));
  }
}

TEST(VqPrecision, ZeroToleranceKeepsEvery16BitCode) {
  const btf::VqPrecision p = btf::vqPrecisionFor(0.0f, btf::BtfRingLayout::ubo2003().maxSize());
  EXPECT_EQ(p.scale_shift, 0);
  EXPECT_EQ(p.value_shift, 0);
  // Shift 0 is the encoding files were always written with.
  for (float v : {0.0f, 1e-6f, 0.1f, 0.33333f, 0.5f, 0.999999f, 1.0f})
    EXPECT_EQ(btf::encodeVqEntryValue(v, 0), std::uint16_t(std::lround(v * 65535.0f))) << v;
  EXPECT_EQ(btf::encodeVqEntryValue(1.0f, 9), 65535);  // 1 stays exact at any step
  // Coarser with the tolerance, never finer.
  btf::VqPrecision last = p;
  for (float epsilon : kEpsilons) {
    const btf::VqPrecision q = btf::vqPrecisionFor(epsilon, btf::BtfRingLayout::ubo2003().maxSize());
    EXPECT_GE(q.scale_shift, last.scale_shift);
    EXPECT_GE(q.value_shift, last.value_shift);
    last = q;
  }
  EXPECT_GE(btf::vqPrecisionFor(0.2f, btf::BtfRingLayout::ubo2003().maxSize()).scale_shift, 4);
  EXPECT_GE(btf::vqPrecisionFor(0.2f, btf::BtfRingLayout::ubo2003().maxSize()).value_shift, 7);
}
