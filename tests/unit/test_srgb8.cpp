// Srgb8 must be a faster srgbEncode/srgbDecode, not a different curve: every output equals the
// pow-based expression it replaces.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "btf/io/image.h"

namespace btf {
namespace {

std::uint8_t referenceCode(float x) { return std::uint8_t(std::lround(srgbEncode(x) * 255.0f)); }

TEST(Srgb8, EncodeAgreesAtEveryThresholdAndItsNeighbours) {
  // The floats where the code steps are the only places a table can disagree with the curve:
  // find each step of the reference by bisection and compare there and one float either side.
  const Srgb8& srgb = Srgb8::instance();
  for (int k = 1; k < 256; ++k) {
    std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      (referenceCode(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
    }
    for (std::uint32_t bits = hi - 2; bits <= hi + 2; ++bits) {
      const float x = std::bit_cast<float>(bits);
      ASSERT_EQ(srgb.encode(x), referenceCode(x)) << "x = " << x << " near the step to code " << k;
    }
  }
}

TEST(Srgb8, EncodeAgreesOnRandomValuesAndOutOfRange) {
  const Srgb8& srgb = Srgb8::instance();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> linear(0.0f, 1.0f);
  std::uniform_int_distribution<std::uint32_t> bits(0, std::bit_cast<std::uint32_t>(1.0f));
  for (int i = 0; i < 200000; ++i) {
    const float x = i % 2 ? linear(rng) : std::bit_cast<float>(bits(rng));  // uniform in value, and in exponent
    ASSERT_EQ(srgb.encode(x), referenceCode(x)) << "x = " << x;
  }
  EXPECT_EQ(srgb.encode(-1.0f), 0);
  EXPECT_EQ(srgb.encode(-0.0f), 0);
  EXPECT_EQ(srgb.encode(2.0f), 255);
  EXPECT_EQ(srgb.encode(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(srgb.encode(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(Srgb8, DecodeIsTheCurveAtEachCode) {
  const Srgb8& srgb = Srgb8::instance();
  for (int k = 0; k < 256; ++k) {
    ASSERT_EQ(srgb.decode(std::uint8_t(k)), srgbDecode(float(k) / 255.0f)) << "code " << k;
    ASSERT_EQ(srgb.encode(srgb.decode(std::uint8_t(k))), k) << "code " << k << " does not survive its round trip";
  }
}

}  // namespace
}  // namespace btf
