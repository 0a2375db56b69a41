// The octree table (compress/octree_table.h) and its material: lossless at tolerance 0 bit for
// bit, every cell within its bound otherwise, node ranges that bound the cells, a file that
// round-trips and refuses damage, and lookups that agree with TabulatedBrdf.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <vector>

#include <tbb/global_control.h>

#include "btf/compress/octree_table.h"
#include "btf/core/half_diff.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "support/test_support.h"

namespace btf {
namespace {

using ::testing::HasSubstr;
constexpr int kNh = MerlTable::kThetaHalfRes, kNd = MerlTable::kThetaDiffRes, kNp = MerlTable::kPhiDiffRes;

// A table with the structures an octree meets in measurements: a smooth lobe that falls with
// theta_h, a slowly varying plateau, a block of exactly constant cells, a block of holes and
// unequal holes (-1 and -2) next to it.
MerlTable structuredTable() {
  MerlTable table;
  for (int i = 0; i < kNh; ++i)
    for (int j = 0; j < kNd; ++j)
      for (int k = 0; k < kNp; ++k) {
        const std::size_t c = MerlTable::index(i, j, k);
        if (i >= 60 && j >= 70) {
          table.setUnmeasured(c);
          if (k >= 170) table.raw(1, c) = -2.0;
          continue;
        }
        if (i >= 60) {  // constant
          for (int ch = 0; ch < 3; ++ch) table.raw(ch, c) = 40.0 + 5 * ch;
          continue;
        }
        const double lobe = 3000.0 * std::exp(-double(i) * i / 60.0) + 30.0 + 0.02 * j + 0.001 * k;
        for (int ch = 0; ch < 3; ++ch) table.raw(ch, c) = lobe * (1.0 + 0.1 * ch);
      }
  return table;
}

const MerlTable& sharedTable() {
  static const MerlTable table = structuredTable();
  return table;
}

TEST(OctreeTable, LosslessAtToleranceZeroBitForBit) {
  const MerlTable& table = sharedTable();
  const OctreeTable octree = OctreeTable::build(table, 0.0);
  const MerlTable back = octree.expand();
  ASSERT_EQ(back.values.size(), table.values.size());
  EXPECT_TRUE(std::memcmp(back.values.data(), table.values.data(), table.values.size() * sizeof(double)) == 0);
  // The constant block and the equal holes consolidate; the lobe does not.
  EXPECT_LT(octree.leaves().size(), MerlTable::kEntriesPerChannel * 7 / 10);
  EXPECT_GT(octree.leaves().size(), std::size_t(60 * kNd * kNp) / 2);
  // Point location agrees with the expansion.
  std::mt19937 rng(5);
  for (int n = 0; n < 2000; ++n) {
    const int i = int(rng() % kNh), j = int(rng() % kNd), k = int(rng() % kNp);
    const std::size_t c = MerlTable::index(i, j, k);
    for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(octree.raw(i, j, k)[ch], table.raw(ch, c));
  }
}

TEST(OctreeTable, EveryCellWithinToleranceOfItsStoredValue) {
  const MerlTable& table = sharedTable();
  std::size_t previous_leaves = MerlTable::kEntriesPerChannel + 1;
  for (double tolerance : {0.001, 0.01, 0.1}) {
    SCOPED_TRACE(tolerance);
    const OctreeTable octree = OctreeTable::build(table, tolerance);
    const MerlTable back = octree.expand();
    double worst = 0;
    for (std::size_t c = 0; c < MerlTable::kEntriesPerChannel; ++c)
      for (int ch = 0; ch < 3; ++ch) {
        const double stored = back.raw(ch, c), cell = table.raw(ch, c);
        if (!table.isMeasured(c)) {
          ASSERT_EQ(stored, cell) << "a hole changed at cell " << c;  // holes kept exactly
          continue;
        }
        worst = std::max(worst, std::abs(stored - cell) / std::abs(stored));
      }
    // Rounding of the midpoint may add an ulp or so to the bound.
    EXPECT_LE(worst, tolerance * (1 + 1e-12));
    EXPECT_GT(worst, tolerance / 10) << "the tolerance was not used";
    EXPECT_LT(octree.leaves().size(), previous_leaves);
    previous_leaves = octree.leaves().size();
  }
}

TEST(OctreeTable, NodeRangesBoundTheirCells) {
  const MerlTable& table = sharedTable();
  const OctreeTable octree = OctreeTable::build(table, 0.05);
  std::mt19937 rng(11);
  for (int n = 0; n < 200; ++n) {
    OctreeTable::Box box;
    const int extent[3] = {kNh, kNd, kNp};
    for (int a = 0; a < 3; ++a) {
      const int x = int(rng() % unsigned(extent[a])), y = int(rng() % unsigned(extent[a]));
      box.lo[a] = std::min(x, y);
      box.hi[a] = std::max(x, y) + 1;
    }
    double brute = 0;
    for (int i = box.lo[0]; i < box.hi[0]; ++i)
      for (int j = box.lo[1]; j < box.hi[1]; ++j)
        for (int k = box.lo[2]; k < box.hi[2]; ++k) {
          const std::size_t c = MerlTable::index(i, j, k);
          if (!table.isMeasured(c)) continue;
          for (int ch = 0; ch < 3; ++ch) brute = std::max(brute, table.raw(ch, c) * MerlTable::kChannelScale[ch]);
        }
    const float bound = octree.maxOver(box);
    ASSERT_GE(double(bound), brute);
    // Tight to within the float rounding when the box is a single cell.
    if (box.hi[0] - box.lo[0] == 1 && box.hi[1] - box.lo[1] == 1 && box.hi[2] - box.lo[2] == 1 && brute > 0) {
      EXPECT_LE(double(bound), brute * (1 + 1e-6));
    }
  }
  EXPECT_EQ(octree.maxOver(OctreeTable::Box{}), octree.root().f_max);
}

TEST(OctreeTable, TheSameTreeOnAnyThreadCountAndEveryRun) {
  auto buildOn = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return OctreeTable::build(sharedTable(), 0.01);
  };
  const OctreeTable a = buildOn(1), b = buildOn(3);
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  ASSERT_EQ(a.leaves().size(), b.leaves().size());
  EXPECT_TRUE(std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(OctreeTable::Node)) == 0);
  EXPECT_TRUE(std::memcmp(a.leaves().data(), b.leaves().data(), a.leaves().size() * sizeof(OctreeTable::Leaf)) == 0);
}

