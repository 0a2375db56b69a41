// Databases of materials with shared codebooks (compress/vq_database.h): every material within
// the tolerance bound it has alone, codebooks that shrink when materials repeat, the .btfz
// database round trip, selection by name, the lossless merge and the reader's rejections.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>

#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "btf/io/container.h"
#include "btf_test_data.h"
#include "support/test_support.h"
#include "synthetic_btf_data.h"

namespace {

using btf::test::vqLuminanceBound;

using btf::test::expectSameDecode;

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Three different materials: a GGX pattern, a Lambert-only analytic BTF, and the upper views of
// another pattern (a partial BTF: the database keeps its view set).
struct Materials {
  btf::BtfData ggx = btf::test::makeGgxBtf(8, 8, false);
  btf::BtfData lambert = btf::test::makeAnalyticBtf(6, 5, false, "lambert");
  btf::BtfData other = btf::test::makeAnalyticBtf(6, 6, true, "analytic");
  btf::BtfSubset upper{other, {0, 0, 6, 6}, btf::BtfViewSet::upToTheta(45.0f)};
  std::vector<const btf::BtfSource*> sources() const { return {&ggx, &lambert, &upper}; }
  std::vector<std::string> names() const { return {"ggx", "lambert", "upper"}; }
};
const Materials& materials() {
  static const Materials m;
  return m;
}

}  // namespace

TEST(VqDatabase, EveryMaterialKeepsTheBoundItHasAloneAtEveryLevel) {
  for (int levels = 1; levels <= 3; ++levels) {
    btf::VqOptions options;
    options.epsilon = 0.05f;
    options.levels = levels;
    const btf::VqDatabase db = btf::compressVqDatabase(materials().sources(), materials().names(), options);
    ASSERT_EQ(db.size(), 3u);
    EXPECT_EQ(db.names(), materials().names());
    for (std::size_t i = 0; i < db.size(); ++i) {
      const btf::BtfSource& source = *materials().sources()[i];
      const btf::VqBtf& m = db.materials()[i];
      EXPECT_EQ(m.width(), source.width());
      EXPECT_EQ(m.views().views(), source.views().views());
      const double luminance = btf::test::luminanceRelRmse(source, m);
      EXPECT_LE(luminance, vqLuminanceBound(options.epsilon, levels)) << db.names()[i] << ", levels " << levels;
      // The library's own measure and bound (what btf.dask reports) agree with the tests' ones.
      EXPECT_NEAR(btf::compareBtf(source, m).luminance_rel_rmse, luminance, 1e-9 + 1e-6 * luminance);
      EXPECT_LE(luminance, btf::vqLuminanceBound(options));
      EXPECT_LE(btf::vqLuminanceBound(options), vqLuminanceBound(options.epsilon, levels));
    }
    EXPECT_EQ(db.sharedEntries().size(), std::size_t(std::min(levels, 2)));
  }
}

TEST(VqDatabase, RepeatedMaterialsShareTheirCodebooks) {
  // The same BTF twice under two names: the second finds its vectors in the codebooks the first
  // made, so the database holds little more than one material alone. (Not exactly nothing more:
  // the second copy may reuse another entry within the tolerance than the first chose, and its
  // level-2 vectors, built from those, then differ a little; and approximate searches may miss.
  // Both counts are of live entries (vq_prune.h): at epsilon 0.02 the second copy still adds
  // level-2 entries.)
  const btf::BtfData& ggx = materials().ggx;
  btf::VqOptions options;
  options.epsilon = 0.02f;
  const btf::VqBtf alone = btf::compressVq(ggx, options);
  const std::vector<const btf::BtfSource*> twice{&ggx, &ggx};
  const btf::VqDatabase db = btf::compressVqDatabase(twice, {"a", "b"}, options);
  std::vector<std::size_t> alone_shared = alone.stats().codebook_entries;
  alone_shared.pop_back();  // level 3 is per material
  ASSERT_EQ(db.sharedEntries().size(), alone_shared.size());
  for (std::size_t level = 0; level < alone_shared.size(); ++level) {
    EXPECT_GE(db.sharedEntries()[level], alone_shared[level]);
    EXPECT_LT(double(db.sharedEntries()[level]), 1.15 * double(alone_shared[level])) << "level " << level + 1;
  }
  EXPECT_LT(double(db.compressedBytes()), 1.3 * double(alone.stats().compressed_bytes));
  // The first material is compressed exactly as it is alone.
  expectSameDecode(db.material("a"), alone);
}

