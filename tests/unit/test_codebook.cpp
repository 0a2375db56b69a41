// The FLANN-searched codebook (compress/codebook.h): the reuse radius, agreement of the exact
// FLANN radius search with a linear scan while the codebook grows and its segments merge, and what
// the approximate (visit-limited) and restricted (first) searches may return.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "btf/compress/codebook.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"

namespace {

std::vector<float> unitAtAngle(float angle) {  // in the plane of the first two axes, dimension 6
  std::vector<float> v(6, 0.0f);
  v[0] = std::cos(angle);
  v[1] = std::sin(angle);
  return v;
}

}  // namespace

TEST(Codebook, ReusesAnEntryExactlyWhenTheLeastSquaresErrorIsWithinEpsilon) {
  const float epsilon = 0.05f;
  btf::Codebook book(6);
  book.add(unitAtAngle(0.0f));
  const float radius = btf::Codebook::chordRadius(epsilon);
  std::vector<btf::Codebook::Match> found;
  // Relative least-squares error of fitting a unit vector at angle a with entry 0 is sin(a).
  book.search(unitAtAngle(std::asin(epsilon) * 0.98f), radius, 1, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].index, 0u);
  book.search(unitAtAngle(std::asin(epsilon) * 1.02f), radius, 1, found);
  EXPECT_TRUE(found.empty());
  // A scaled entry is the same direction.
  std::vector<float> scaled = unitAtAngle(0.5f);
  for (float& x : scaled) x *= 7.0f;
  EXPECT_EQ(book.add(scaled), 1u);
  book.search(unitAtAngle(0.5f), radius, 2, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].index, 1u);
  EXPECT_LT(found[0].distance, 1e-3f);
  EXPECT_THROW(btf::Codebook(0), btf::Error);
  EXPECT_THROW(book.add(std::vector<float>(5, 1.0f)), btf::Error);
}

TEST(Codebook, FlannAgreesWithBruteForceWhileGrowingOneByOne) {
  // 3000 random non-negative directions in 12 dimensions, clustered so that radius searches find
  // several entries; 20 queries at 3 radii after every 100 insertions. index() after every
  // insertion (it builds a segment per 64 entries and merges them), except for the last 30 of each
  // hundred, so that searches see segments and unindexed entries together.
  btf::Rng rng(11);
  const int dim = 12;
  std::vector<std::vector<float>> centres(20, std::vector<float>(dim));
  for (auto& c : centres)
    for (float& x : c) x = rng.uniform();
  auto randomUnit = [&] {
    const auto& c = centres[std::size_t(rng.uniform() * 20.0f) % 20];
    std::vector<float> v(dim);
    double n = 0;
    for (int k = 0; k < dim; ++k) {
      v[std::size_t(k)] = c[std::size_t(k)] + 0.05f * rng.uniform();
      n += double(v[std::size_t(k)]) * v[std::size_t(k)];
    }
    for (float& x : v) x = float(x / std::sqrt(n));
    return v;
  };
  btf::Codebook book(dim);
  std::vector<btf::Codebook::Match> flann, brute;
  int compared = 0, nonempty = 0, agreed = 0;
  int approximate_found = 0;
  for (int i = 0; i < 3000; ++i) {
    book.add(randomUnit());
    if (i % 100 < 70) book.index();
    if (i % 100 != 99) continue;
    for (int q = 0; q < 20; ++q) {
      const auto query = randomUnit();
      for (float radius : {0.01f, 0.03f, 0.1f}) {
        book.search(query, radius, 8, flann);
        book.searchBruteForce(query, radius, 8, brute);
        // The exact search returns what the scan returns (up to float rounding at the radius:
        // FLANN sums the squared differences in another order)...
        for (const auto& m : flann) {
          EXPECT_LE(m.distance, radius * 1.0001f);
          EXPECT_TRUE(std::any_of(brute.begin(), brute.end(), [&](const auto& b) { return b.index == m.index; }));
        }
        EXPECT_NEAR(double(flann.size()), double(brute.size()), 1.0);
        if (!brute.empty()) {
          ++nonempty;
          if (!flann.empty() && flann[0].index == brute[0].index) ++agreed;
        }
        ++compared;
        // ...the approximate one only true matches, nearest first...
        btf::Codebook::SearchOptions approximate;
        approximate.max_visits = 4;
        book.search(query, radius, 8, flann, approximate);
        for (std::size_t k = 0; k < flann.size(); ++k) {
          EXPECT_LE(flann[k].distance, radius * 1.0001f);
          if (k > 0) {
            EXPECT_LE(flann[k - 1].distance, flann[k].distance);
          }
        }
        if (!brute.empty() && !flann.empty()) ++approximate_found;
        // ...and the restricted one only entries from `first` on.
        btf::Codebook::SearchOptions recent;
        recent.first = std::uint32_t(book.size() - 150);
        book.search(query, radius, 8, flann, recent);
        std::size_t expected = 0;
        for (const auto& b : brute) expected += b.index >= recent.first ? 1 : 0;
        for (const auto& m : flann) EXPECT_GE(m.index, recent.first);
        if (brute.size() < 8) {
          EXPECT_NEAR(double(flann.size()), double(expected), 1.0);
        }
      }
    }
  }
  EXPECT_EQ(compared, 30 * 20 * 3);
  EXPECT_GT(nonempty, compared / 4);  // the test exercised real matches
  EXPECT_GE(agreed, nonempty * 99 / 100) << agreed << " of " << nonempty;
  EXPECT_GE(approximate_found, nonempty / 2);  // it mostly still finds one
  std::printf("nearest found by FLANN: %d of %d queries; some match found by the approximate search: %d\n", agreed,
              nonempty, approximate_found);
}
