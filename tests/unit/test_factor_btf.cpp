// The factor form of a compressed BTF (compress/factor_btf.h): the error it promises against its
// source in both colour models, the same bits from value() and loadView(), write/read and the thread
// count leaving the bytes unchanged, a Bonn DFMF file's own factors re-coded, and the reader's errors
// on damaged files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "btf/compress/compressed_btf.h"
#include "btf/compress/factor_btf.h"
#include "btf/core/error.h"
#include "btf/io/bonn_btf.h"
#include "support/test_support.h"
#include "synthetic_btf_data.h"

namespace btf {
namespace {

using ::testing::HasSubstr;

double relRmse(const BtfSource& reference, const BtfSource& test) { return compareBtf(reference, test).rel_rmse; }

void writeAll(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

std::string readAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void expectLookupMatchesViews(const FactorBtf& f) {
  std::vector<Rgb> view;
  for (const int v : f.views().views()) {
    f.loadView(v, view);
    const int lights = f.directions().lightCount(v);
    for (int l = 0; l < lights; ++l)
      for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
          const Rgb a = view[(std::size_t(l) * std::size_t(f.height()) + std::size_t(y)) * std::size_t(f.width()) + std::size_t(x)];
          const Rgb b = f.value(x, y, v, l);
          ASSERT_EQ(std::memcmp(&a, &b, sizeof(Rgb)), 0) << "view " << v << " light " << l << " texel " << x << ", " << y;
        }
  }
}

TEST(FactorBtf, MeetsEpsilonInBothColourModels) {
  const BtfData data = test::makeAnalyticBtf(12, 10);
  for (const FactorColorModel model : {FactorColorModel::Linear, FactorColorModel::LogLuminance})
    for (const float epsilon : {0.05f, 0.01f}) {
      FactorOptions o;
      o.epsilon = epsilon;
      o.color_model = model;
      const FactorBtf f = compressFactor(data, o);
      const double measured = relRmse(data, f);
      SCOPED_TRACE(factorColorModelName(model) + " epsilon " + std::to_string(epsilon));
      EXPECT_LE(measured, epsilon);
      // Not far below either: the step is the largest that meets the budget.
      EXPECT_GT(measured, 0.3 * epsilon);
      if (model == FactorColorModel::LogLuminance) {
        EXPECT_NEAR(f.stats().measured_rel_rmse, measured, 1e-4);
      }
      EXPECT_GE(f.stats().components[0], 1);
      expectLookupMatchesViews(f);
    }
}

TEST(FactorBtf, WrittenFileDecodesTheSameAndDoesNotDependOnThreads) {
  test::TempDir dir;
  const BtfData data = test::makeAnalyticBtf(9, 7);
  FactorOptions o;
  o.epsilon = 0.02f;
  o.color_model = FactorColorModel::LogLuminance;
  o.threads = 1;
  const FactorBtf one = compressFactor(data, o);
  o.threads = 2;
  const FactorBtf two = compressFactor(data, o);
  one.write(dir / "one.btfz");
  two.write(dir / "two.btfz");
  EXPECT_EQ(readAll(dir / "one.btfz"), readAll(dir / "two.btfz"));
  const FactorBtf back = FactorBtf::read(dir / "one.btfz");
  EXPECT_EQ(compressedBtfFormat(dir / "one.btfz"), "libbtf-factor");
  EXPECT_EQ(back.stats().components, one.stats().components);
  EXPECT_EQ(relRmse(one, back), 0.0);
  EXPECT_EQ(relRmse(*readCompressedBtf(dir / "one.btfz"), one), 0.0);
  EXPECT_THAT(test::errorOf([&] { readCompressedBtf(dir / "one.btfz", "other"); }), HasSubstr("not a database"));
}

// A DFMF file in colour model 11 is coded from its own factors: the decode of the file is the
// reference, and the components do not exceed the file's.
TEST(FactorBtf, BonnDfmfIsCodedFromItsOwnFactors) {
  test::TempDir dir;
  const BtfData data = test::makeAnalyticBtf(8, 8);
  BonnBtfWriteOptions w;
  w.max_components = 6;
  w.scalar_bytes = 4;
  writeBonnBtf(data, dir / "m.btf", w);
  const BonnBtf bonn = BonnBtf::open(dir / "m.btf");
  FactorOptions o;
  o.epsilon = 0.02f;
  o.color_model = FactorColorModel::LogLuminance;
  ASSERT_TRUE(factorFromSourceFactors(bonn, o));
  o.color_model = FactorColorModel::Linear;
  EXPECT_FALSE(factorFromSourceFactors(bonn, o));
  o.color_model = FactorColorModel::LogLuminance;
  const FactorBtf f = compressFactor(bonn, o);
  EXPECT_TRUE(f.stats().from_source_factors);
  for (int c = 0; c < 3; ++c) EXPECT_LE(f.stats().components[std::size_t(c)], 6);
  EXPECT_LE(relRmse(bonn, f), 0.02);
  expectLookupMatchesViews(f);
}

TEST(FactorBtf, RefusesBadOptionsAndValues) {
  const BtfData data = test::makeAnalyticBtf(4, 4);
  FactorOptions o;
  o.epsilon = 0.0f;
  EXPECT_THAT(test::errorOf([&] { compressFactor(data, o); }), HasSubstr("epsilon must be in (0, 1)"));
  o.epsilon = 0.02f;
  o.max_components = 0;
  EXPECT_THAT(test::errorOf([&] { compressFactor(data, o); }), HasSubstr("at least 1"));
  BtfData bad = test::makeAnalyticBtf(4, 4, true, "bad");
  bad.at(1, 2, 5, 7) = Rgb(-1.0f, 0.0f, 0.0f);
  EXPECT_THAT(test::errorOf([&] { compressFactor(bad, FactorOptions{}); }),
              HasSubstr("bad: view 5, light 7, texel (1, 2) holds a negative"));
  BtfData zero(3, 3, "zero");
  EXPECT_THAT(test::errorOf([&] { compressFactor(zero, FactorOptions{}); }), HasSubstr("every value is 0"));
}

TEST(FactorBtf, DamagedFilesFailNamingTheFile) {
  test::TempDir dir;
  const FactorBtf f = compressFactor(test::makeAnalyticBtf(6, 6), FactorOptions{});
  f.write(dir / "f.btfz");
  const std::string bytes = readAll(dir / "f.btfz");
  for (const std::size_t keep : {bytes.size() - 1, bytes.size() / 2, std::size_t(40), std::size_t(3)}) {
    {
      std::ofstream cut(dir / "cut.btfz", std::ios::binary);
      cut.write(bytes.data(), std::streamsize(keep));
    }
    const std::string message = test::errorOf([&] { FactorBtf::read(dir / "cut.btfz"); });
    EXPECT_THAT(message, HasSubstr("cut.btfz")) << "kept " << keep << " bytes";
    EXPECT_THAT(test::errorOf([&] { readCompressedBtf(dir / "cut.btfz"); }), HasSubstr("cut.btfz"));
  }
  // Flipped bytes in the payload: an error naming the file, or (where zstd and the plane coder
  // cannot tell) values, never a crash.
  for (std::size_t at = bytes.size() / 3; at < bytes.size(); at += bytes.size() / 7) {
    std::string damaged = bytes;
    damaged[at] = char(damaged[at] ^ 0x5a);
    writeAll(dir / "flip.btfz", damaged);
    try {
      const FactorBtf g = FactorBtf::read(dir / "flip.btfz");
      std::vector<Rgb> view;
      g.loadView(g.views().views().front(), view);
    } catch (const FileError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr("flip.btfz"));
    }
  }
}

}  // namespace
}  // namespace btf