TEST(VqDatabase, WriteReadRoundTripAndSelectionByName) {
  btf::test::TempDir dir;
  btf::VqDatabase db = btf::compressVqDatabase(materials().sources(), materials().names(), {});
  const auto path = dir / "db.btfz";
  db.write(path);
  EXPECT_EQ(db.compressedBytes(), std::filesystem::file_size(path));
  const btf::VqDatabase back = btf::VqDatabase::read(path);
  ASSERT_EQ(back.names(), db.names());
  for (std::size_t i = 0; i < db.size(); ++i) expectSameDecode(db.materials()[i], back.materials()[i]);
  // VqBtf::read: by name; a database of several needs one.
  expectSameDecode(btf::VqBtf::read(path, "lambert"), db.material("lambert"));
  const std::string unnamed = btf::test::errorOf([&] { btf::VqBtf::read(path); });
  EXPECT_NE(unnamed.find("ggx, lambert, upper"), std::string::npos) << unnamed;
  const std::string unknown = btf::test::errorOf([&] { btf::VqBtf::read(path, "velvet"); });
  EXPECT_NE(unknown.find("velvet"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("lambert"), std::string::npos) << unknown;
  EXPECT_NE(btf::test::errorOf([&] { (void)db.material("velvet"); }).find("ggx"), std::string::npos);
  // A single-material file reads as a database of one, named without the compressor's suffix.
  const btf::VqBtf single = btf::compressVq(materials().lambert, {});
  single.write(dir / "single.btfz");
  const btf::VqDatabase one = btf::VqDatabase::read(dir / "single.btfz");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.names().front(), "lambert");
}

TEST(VqDatabase, OutputDoesNotDependOnTheThreadCount) {
  btf::test::TempDir dir;
  btf::VqOptions options;
  options.threads = 1;
  btf::VqDatabase one = btf::compressVqDatabase(materials().sources(), materials().names(), options);
  options.threads = 2;
  btf::VqDatabase two = btf::compressVqDatabase(materials().sources(), materials().names(), options);
  one.write(dir / "one.btfz");
  two.write(dir / "two.btfz");
  const std::string a = fileBytes(dir / "one.btfz");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a == fileBytes(dir / "two.btfz"), true);
}

TEST(VqDatabase, MergeIsLosslessAndStoresRepeatedEntriesOnce) {
  btf::test::TempDir dir;
  for (int levels = 1; levels <= 3; ++levels) {
    btf::VqOptions options;
    options.levels = levels;
    // Compressed apart, as on different machines; then joined.
    const btf::VqBtf a = btf::compressVq(materials().ggx, options), b = btf::compressVq(materials().lambert, options);
    a.write(dir / "a.btfz");
    b.write(dir / "b.btfz");
    const btf::VqDatabase parts[] = {btf::VqDatabase::read(dir / "a.btfz"), btf::VqDatabase::read(dir / "b.btfz")};
    btf::VqDatabase merged = btf::mergeVqDatabases(parts);
    merged.write(dir / "merged.btfz");
    const btf::VqDatabase back = btf::VqDatabase::read(dir / "merged.btfz");
    ASSERT_EQ(back.names(), (std::vector<std::string>{"ggx-pattern", "lambert"}));
    expectSameDecode(back.material("ggx-pattern"), a);
    expectSameDecode(back.material("lambert"), b);
    // The seed entries (and any other equal entries) are stored once: fewer shared entries than
    // the two files' together.
    for (std::size_t level = 0; level < back.sharedEntries().size(); ++level)
      EXPECT_LT(back.sharedEntries()[level], a.stats().codebook_entries[level] + b.stats().codebook_entries[level])
          << "level " << level + 1;
    EXPECT_LT(std::filesystem::file_size(dir / "merged.btfz"),
              std::filesystem::file_size(dir / "a.btfz") + std::filesystem::file_size(dir / "b.btfz"));
  }
}

TEST(VqDatabase, MergeOfACopyAddsNoSharedEntry) {
  btf::test::TempDir dir;
  const std::vector<const btf::BtfSource*> one{&materials().ggx}, other{&materials().ggx};
  const btf::VqDatabase a = btf::compressVqDatabase(one, {"first"}, {});
  const btf::VqDatabase b = btf::compressVqDatabase(other, {"second"}, {});
  const btf::VqDatabase merged = btf::mergeVqDatabases(std::vector<btf::VqDatabase>{a, b});
  EXPECT_EQ(merged.sharedEntries(), a.sharedEntries());
  expectSameDecode(merged.material("second"), b.materials().front());
}

