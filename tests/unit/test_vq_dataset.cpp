// A dataset compressed in parts (compress/vq_dataset.h): map, reduce, re-code and join give a
// database of the single-machine format in which every material keeps its bound, of about the
// single-machine size; the same partition gives the same bytes; tiles of one BTF join into one
// material; bad inputs are refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "btf/compress/vq_dataset.h"
#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "btf_test_data.h"
#include "support/test_support.h"
#include "synthetic_btf_data.h"

namespace {

using btf::test::vqLuminanceBound;

struct DatasetMaterials {
  btf::BtfData ggx = btf::test::makeGgxBtf(8, 8, false);
  btf::BtfData tinted = btf::test::makeGgxBtf(8, 6, true);
  btf::BtfData lambert = btf::test::makeAnalyticBtf(6, 5, false, "lambert");
  btf::BtfData analytic = btf::test::makeAnalyticBtf(6, 6, true, "analytic");
  std::vector<const btf::BtfSource*> sources() const { return {&ggx, &tinted, &lambert, &analytic}; }
  std::vector<std::string> names() const { return {"ggx", "tinted", "lambert", "analytic"}; }
};
const DatasetMaterials& dataset() {
  static const DatasetMaterials m;
  return m;
}

// The four steps over a partition of the dataset's materials (index lists), the way a cluster
// runs them, every step's result passed as bytes.
btf::VqDatabase compressInParts(const std::vector<std::vector<std::size_t>>& partition, const btf::VqOptions& options) {
  const auto sources = dataset().sources();
  const auto names = dataset().names();
  auto partOf = [&](const std::vector<std::size_t>& part) {
    std::vector<const btf::BtfSource*> s;
    std::vector<std::string> n;
    for (std::size_t i : part) s.push_back(sources[i]), n.push_back(names[i]);
    return std::make_pair(s, n);
  };
  std::vector<btf::VqCodebooks> mapped;
  for (const auto& part : partition) {
    const auto [s, n] = partOf(part);
    const auto bytes = btf::VqCodebooks::of(btf::compressVqDatabase(s, n, options)).toBytes();
    mapped.push_back(btf::VqCodebooks::fromBytes(bytes));
  }
  const btf::VqCodebooks seed = btf::VqCodebooks::fromBytes(btf::mergeVqCodebooks(mapped).toBytes());
  std::vector<btf::VqDatabase> recoded;
  for (const auto& part : partition) {
    const auto [s, n] = partOf(part);
    btf::VqDatabase db = btf::compressVqDatabase(s, n, options, seed);
    recoded.push_back(btf::vqDatabaseFromBytes(btf::vqDatabaseBytes(db)));
  }
  return btf::mergeVqDatabases(recoded);
}

std::string bytesOf(btf::VqDatabase& db) {
  const auto b = btf::vqDatabaseBytes(db);
  return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

}  // namespace

TEST(VqDataset, PartsKeepTheBoundAndTheSingleMachineSizeAtEveryLevel) {
  for (int levels : {1, 3}) {
    btf::VqOptions options;
    options.epsilon = 0.05f;
    options.levels = levels;
    btf::VqDatabase whole = btf::compressVqDatabase(dataset().sources(), dataset().names(), options);
    btf::VqDatabase parts = compressInParts({{0, 2}, {1, 3}}, options);
    ASSERT_EQ(parts.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
      const btf::BtfSource& source = *dataset().sources()[i];
      const btf::VqBtf& m = parts.material(dataset().names()[i]);
      EXPECT_EQ(m.width(), source.width());
      EXPECT_LE(btf::test::luminanceRelRmse(source, m), vqLuminanceBound(options.epsilon, levels))
          << dataset().names()[i] << ", levels " << levels;
    }
    // The shared entries are reused across parts as they are in one run: about the same size.
    const double ratio = double(parts.compressedBytes()) / double(whole.compressedBytes());
    EXPECT_LT(ratio, 1.15) << "levels " << levels << ": " << parts.compressedBytes() << " against " << whole.compressedBytes();
    // The same format: the file reads back as a database.
    btf::test::TempDir dir;
    parts.write(dir / "parts.btfz");
    EXPECT_EQ(btf::VqDatabase::read(dir / "parts.btfz").names(), parts.names());
  }
}

TEST(VqDataset, ReCodingFromItsOwnCodebooksAddsNothingOfNote) {
  // A material re-coded from the codebooks it made alone finds its own entries again.
  btf::VqOptions options;
  const std::vector<const btf::BtfSource*> one{&dataset().ggx};
  btf::VqDatabase alone = btf::compressVqDatabase(one, {"ggx"}, options);
  btf::VqDatabase again = btf::compressVqDatabase(one, {"ggx"}, options, btf::VqCodebooks::of(alone));
  EXPECT_LE(btf::test::luminanceRelRmse(dataset().ggx, again.materials().front()), vqLuminanceBound(options.epsilon, 3));
  for (std::size_t level = 0; level < alone.sharedEntries().size(); ++level)
    EXPECT_LT(double(again.sharedEntries()[level]), 1.05 * double(alone.sharedEntries()[level]) + 2) << "level " << level + 1;
}

TEST(VqDataset, TheSamePartitionGivesTheSameBytes) {
  btf::VqOptions options;
  options.threads = 1;
  btf::VqDatabase a = compressInParts({{0}, {2}}, options);
  options.threads = 2;
  btf::VqDatabase b = compressInParts({{0}, {2}}, options);
  EXPECT_TRUE(bytesOf(a) == bytesOf(b));
}

TEST(VqDataset, CodebooksRoundTripAsBytes) {
  btf::VqOptions options;
  const btf::VqCodebooks books = btf::VqCodebooks::of(btf::compressVqDatabase(dataset().sources(), dataset().names(), options));
  const btf::VqCodebooks back = btf::VqCodebooks::fromBytes(books.toBytes());
  EXPECT_EQ(back.entries(), books.entries());
  EXPECT_EQ(back.groupCount(), 1u);
  const std::vector<const btf::BtfSource*> one{&dataset().lambert};
  btf::VqDatabase from_books = btf::compressVqDatabase(one, {"l"}, options, books);
  btf::VqDatabase from_back = btf::compressVqDatabase(one, {"l"}, options, back);
  EXPECT_TRUE(bytesOf(from_books) == bytesOf(from_back));
}

TEST(VqDataset, MergedCodebooksHoldEachPartsEntriesWithinTheTolerance) {
  // The same material in two parts: the second copy adds nothing, and the merge holds at most the
  // part's entries (fewer where the compressor's bounded search missed an entry within the
  // tolerance, which the merge's exact search finds).
  btf::VqOptions options;
  const std::vector<const btf::BtfSource*> one{&dataset().ggx};
  const btf::VqCodebooks part = btf::VqCodebooks::of(btf::compressVqDatabase(one, {"ggx"}, options));
  const btf::VqCodebooks once[] = {part}, twice[] = {part, part};
  const std::vector<std::size_t> merged = btf::mergeVqCodebooks(once).entries();
  EXPECT_EQ(btf::mergeVqCodebooks(twice).entries(), merged);
  for (std::size_t level = 0; level < merged.size(); ++level) EXPECT_LE(merged[level], part.entries()[level]);
}

TEST(VqDataset, TilesOfOneBtfJoinIntoOneMaterial) {
  btf::VqOptions options;
  options.epsilon = 0.04f;
  const btf::BtfData& big = dataset().analytic;
  const std::vector<btf::BtfRect> rects = btf::vqTiles(big.width(), big.height(), 4);
  ASSERT_EQ(rects.size(), 4u);
  std::vector<btf::BtfSubset> tiles;
  tiles.reserve(rects.size());
  std::vector<std::string> names;
  for (const btf::BtfRect& r : rects) {
    tiles.emplace_back(big, r, big.views());
    names.push_back("analytic@" + std::to_string(r.x) + "," + std::to_string(r.y));
  }
  std::vector<btf::VqCodebooks> mapped;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const std::vector<const btf::BtfSource*> s{&tiles[i]};
    mapped.push_back(btf::VqCodebooks::of(btf::compressVqDatabase(s, {names[i]}, options)));
  }
  const btf::VqCodebooks seed = btf::mergeVqCodebooks(mapped);
  std::vector<btf::VqDatabase> recoded;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const std::vector<const btf::BtfSource*> s{&tiles[i]};
    recoded.push_back(btf::compressVqDatabase(s, {names[i]}, options, seed));
  }
  btf::VqDatabase joined = btf::joinVqTiles(btf::mergeVqDatabases(recoded), rects, big.width(), big.height(), "analytic");
  ASSERT_EQ(joined.size(), 1u);
  const btf::VqBtf& m = joined.materials().front();
  EXPECT_EQ(m.width(), big.width());
  EXPECT_EQ(m.height(), big.height());
  EXPECT_LE(btf::test::luminanceRelRmse(big, m), vqLuminanceBound(options.epsilon, 3));
  // Every texel decodes as it did in its tile.
  for (std::size_t i = 0; i < rects.size(); ++i)
    for (int y = 0; y < rects[i].height; ++y)
      for (int x = 0; x < rects[i].width; ++x)
        for (int v : {0, 40, 80})
          EXPECT_EQ(m.value(rects[i].x + x, rects[i].y + y, v, 7), recoded[i].materials().front().value(x, y, v, 7));
  btf::test::TempDir dir;
  joined.write(dir / "joined.btfz");
  const btf::VqBtf back = btf::VqBtf::read(dir / "joined.btfz");
  btf::test::expectSameDecode(back, m);
}

