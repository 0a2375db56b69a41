// Core math: the half/diff transform, shading frames, spherical coordinates and the RNG.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "btf/core/frame.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/core/warp.h"

namespace btf {
namespace {

// Distance between two directions, the quantity the round-trip tolerances bound.
float distance(const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b); }

glm::vec3 direction(float theta, float phi) { return sphericalDirection(theta, phi); }

// Random pairs above the horizon plus the cases that stress the transform: both directions near
// the normal (h at the pole, where phi_h is degenerate), grazing directions, and mirror pairs.
std::vector<DirectionPair> testPairs() {
  std::vector<DirectionPair> pairs;
  Rng rng(7);
  for (int n = 0; n < 20000; ++n)
    pairs.push_back({squareToUniformHemisphere(rng.uniform2D()), squareToUniformHemisphere(rng.uniform2D())});
  for (int n = 0; n < 2000; ++n) {
    const float phi_i = kTwoPi * rng.uniform(), phi_o = kTwoPi * rng.uniform();
    pairs.push_back({direction(1e-3f * rng.uniform(), phi_i), direction(1e-3f * rng.uniform(), phi_o)});  // near normal
    pairs.push_back({direction(kHalfPi - 1e-3f * rng.uniform(), phi_i), direction(kHalfPi - 1e-3f * rng.uniform(), phi_o)});  // grazing
    pairs.push_back({direction(kHalfPi - 1e-3f, phi_i), direction(0.5f * rng.uniform(), phi_o)});  // one grazing
    const float theta = kHalfPi * rng.uniform();
    pairs.push_back({direction(theta, phi_i), direction(theta, phi_i + kPi)});  // mirror: h at the pole
  }
  return pairs;
}

TEST(HalfDiff, RoundTripRecoversBothDirectionsTo1e5) {
  float worst = 0;
  DirectionPair worst_pair{};
  int failures = 0;
  const std::vector<DirectionPair> pairs = testPairs();
  for (const DirectionPair& p : pairs) {
    const DirectionPair back = fromHalfDiff(toHalfDiff(p.wi, p.wo));
    const float error = std::max(distance(back.wi, p.wi), distance(back.wo, p.wo));
    failures += error >= 1e-5f;
    if (error > worst) {
      worst = error;
      worst_pair = p;
    }
  }
  RecordProperty("worst_distance", std::to_string(worst));
  EXPECT_LT(worst, 1e-5f) << failures << " of " << pairs.size() << " pairs fail; worst: wi (" << worst_pair.wi.x
                          << ", " << worst_pair.wi.y << ", " << worst_pair.wi.z << ") wo (" << worst_pair.wo.x << ", "
                          << worst_pair.wo.y << ", " << worst_pair.wo.z << ")";
}

TEST(HalfDiff, EqualDirectionsGiveZeroThetaDiffAndHalfVectorEqualToThem) {
  Rng rng(11);
  for (int n = 0; n < 1000; ++n) {
    const glm::vec3 w = squareToUniformHemisphere(rng.uniform2D());
    const HalfDiff hd = toHalfDiff(w, w);
    // theta_d comes from acos of a value rounded to within 1 ulp of 1, which is 3.5e-4 rad.
    EXPECT_LT(hd.theta_d, 5e-4f);
    EXPECT_LT(distance(direction(hd.theta_h, hd.phi_h), w), 1e-5f);
  }
}

TEST(HalfDiff, KnownValues) {
  // A mirror pair in the xz-plane: h is the normal, d is wi itself.
  const float a = 0.7f;
  // phi_h is arbitrary there (h_xy is rounding noise), but phi_h + phi_d is wi's azimuth, 0.
  HalfDiff hd = toHalfDiff(direction(a, 0), direction(a, kPi));
  EXPECT_NEAR(hd.theta_h, 0, 1e-5f);
  EXPECT_NEAR(hd.theta_d, a, 1e-5f);
  EXPECT_NEAR(std::sin(hd.phi_h + hd.phi_d), 0, 1e-5f);
  EXPECT_GT(std::cos(hd.phi_h + hd.phi_d), 0);
  // Light at angle a in the xz-plane, view along the normal: h halfway, d at a/2 towards +x.
  hd = toHalfDiff(direction(a, 0), glm::vec3(0, 0, 1));
  EXPECT_NEAR(hd.theta_h, a / 2, 1e-5f);
  EXPECT_NEAR(hd.theta_d, a / 2, 1e-5f);
  EXPECT_NEAR(std::sin(hd.phi_h), 0, 1e-5f);
  EXPECT_NEAR(std::sin(hd.phi_d), 0, 1e-5f);
  // Swapping wi and wo keeps theta_h, theta_d and turns phi_d by pi (the reciprocity MERL uses).
  const glm::vec3 wi = direction(0.4f, 1.0f), wo = direction(1.1f, 2.5f);
  const HalfDiff forward = toHalfDiff(wi, wo), backward = toHalfDiff(wo, wi);
  EXPECT_NEAR(forward.theta_h, backward.theta_h, 1e-5f);
  EXPECT_NEAR(forward.theta_d, backward.theta_d, 1e-5f);
  EXPECT_NEAR(std::cos(forward.phi_d - backward.phi_d), -1.0f, 1e-5f);
}

void expectOrthonormalRightHanded(const Frame& f) {
  EXPECT_NEAR(glm::length(f.s), 1, 1e-5f);
  EXPECT_NEAR(glm::length(f.t), 1, 1e-5f);
  EXPECT_NEAR(glm::length(f.n), 1, 1e-5f);
  EXPECT_NEAR(glm::dot(f.s, f.t), 0, 1e-5f);
  EXPECT_NEAR(glm::dot(f.s, f.n), 0, 1e-5f);
  EXPECT_NEAR(glm::dot(f.t, f.n), 0, 1e-5f);
  EXPECT_LT(distance(glm::cross(f.s, f.t), f.n), 1e-5f);
}

TEST(Frame, FromNormalIsOrthonormalAndRoundTrips) {
  Rng rng(3);
  std::vector<glm::vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, glm::normalize(glm::vec3(1e-4f, 0, -1))};
  for (int n = 0; n < 2000; ++n) normals.push_back(squareToUniformSphere(rng.uniform2D()));
  for (const glm::vec3& normal : normals) {
    const Frame f = Frame::fromNormal(normal);
    expectOrthonormalRightHanded(f);
    EXPECT_LT(distance(f.n, normal), 1e-6f);
    const glm::vec3 w = squareToUniformSphere(rng.uniform2D());
    EXPECT_LT(distance(f.toWorld(f.toLocal(w)), w), 1e-5f);
    EXPECT_LT(distance(f.toLocal(f.toWorld(w)), w), 1e-5f);
    EXPECT_NEAR(f.toLocal(normal).z, 1, 1e-5f);
  }
}