TEST(VqDatabase, RefusesWhatCannotBeADatabase) {
  const auto& m = materials();
  EXPECT_NE(btf::test::errorOf([&] { btf::compressVqDatabase(m.sources(), {"a", "a", "b"}, {}); }).find("two materials named 'a'"),
            std::string::npos);
  EXPECT_NE(btf::test::errorOf([&] { btf::compressVqDatabase(m.sources(), {"a"}, {}); }).find("one name per material"),
            std::string::npos);
  EXPECT_NE(btf::test::errorOf([&] { btf::compressVqDatabase({}, {}, {}); }).find("at least one"), std::string::npos);
  // Materials compressed apart do not share codebooks: only a merge joins them.
  const btf::VqBtf a = btf::compressVq(m.ggx, {}), b = btf::compressVq(m.lambert, {});
  EXPECT_NE(btf::test::errorOf([&] { btf::VqDatabase(std::vector<btf::VqBtf>{a, b}); }).find("mergeVqDatabases"),
            std::string::npos);
  // Merging needs one set of options and distinct names.
  btf::VqOptions coarse;
  coarse.epsilon = 0.1f;
  const std::vector<const btf::BtfSource*> ggx{&m.ggx}, lambert{&m.lambert};
  const btf::VqDatabase fine_db = btf::compressVqDatabase(ggx, {"ggx"}, {});
  const btf::VqDatabase coarse_db = btf::compressVqDatabase(lambert, {"lambert"}, coarse);
  EXPECT_NE(btf::test::errorOf([&] { btf::mergeVqDatabases(std::vector<btf::VqDatabase>{fine_db, coarse_db}); }).find("epsilon"),
            std::string::npos);
  EXPECT_NE(btf::test::errorOf([&] { btf::mergeVqDatabases(std::vector<btf::VqDatabase>{fine_db, fine_db}); }).find("named 'ggx'"),
            std::string::npos);
  // Invalid data in any material is named as compressVq names it.
  btf::BtfData bad(2, 2, "bad");
  bad.at(1, 0, 3, 7) = btf::Rgb(std::nanf(""), 0.0f, 0.0f);
  const std::vector<const btf::BtfSource*> with_bad{&m.lambert, &bad};
  EXPECT_NE(btf::test::errorOf([&] { btf::compressVqDatabase(with_bad, {"lambert", "bad"}, {}); }).find("bad: view 3, light 7"),
            std::string::npos);
}

TEST(VqDatabase, ReaderRejectsDamagedDatabases) {
  btf::test::TempDir dir;
  btf::VqDatabase db = btf::compressVqDatabase(materials().sources(), materials().names(), {});
  const auto good = dir / "good.btfz";
  db.write(good);
  auto rewrite = [&](const std::string& name, const std::function<void(std::vector<btf::ContainerSection>&)>& change) {
    return btf::test::rewriteContainer(good, dir / (name + ".btfz"), change);
  };
  auto editHeader = [&](const std::string& name, auto&& change) {
    return rewrite(name, [&](std::vector<btf::ContainerSection>& sections) {
      for (auto& s : sections)
        if (s.name == "header") {
          std::string text(reinterpret_cast<const char*>(s.data.data()), s.data.size());
          change(text);
          s.data.resize(text.size());
          std::memcpy(s.data.data(), text.data(), text.size());
        }
    });
  };
  auto replaceFirst = [](std::string& text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  auto expectError = [](const std::filesystem::path& path, const std::string& words) {
    try {
      btf::VqDatabase::read(path);
      ADD_FAILURE() << path << " accepted";
    } catch (const btf::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
    }
  };
  expectError(rewrite("missing", [](auto& sections) { std::erase_if(sections, [](const auto& s) { return s.name == "material1/top/index"; }); }),
              "material1/top/index is missing");
  expectError(editHeader("renamed", [&](std::string& t) { replaceFirst(t, "\"lambert\"", "\"ggx\""); }), "repeated name");
  expectError(editHeader("entries", [&](std::string& t) { replaceFirst(t, "\"level3_entries\":", "\"level3_entries\":1"); }),
              "disagree");
  expectError(editHeader("many", [&](std::string& t) {
                std::string list = "\"materials\":[";
                for (int i = 0; i < 200; ++i) list += "{\"name\":\"m" + std::to_string(i) + "\",\"width\":1,\"height\":1},";
                replaceFirst(t, "\"materials\":[", list);
              }),
              "more than its sections");
  expectError(editHeader("version",
                         [&](std::string& t) {
                           const std::string key = "\"format_version\":";
                           const std::size_t at = t.find(key);
                           ASSERT_NE(at, std::string::npos);
                           t[at + key.size()] = '7';  // a single digit: 1..3 written
                         }),
              "version 7");
}
