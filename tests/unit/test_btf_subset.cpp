// BtfSubset: a rectangle of texels and some views of another BTF, value for value.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "support/test_support.h"

namespace btf {
namespace {
using testing::HasSubstr;
using test::errorOf;

// Every entry distinct, so a wrong offset or view shows.
BtfData numberedBtf(int width, int height, BtfViewSet views) {
  BtfData data(width, height, "numbered", views);
  for (const int v : views.views())
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) data.at(x, y, v, l) = Rgb(float(x), float(y), float(v * 100 + l));
  return data;
}

TEST(BtfSubset, HoldsTheRectangleAndViewsOfItsSource) {
  const BtfData source = numberedBtf(7, 5, BtfViewSet({0, 3, 20}));
  const BtfSubset subset(source, {2, 1, 4, 3}, BtfViewSet({3, 20}));
  EXPECT_EQ(subset.width(), 4);
  EXPECT_EQ(subset.height(), 3);
  EXPECT_EQ(subset.views(), BtfViewSet({3, 20}));
  EXPECT_THAT(subset.name(), HasSubstr("4x3 at 2,1"));
  std::vector<Rgb> view;
  for (const int v : {3, 20}) {
    subset.loadView(v, view);
    ASSERT_EQ(view.size(), std::size_t(81 * 4 * 3));
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x)
          EXPECT_EQ(view[(std::size_t(l) * 3 + std::size_t(y)) * 4 + std::size_t(x)], source.at(x + 2, y + 1, v, l));
  }
  EXPECT_THAT(errorOf([&] { subset.loadView(0, view); }), HasSubstr("theta 0, phi 0"));
}

TEST(BtfSubset, CentredRectangleIsClampedToTheSource) {
  const BtfData source = numberedBtf(7, 5, BtfViewSet({0}));
  const BtfRect r = BtfSubset::centredRect(source, 3, 3);
  EXPECT_EQ(r.x, 2);
  EXPECT_EQ(r.y, 1);
  const BtfRect whole = BtfSubset::centredRect(source, 64, 64);
  EXPECT_EQ(whole.x, 0);
  EXPECT_EQ(whole.width, 7);
  EXPECT_EQ(whole.height, 5);
}

TEST(BtfSubset, RefusesARectangleOutsideOrAViewNotHeld) {
  const BtfData source = numberedBtf(7, 5, BtfViewSet({0, 3}));
  EXPECT_THAT(errorOf([&] { BtfSubset(source, {5, 0, 3, 2}, BtfViewSet({0})); }), HasSubstr("is not inside its 7 x 5"));
  EXPECT_THAT(errorOf([&] { BtfSubset(source, {0, 0, 0, 2}, BtfViewSet({0})); }), HasSubstr("numbered"));
  EXPECT_THAT(errorOf([&] { BtfSubset(source, {0, 0, 2, 2}, BtfViewSet({0, 4})); }), HasSubstr("is not in this BTF"));
}

}  // namespace
}  // namespace btf