TEST(OctreeTable, RefusesABadTolerance) {
  EXPECT_THAT(test::errorOf([] { (void)OctreeTable::build(sharedTable(), -0.1); }), HasSubstr("tolerance"));
  EXPECT_THAT(test::errorOf([] { (void)OctreeTable::build(sharedTable(), NAN); }), HasSubstr("tolerance"));
}

TEST(OctreeFile, RoundTripsAndRefusesDamage) {
  test::TempDir dir;
  const OctreeTable octree = OctreeTable::build(sharedTable(), 0.1);
  const auto path = dir / "table.octree";
  writeOctreeFile(path, octree);
  const OctreeTable back = readOctreeFile(path);
  EXPECT_EQ(back.tolerance(), 0.1);
  ASSERT_EQ(back.nodes().size(), octree.nodes().size());
  EXPECT_TRUE(std::memcmp(back.leaves().data(), octree.leaves().data(), octree.leaves().size() * sizeof(OctreeTable::Leaf)) == 0);

  // Truncated: the container names the file.
  const auto truncated = dir / "truncated.octree";
  std::filesystem::copy_file(path, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(path) / 2);
  EXPECT_THAT(test::errorOf([&] { (void)readOctreeFile(truncated); }), HasSubstr(truncated.string()));

  // A valid container holding a broken tree: the reader names the file and the problem.
  const auto cyclic = test::rewriteContainer(path, dir / "cycle.octree", [](std::vector<ContainerSection>& sections) {
    for (ContainerSection& s : sections)
      if (s.name == "nodes") {
        const std::uint32_t last = std::uint32_t(s.data.size() / 12 - 1);
        std::memcpy(s.data.data() + 12 * std::size_t(last), &last, 4);  // the root its own child
      }
  });
  const std::string message = test::errorOf([&] { (void)readOctreeFile(cyclic); });
  EXPECT_THAT(message, HasSubstr(cyclic.string()));
  EXPECT_THAT(message, HasSubstr("malformed octree: node"));
  EXPECT_THAT(message, HasSubstr("not all stored before it"));
}