TEST(Frame, FromNormalTangentKeepsTheTangentDirection) {
  Rng rng(4);
  for (int n = 0; n < 1000; ++n) {
    const glm::vec3 normal = squareToUniformSphere(rng.uniform2D());
    const glm::vec3 tangent = squareToUniformSphere(rng.uniform2D());
    const Frame f = Frame::fromNormalTangent(normal, tangent);
    expectOrthonormalRightHanded(f);
    const glm::vec3 projected = tangent - glm::dot(tangent, normal) * normal;
    if (glm::length(projected) > 1e-3f) {
      EXPECT_LT(distance(f.s, glm::normalize(projected)), 1e-4f);
    }
  }
}

TEST(Spherical, CartesianToSphericalAndBackRoundTrips) {
  Rng rng(5);
  std::vector<glm::vec3> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  for (int n = 0; n < 20000; ++n) dirs.push_back(squareToUniformSphere(rng.uniform2D()));
  for (const glm::vec3& w : dirs) {
    const float theta = sphericalTheta(w), phi = sphericalPhi(w);
    EXPECT_GE(theta, 0);
    EXPECT_LE(theta, kPi);
    EXPECT_GE(phi, 0);
    EXPECT_LT(phi, kTwoPi);
    EXPECT_LT(distance(direction(theta, phi), w), 1e-5f);
  }
}

TEST(Spherical, SphericalToCartesianAndBackRoundTrips) {
  Rng rng(6);
  for (int n = 0; n < 20000; ++n) {
    // Away from the poles, where phi is undefined and theta is ill-conditioned in float.
    const float theta = 0.01f + (kPi - 0.02f) * rng.uniform(), phi = kTwoPi * rng.uniform();
    const glm::vec3 w = direction(theta, phi);
    EXPECT_NEAR(glm::length(w), 1, 1e-6f);
    EXPECT_NEAR(sphericalTheta(w), theta, 1e-4f);
    EXPECT_NEAR(std::cos(sphericalPhi(w) - phi), 1, 1e-6f);
  }
}

TEST(Rng, SameSeedAndStreamGiveTheSameSequence) {
  Rng a(42, 9), b(42, 9);
  for (int n = 0; n < 1000; ++n) ASSERT_EQ(a.nextU64(), b.nextU64());
  // seek() makes the sequence addressable: position 500 again gives the same value.
  Rng c(42, 9);
  c.seek(500);
  Rng d(42, 9);
  for (int n = 0; n < 500; ++n) d.nextU64();
  EXPECT_EQ(c.nextU64(), d.nextU64());
}

TEST(Rng, DifferentStreamsAndSeedsDiffer) {
  Rng a(42, 0), b(42, 1), c(43, 0);
  int equal_ab = 0, equal_ac = 0;
  for (int n = 0; n < 1000; ++n) {
    const std::uint64_t x = a.nextU64();
    equal_ab += x == b.nextU64();
    equal_ac += x == c.nextU64();
  }
  // Independent 64-bit values coincide with probability 2^-64 each.
  EXPECT_EQ(equal_ab, 0);
  EXPECT_EQ(equal_ac, 0);
}

TEST(Rng, UniformIsInUnitIntervalWithTheRightMeanAndVariance) {
  // N = 10^6 draws. Mean of U[0,1): 1/2, standard error sqrt(1/12 / N) = 2.9e-4. Variance 1/12,
  // standard error sqrt((1/80 - 1/144) / N) = 7.5e-5. Bounds at 5 standard errors: a correct
  // generator fails each with probability 6e-7.
  constexpr int kN = 1'000'000;
  Rng rng(1234, 5);
  double sum = 0, sum2 = 0;
  for (int n = 0; n < kN; ++n) {
    const float u = rng.uniform();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    sum += u;
    sum2 += double(u) * u;
  }
  const double mean = sum / kN, variance = sum2 / kN - mean * mean;
  EXPECT_NEAR(mean, 0.5, 5 * 2.9e-4);
  EXPECT_NEAR(variance, 1.0 / 12.0, 5 * 7.5e-5);
}

}  // namespace
}  // namespace btf