TEST(VqDataset, TilesCoverEveryTexelOnce) {
  for (const auto& [w, h, n] : std::vector<std::tuple<int, int, int>>{{8, 8, 4}, {7, 5, 6}, {3, 40, 5}, {2, 2, 9}, {100, 1, 3}}) {
    const auto rects = btf::vqTiles(w, h, n);
    EXPECT_EQ(int(rects.size()), std::min(n, w * h));
    std::vector<int> covered(std::size_t(w * h), 0);
    for (const auto& r : rects) {
      EXPECT_GE(r.width, 1);
      EXPECT_GE(r.height, 1);
      for (int y = r.y; y < r.y + r.height; ++y)
        for (int x = r.x; x < r.x + r.width; ++x) ++covered[std::size_t(y * w + x)];
    }
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; })) << w << " x " << h << " / " << n;
  }
}

TEST(VqDataset, BadInputsAreRefusedByName) {
  btf::VqOptions options;
  const std::vector<const btf::BtfSource*> one{&dataset().lambert};
  const btf::VqCodebooks books = btf::VqCodebooks::of(btf::compressVqDatabase(one, {"l"}, options));
  btf::VqOptions other = options;
  other.epsilon = 0.1f;
  const btf::VqCodebooks other_books = btf::VqCodebooks::of(btf::compressVqDatabase(one, {"l"}, other));
  const btf::VqCodebooks mixed[] = {books, other_books};
  const std::string labels[] = {"a.btfz", "b.btfz"};
  const std::string merge = btf::test::errorOf([&] { (void)btf::mergeVqCodebooks(mixed, labels); });
  EXPECT_NE(merge.find("b.btfz"), std::string::npos) << merge;
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::compressVqDatabase(one, {"l"}, options, other_books); }).find("options"),
            std::string::npos);
  btf::VqOptions cut = options;
  cut.level1_cut = true;
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::compressVqDatabase(one, {"l"}, cut, books); }).find("level1_cut"),
            std::string::npos);
  const std::vector<std::byte> junk(100, std::byte{7});
  const std::string bytes = btf::test::errorOf([&] { (void)btf::VqCodebooks::fromBytes(junk, "from worker 3"); });
  EXPECT_NE(bytes.find("from worker 3"), std::string::npos) << bytes;
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::vqDatabaseFromBytes(junk, "part 2"); }).find("part 2"), std::string::npos);
  // A database's bytes are not codebooks.
  btf::VqDatabase db = btf::compressVqDatabase(one, {"l"}, options);
  const std::string wrong = btf::test::errorOf([&] { (void)btf::VqCodebooks::fromBytes(btf::vqDatabaseBytes(db), "x"); });
  EXPECT_NE(wrong.find("not a set of VQ codebooks"), std::string::npos) << wrong;
  // Tiles that overlap or leave a texel out.
  const std::vector<btf::BtfRect> overlap{{0, 0, 4, 5}, {3, 0, 3, 5}};
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::joinVqTiles(db, overlap, 6, 5, "x"); }).find("tiles but"), std::string::npos);
  btf::VqDatabase pair = btf::mergeVqDatabases(std::vector<btf::VqDatabase>{
      btf::compressVqDatabase(one, {"a"}, options, books), btf::compressVqDatabase(one, {"b"}, options, books)});
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::joinVqTiles(pair, overlap, 6, 5, "x"); }).find("two tiles"), std::string::npos);
  const std::vector<btf::BtfRect> gap{{0, 0, 6, 5}, {0, 0, 0, 0}};
  EXPECT_NE(btf::test::errorOf([&] { (void)btf::joinVqTiles(pair, gap, 6, 6, "x"); }).find("not inside"), std::string::npos);
}