// Trees that do not hold together, as a damaged or hostile file could store them: each refused
// by what is wrong.
TEST(OctreeTable, FromPartsRefusesBrokenTrees) {
  const OctreeTable octree = OctreeTable::build(sharedTable(), 0.1);
  auto broken = [&](const std::function<void(std::vector<OctreeTable::Node>&)>& change) {
    std::vector<OctreeTable::Node> nodes = octree.nodes();
    change(nodes);
    return test::errorOf([&] { (void)OctreeTable::fromParts(nodes, octree.leaves(), 0.1); });
  };
  EXPECT_EQ(broken([](auto&) {}), "(no error)");
  EXPECT_THAT(broken([](auto& nodes) { nodes.back().ref = std::uint32_t(nodes.size() - 1); }), HasSubstr("not all stored before it"));
  EXPECT_THAT(broken([](auto& nodes) {
                for (auto& n : nodes)
                  if (n.ref & OctreeTable::kLeaf) {
                    n.ref = OctreeTable::kLeaf | 0x7fffffffu;
                    break;
                  }
              }),
              HasSubstr("refers to leaf"));
  EXPECT_THAT(broken([](auto& nodes) {
                const OctreeTable::Node* first = nullptr;
                for (auto& n : nodes) {
                  if (!(n.ref & OctreeTable::kLeaf)) continue;
                  if (first == nullptr) {
                    first = &n;
                  } else {
                    n = *first;  // ranges and all: only the second reference is wrong
                    break;
                  }
                }
              }),
              HasSubstr("referred to twice"));
  EXPECT_THAT(broken([](auto& nodes) { nodes.back().f_max = nodes.back().f_min / 2 - 1; }), HasSubstr("f range"));
  EXPECT_THAT(test::errorOf([&] { (void)OctreeTable::fromParts(octree.nodes(), {}, 0.1); }), HasSubstr("refers to leaf"));
  auto extra = octree.leaves();
  extra.push_back({1, 1, 1});
  EXPECT_THAT(test::errorOf([&] { (void)OctreeTable::fromParts(octree.nodes(), extra, 0.1); }), HasSubstr("leaves no node refers to"));
  auto nan = octree.leaves();
  nan[0][1] = NAN;
  EXPECT_THAT(test::errorOf([&] { (void)OctreeTable::fromParts(octree.nodes(), nan, 0.1); }), HasSubstr("not finite"));
}

// rawBlock's shared walk must find the same leaves as eight walks from the root: on blocks at
// random, at the clamped upper edges (both indices equal), across the middle splits and across
// phi_d's wrap (179, 0), on a lossless tree and on one whose leaves cover many cells.
TEST(OctreeTable, RawBlockFindsTheLeavesOfEightPointLocations) {
  for (double tolerance : {0.0, 0.1}) {
    const OctreeTable octree = OctreeTable::build(sharedTable(), tolerance);
    std::mt19937 rng(11);
    std::vector<std::array<std::array<int, 2>, 3>> blocks = {
        {{{89, 89}, {89, 89}, {179, 0}}},
        {{{44, 45}, {44, 45}, {89, 90}}},
        {{{0, 1}, {0, 1}, {0, 1}}},
        {{{59, 60}, {69, 70}, {169, 170}}},
    };
    for (int n = 0; n < 5000; ++n) {
      const int i = int(rng() % kNh), j = int(rng() % kNd), k = int(rng() % kNp);
      blocks.push_back({{{i, std::min(i + 1, kNh - 1)}, {j, std::min(j + 1, kNd - 1)}, {k, (k + 1) % kNp}}});
    }
    for (const auto& [h, d, p] : blocks) {
      const OctreeTable::Block block = octree.rawBlock(h, d, p);
      for (int c = 0; c < 8; ++c)
        ASSERT_EQ(block[std::size_t(c)], &octree.raw(h[c >> 2], d[(c >> 1) & 1], p[c & 1]))
            << "tolerance " << tolerance << ", cell (" << h[c >> 2] << ", " << d[(c >> 1) & 1] << ", " << p[c & 1] << ")";
    }
  }
}

// At tolerance 0 the octree material reads what TabulatedBrdf reads, wherever the table is
// measured (the structured table's holes lie where theta_h >= 60 and theta_d >= 70 only).
TEST(OctreeBrdf, AgreesWithTabulatedBrdfOnMeasuredCells) {
  auto table = std::make_shared<const MerlTable>(sharedTable());
  auto octree = std::make_shared<const OctreeTable>(OctreeTable::build(*table, 0.0));
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (TableLookup lookup : {TableLookup::Interpolated, TableLookup::Nearest, TableLookup::Truncated}) {
    const TabulatedBrdf reference(table, lookup);
    const OctreeBrdf material(octree, lookup);
    int compared = 0;
    for (int n = 0; n < 3000; ++n) {
      const float theta_i = 1.2f * u(rng), theta_o = 1.2f * u(rng), phi = 6.28f * u(rng);
      const glm::vec3 wi(std::sin(theta_i) * std::cos(phi), std::sin(theta_i) * std::sin(phi), std::cos(theta_i));
      const glm::vec3 wo(std::sin(theta_o), 0.0f, std::cos(theta_o));
      const HalfDiff hd = toHalfDiff(wi, wo);
      if (MerlTable::thetaHalfCoordinate(hd.theta_h) >= 58 && MerlTable::thetaDiffCoordinate(hd.theta_d) >= 68) continue;
      const Rgb a = material.eval(wi, wo), b = reference.eval(wi, wo);
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(a[ch], b[ch], 1e-5f * b[ch]) << material.name();
      ++compared;
    }
    EXPECT_GT(compared, 2000);
  }
  EXPECT_EQ(OctreeBrdf(octree).eval({0, 0, -1}, {0, 0, 1}), Rgb(0.0f));
}

}  // namespace
}  // namespace btf
