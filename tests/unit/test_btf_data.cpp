// The 81-direction set (core/btf_directions.h) and the in-memory BTF with its comparison
// (io/btf_data.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"
#include "btf/io/btf_data.h"
#include "synthetic_btf_data.h"

namespace btf {
namespace {

TEST(BtfDirections, EightyOneDirectionsInSixRings) {
  const auto& dirs = btfDirections();
  ASSERT_EQ(dirs.size(), 81u);
  const int expected_sizes[6] = {1, 6, 12, 18, 20, 24};
  int index = 0, total = 0;
  for (int ring = 0; ring < kBtfRingCount; ++ring) {
    EXPECT_EQ(btfRingSize(ring), expected_sizes[ring]);
    EXPECT_EQ(btfRingStart(ring), total);
    EXPECT_FLOAT_EQ(btfRingThetaDeg(ring), 15.0f * float(ring));
    total += expected_sizes[ring];
    for (int j = 0; j < btfRingSize(ring); ++j, ++index) {
      const BtfDirection& d = dirs[std::size_t(index)];
      EXPECT_EQ(btfDirectionIndex(ring, j), index);
      EXPECT_EQ(d.ring, ring);
      EXPECT_EQ(d.azimuth, j);
      EXPECT_FLOAT_EQ(d.theta_deg, 15.0f * float(ring));
      EXPECT_NEAR(d.phi_deg, 360.0 * j / expected_sizes[ring], 1e-4);
      // The unit vector matches its angles.
      const double theta = d.theta_deg * M_PI / 180.0, phi = d.phi_deg * M_PI / 180.0;
      EXPECT_NEAR(glm::length(d.w), 1.0, 1e-6);
      EXPECT_NEAR(d.w.z, std::cos(theta), 1e-6);
      EXPECT_NEAR(d.w.x, std::sin(theta) * std::cos(phi), 1e-6);
      EXPECT_NEAR(d.w.y, std::sin(theta) * std::sin(phi), 1e-6);
    }
  }
  EXPECT_EQ(total, kBtfDirectionCount);
}

TEST(BtfDirections, FindEveryDirectionByItsAngles) {
  for (int i = 0; i < kBtfDirectionCount; ++i) {
    const BtfDirection& d = btfDirections()[std::size_t(i)];
    EXPECT_EQ(findBtfDirection(d.theta_deg, d.phi_deg), i);
    // Within half a degree in either angle.
    EXPECT_EQ(findBtfDirection(d.theta_deg + 0.4f, d.phi_deg - 0.4f), i);
    // phi modulo 360, both ways.
    EXPECT_EQ(findBtfDirection(d.theta_deg, d.phi_deg + 360.0f), i);
    EXPECT_EQ(findBtfDirection(d.theta_deg, d.phi_deg - 720.0f), i);
  }
}

TEST(BtfDirections, PhiWrapsAroundNearThreeSixty) {
  // Just below 360 is azimuth 0 of the ring, not an index past its end.
  for (int ring = 1; ring < kBtfRingCount; ++ring) {
    EXPECT_EQ(findBtfDirection(btfRingThetaDeg(ring), 359.7f), btfRingStart(ring)) << ring;
    EXPECT_EQ(findBtfDirection(btfRingThetaDeg(ring), -0.3f), btfRingStart(ring)) << ring;
  }
  EXPECT_EQ(findBtfDirection(75.0f, 345.0f), btfDirectionIndex(5, 23));
}

TEST(BtfDirections, PoleAcceptsAnyAzimuth) {
  for (const float phi : {0.0f, 37.0f, 180.0f, 359.9f, -90.0f, 1234.5f}) EXPECT_EQ(findBtfDirection(0.0f, phi), 0);
  EXPECT_EQ(findBtfDirection(0.3f, 77.0f), 0);
}

TEST(BtfDirections, RejectsAnglesOffTheSet) {
  EXPECT_FALSE(findBtfDirection(7.5f, 0.0f));     // between rings
  EXPECT_FALSE(findBtfDirection(15.6f, 0.0f));    // beyond half a degree
  EXPECT_FALSE(findBtfDirection(90.0f, 0.0f));    // no ring at the horizon
  EXPECT_FALSE(findBtfDirection(-15.0f, 0.0f));   // below the pole
  EXPECT_FALSE(findBtfDirection(15.0f, 30.0f));   // ring 1 has azimuths every 60 degrees
  EXPECT_FALSE(findBtfDirection(75.0f, 7.5f));    // between azimuths of ring 5
  EXPECT_FALSE(findBtfDirection(60.0f, 0.6f));    // beyond half a degree in phi
  EXPECT_FALSE(findBtfDirection(std::numeric_limits<float>::quiet_NaN(), 0.0f));
  EXPECT_FALSE(findBtfDirection(30.0f, std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(findBtfDirection(1e30f, 0.0f));
}

TEST(BtfData, IndexingAndLoadViewLayout) {
  BtfData data(3, 2, "grid");
  EXPECT_EQ(data.width(), 3);
  EXPECT_EQ(data.height(), 2);
  EXPECT_EQ(data.name(), "grid");
  EXPECT_EQ(data.texelCount(), 6u);
  EXPECT_EQ(data.entryCount(), 6u * 81 * 81);
  EXPECT_EQ(data.viewValueCount(0), 6u * 81);
  // A value that encodes its own coordinates, so any mix-up of indices shows.
  for (int v = 0; v < 81; ++v)
    for (int l = 0; l < 81; ++l)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) data.at(x, y, v, l) = Rgb(float(x), float(y), float(v * 100 + l));
  std::vector<Rgb> out;
  for (const int v : {0, 40, 80}) {
    data.loadView(v, out);
    ASSERT_EQ(out.size(), data.viewValueCount(v));
    for (int l = 0; l < 81; ++l)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
          const Rgb expected(float(x), float(y), float(v * 100 + l));
          EXPECT_EQ(out[(std::size_t(l) * 2 + std::size_t(y)) * 3 + std::size_t(x)], expected);
          EXPECT_EQ(data.value(x, y, v, l), expected);
        }
    EXPECT_EQ(data.view(v)[0], Rgb(0.0f, 0.0f, float(v * 100)));
  }
  EXPECT_THROW(data.loadView(-1, out), Error);
  EXPECT_THROW(data.loadView(81, out), Error);
  EXPECT_THROW(BtfData(0, 2), Error);
  EXPECT_THROW(BtfData(2, -1), Error);
}

TEST(BtfData, CopyOfReadsEveryView) {
  const BtfData source = test::makeAnalyticBtf(3, 2, true, "ggx");
  const BtfData copy = BtfData::copyOf(source);
  EXPECT_EQ(copy.name(), "ggx");
  ASSERT_EQ(copy.width(), 3);
  ASSERT_EQ(copy.height(), 2);
  for (int v = 0; v < 81; ++v)
    for (std::size_t i = 0; i < source.viewValueCount(v); ++i) ASSERT_EQ(copy.view(v)[i], source.view(v)[i]);
}

TEST(CompareBtf, IdenticalDataHasZeroError) {
  const BtfData data = test::makeAnalyticBtf(3, 3);
  const BtfErrorStats s = compareBtf(data, BtfData::copyOf(data));
  EXPECT_EQ(s.rel_rmse, 0.0);
  EXPECT_EQ(s.rmse, 0.0);
  EXPECT_TRUE(std::isinf(s.psnr_db));
  EXPECT_EQ(s.entries, data.entryCount());
}

TEST(CompareBtf, ScaleErrorGivesKnownRelRmseAndPsnr) {
  // test = (1 + e) reference: RMSE = e RMS(ref), so rel_rmse = e and psnr = 20 log10(max / (e rms)).
  const BtfData reference = test::makeAnalyticBtf(4, 3);
  const double e = 0.03;
  BtfData test_data(4, 3);
  double sum_sq = 0, max_ref = 0;
  for (int v = 0; v < 81; ++v)
    for (std::size_t i = 0; i < reference.viewValueCount(v); ++i) {
      const Rgb r = reference.view(v)[i];
      test_data.view(v)[i] = Rgb(float(r.r * (1 + e)), float(r.g * (1 + e)), float(r.b * (1 + e)));
      for (int c = 0; c < 3; ++c) {
        sum_sq += double(r[c]) * r[c];
        max_ref = std::max(max_ref, double(r[c]));
      }
    }
  const double rms = std::sqrt(sum_sq / (double(reference.entryCount()) * 3));
  const BtfErrorStats s = compareBtf(reference, test_data);
  EXPECT_NEAR(s.rel_rmse, e, 1e-5);
  EXPECT_NEAR(s.reference_rms, rms, 1e-6 * rms);
  EXPECT_DOUBLE_EQ(s.reference_max, max_ref);
  EXPECT_NEAR(s.rmse, e * rms, 1e-5 * rms);
  EXPECT_NEAR(s.psnr_db, 20 * std::log10(max_ref / (e * rms)), 1e-3);
  // Swapping the roles changes the reference: rel_rmse = e / (1 + e).
  EXPECT_NEAR(compareBtf(test_data, reference).rel_rmse, e / (1 + e), 1e-5);
}

TEST(BtfData, ViewsOfTheWrongLengthAreRejectedNotOverrun) {
  const BtfData good = test::makeAnalyticBtf(2, 2, false);
  EXPECT_THROW(BtfData::copyOf(test::ShortViewSource()), Error);
  EXPECT_THROW(compareBtf(good, test::ShortViewSource()), Error);
  EXPECT_THROW(compareBtf(test::ShortViewSource(), good), Error);
}

TEST(CompareBtf, MismatchedSizesAndZeroReferenceThrow) {
  const BtfData a = test::makeAnalyticBtf(2, 2, false);
  EXPECT_THROW(compareBtf(a, BtfData(2, 3)), Error);
  EXPECT_THROW(compareBtf(a, BtfData(3, 2)), Error);
  EXPECT_THROW(compareBtf(BtfData(2, 2, "zeros"), a), Error);
  try {
    compareBtf(BtfData(2, 2, "zeros"), a);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("zeros"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace btf
