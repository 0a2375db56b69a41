// Level-1 entries coded in a learned principal basis of their ring (compress/vq_basis.h): the
// basis is orthonormal and ordered by energy, every entry stays within the budget it was given,
// and compressed files that use it keep the bounds of vq_btf.h, read back exactly, stay
// independent of the thread count, and merge losslessly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <memory>
#include <random>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "btf/io/container.h"
#include "btf_test_data.h"
#include "support/test_support.h"
#include "camera_btf.h"
#include "compress/vq_basis.h"
#include "compress/vq_impl.h"
#include "btf_patterns.h"
#include "synthetic_btf.h"

namespace {

// 48 x 48 texels of the calibrated print through the camera (enough lit vectors, 4 n^2 = 2304, for
// every ring's basis), two views to keep the test short.
struct CameraPrint48 {
  std::unique_ptr<btf::synthetic::SyntheticBtf> print =
      btf::synthetic::makeSyntheticBtf(btf::synthetic::BtfPattern::Print, 48, 48, 1);
  btf::synthetic::CameraBtf camera{*print, btf::synthetic::measuredCameraOptions(*print, 1)};
  btf::BtfData full{btf::BtfData::copyOf(btf::BtfSubset(camera, {0, 0, 48, 48}, btf::BtfViewSet({0, 40})))};
};
const btf::BtfData& print48() {
  static const CameraPrint48 btf;
  return btf.full;
}

btf::VqOptions options(float epsilon, int levels, bool cut = true) {
  btf::VqOptions o;
  o.level1_cut = cut;
  o.epsilon = epsilon;
  o.chroma_epsilon = 0.1f;
  o.levels = levels;
  return o;
}

std::vector<btf::Rgb> firstView(const btf::BtfSource& source) {
  std::vector<btf::Rgb> view;
  source.loadView(source.views().view(0), view);
  return view;
}

TEST(VqBasis, LearnedBasisIsOrthonormalAndOrderedByEnergy) {
  const auto view = firstView(print48());
  const auto bases = btf::learnVqRingBases(view, print48().texelCount(), btf::BtfRingLayout::ubo2003(), 64.0f / 65535.0f);
  ASSERT_EQ(bases.size(), std::size_t(btf::kBtfRingCount));
  EXPECT_TRUE(bases[0].empty());
  for (int r = 1; r < btf::kBtfRingCount; ++r) {
    const btf::VqRingBasis& b = bases[std::size_t(r)];
    const int n = btf::btfRingSize(r);
    ASSERT_EQ(b.n, n) << "ring " << r;
    ASSERT_EQ(b.v.size(), std::size_t(n * n));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double d = 0;
        for (int a = 0; a < n; ++a) d += double(b.v[std::size_t(a * n + i)]) * b.v[std::size_t(a * n + j)];
        EXPECT_NEAR(d, i == j ? 1.0 : 0.0, 1e-5) << "ring " << r << " columns " << i << ", " << j;
      }
    // The energy of the view's unit functions along each direction does not grow with j.
    std::vector<double> energy(static_cast<std::size_t>(n), 0.0);
    const std::size_t T = print48().texelCount();
    for (std::size_t t = 0; t < T; ++t) {
      std::vector<double> u(static_cast<std::size_t>(n));
      double len2 = 0;
      for (int a = 0; a < n; ++a) {
        u[std::size_t(a)] = view[std::size_t(btf::btfRingStart(r) + a) * T + t].luminance();
        len2 += u[std::size_t(a)] * u[std::size_t(a)];
      }
      if (!(len2 > 0)) continue;
      for (int j = 0; j < n; ++j) {
        double c = 0;
        for (int a = 0; a < n; ++a) c += b.v[std::size_t(a * n + j)] * u[std::size_t(a)];
        energy[std::size_t(j)] += c * c / len2;
      }
    }
    for (int j = 1; j < n; ++j)
      EXPECT_LE(energy[std::size_t(j)], energy[std::size_t(j - 1)] * (1 + 1e-6) + 1e-9) << "ring " << r << ", direction " << j;
  }
}

TEST(VqBasis, FewLitVectorsKeepTheValueByValueForm) {
  // 20 x 20 = 400 texels: enough for ring 1 (4 * 36 = 144), not for ring 2 (4 * 144 = 576).
  const btf::BtfSubset small(print48(), {0, 0, 20, 20}, print48().views());
  const auto bases = btf::learnVqRingBases(firstView(small), small.texelCount(), btf::BtfRingLayout::ubo2003(), 64.0f / 65535.0f);
  EXPECT_FALSE(bases[1].empty());
  for (int r = 2; r < btf::kBtfRingCount; ++r) EXPECT_TRUE(bases[std::size_t(r)].empty()) << "ring " << r;
}

// Over 2,000 random non-negative unit functions per ring and five budgets: the stored entry (the
// 16-bit codes of the kept coefficients' reconstruction) is within the budget plus the rounding
// VqPrecision allows (sqrt(n) step / 2) plus the 16-bit codes' own (sqrt(n) / 2 / 65535), and the
// budget is used: larger budgets keep fewer coefficients.
TEST(VqBasis, StoredEntriesStayWithinTheirBudget) {
  const auto bases = btf::learnVqRingBases(firstView(print48()), print48().texelCount(), btf::BtfRingLayout::ubo2003(), 128.0f / 65535.0f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int r = 1; r < btf::kBtfRingCount; ++r) {
    const btf::VqRingBasis& b = bases[std::size_t(r)];
    const int n = b.n;
    ASSERT_FALSE(b.empty());
    std::size_t previous_zeros = 0;
    for (double budget : {0.0, 0.02, 0.05, 0.1, 0.3}) {
      std::size_t zeros = 0;
      double worst = 0;
      for (int i = 0; i < 2000; ++i) {
        std::vector<float> u(static_cast<std::size_t>(n));
        double len2 = 0;
        for (float& x : u) {
          x = 0.5f + uniform(rng) * uniform(rng);
          len2 += double(x) * x;
        }
        for (float& x : u) x = float(x / std::sqrt(len2));
        std::vector<std::int32_t> c(static_cast<std::size_t>(n));
        std::vector<std::uint16_t> codes(static_cast<std::size_t>(n));
        btf::vqBasisCoefficients(b, u, budget, c.data());
        btf::vqBasisCodes(b, c.data(), codes.data());
        double e2 = 0;
        for (int a = 0; a < n; ++a) {
          const double d = btf::decodeVqEntryValue(codes[std::size_t(a)]) - u[std::size_t(a)];
          e2 += d * d;
        }
        worst = std::max(worst, std::sqrt(e2));
        for (std::int32_t k : c) zeros += k == 0;
      }
      const double allowed = budget + std::sqrt(double(n)) * (b.step / 2.0 + 0.5 / 65535.0);
      EXPECT_LE(worst, allowed) << "ring " << r << ", budget " << budget;
      EXPECT_GE(zeros, previous_zeros) << "ring " << r << ", budget " << budget;
      if (budget >= 0.05) {
        EXPECT_GT(zeros, previous_zeros) << "ring " << r << ", budget " << budget << ": no coefficient dropped";
      }
      previous_zeros = zeros;
    }
  }
}

TEST(VqBasis, CompressedFilesUseItKeepTheBoundAndReadBackExactly) {
  btf::test::TempDir dir;
  for (int levels : {1, 3}) {
    const btf::VqBtf vq = btf::compressVq(print48(), options(0.1f, levels));
    const btf::VqBtf::Impl& m = vq.impl();
    for (int r = 1; r < btf::kBtfRingCount; ++r) {
      ASSERT_FALSE(m.l1_basis[std::size_t(r)].empty()) << "ring " << r;
      EXPECT_EQ(m.l1_coef[std::size_t(r)].size(), m.l1[std::size_t(r)].size()) << "ring " << r;
    }
    EXPECT_LE(btf::test::luminanceRelRmse(print48(), vq), btf::test::vqLuminanceBound(0.1f, levels)) << levels << " levels";
    const auto path = dir / ("basis" + std::to_string(levels) + ".btfz");
    vq.write(path);
    const btf::VqBtf back = btf::VqBtf::read(path);
    for (int r = 0; r < btf::kBtfRingCount; ++r) {
      EXPECT_EQ(back.impl().l1[std::size_t(r)], m.l1[std::size_t(r)]) << "ring " << r;
      EXPECT_EQ(back.impl().l1_coef[std::size_t(r)], m.l1_coef[std::size_t(r)]) << "ring " << r;
    }
    EXPECT_EQ(std::filesystem::file_size(path), vq.stats().compressed_bytes);
  }
  // Without level1_cut the entries are stored value by value (files as before), and with it the
  // cut leaves many coefficients zero.
  const btf::VqBtf plain = btf::compressVq(print48(), options(0.1f, 1, false));
  const btf::VqBtf cut = btf::compressVq(print48(), options(0.1f, 1, true));
  std::size_t coefficients = 0, zeros = 0;
  for (int r = 1; r < btf::kBtfRingCount; ++r) {
    EXPECT_TRUE(plain.impl().l1_basis[std::size_t(r)].empty()) << "ring " << r;
    EXPECT_TRUE(plain.impl().l1_coef[std::size_t(r)].empty()) << "ring " << r;
    coefficients += cut.impl().l1_coef[std::size_t(r)].size();
    for (std::int32_t k : cut.impl().l1_coef[std::size_t(r)]) zeros += k == 0;
  }
  EXPECT_GT(zeros, coefficients / 4);
  // Epsilon 0 keeps every value as it is: no basis.
  const btf::VqBtf exact = btf::compressVq(print48(), options(0.0f, 1));
  for (int r = 0; r < btf::kBtfRingCount; ++r) EXPECT_TRUE(exact.impl().l1_basis[std::size_t(r)].empty());
}

TEST(VqBasis, OutputDoesNotDependOnTheThreadCount) {
  btf::VqOptions one = options(0.1f, 2), two = options(0.1f, 2);
  one.threads = 1;
  two.threads = 2;
  const btf::VqBtf a = btf::compressVq(print48(), one), b = btf::compressVq(print48(), two);
  for (int r = 0; r < btf::kBtfRingCount; ++r) {
    EXPECT_EQ(a.impl().l1_coef[std::size_t(r)], b.impl().l1_coef[std::size_t(r)]);
    EXPECT_EQ(a.impl().l1_basis[std::size_t(r)].v, b.impl().l1_basis[std::size_t(r)].v);
  }
  EXPECT_EQ(a.impl().top_index, b.impl().top_index);
  EXPECT_EQ(a.stats().compressed_bytes, b.stats().compressed_bytes);
}

// Files compressed alone learn different bases: their merge stores the rings value by value and
// decodes every material exactly as before. A database compressed at once shares one basis.
TEST(VqBasis, MergesAreLosslessAndDatabasesShareTheBasis) {
  // Two 48 x 24 halves: 1152 texels, bases for rings 1..3 (4 n^2 <= 1152).
  const btf::BtfData top = btf::BtfData::copyOf(btf::BtfSubset(print48(), {0, 0, 48, 24}, print48().views()));
  const btf::BtfData bottom = btf::BtfData::copyOf(btf::BtfSubset(print48(), {0, 24, 48, 24}, print48().views()));
  const btf::VqDatabase a(std::vector<btf::VqBtf>{btf::compressVq(top, options(0.1f, 2))});
  const btf::VqDatabase b(std::vector<btf::VqBtf>{btf::compressVq(bottom, options(0.1f, 2))});
  ASSERT_FALSE(a.materials()[0].impl().l1_basis[1].empty());
  ASSERT_TRUE(a.materials()[0].impl().l1_basis[4].empty());
  const btf::VqDatabase parts[] = {a, b};
  const btf::VqDatabase merged = btf::mergeVqDatabases(parts);
  EXPECT_TRUE(merged.materials()[0].impl().l1_basis[1].empty());
  for (std::size_t i = 0; i < 2; ++i) {
    const btf::VqBtf& before = (i == 0 ? a : b).materials()[0];
    const btf::VqBtf& after = merged.materials()[i];
    for (int view : before.views().views()) {
      std::vector<btf::Rgb> x, y;
      before.loadView(view, x);
      after.loadView(view, y);
      ASSERT_EQ(x.size(), y.size());
      EXPECT_EQ(0, std::memcmp(x.data(), y.data(), x.size() * sizeof(btf::Rgb))) << "material " << i << ", view " << view;
    }
  }
  btf::test::TempDir dir;
  const btf::BtfSource* sources[] = {&top, &bottom};
  btf::VqDatabase database = btf::compressVqDatabase(sources, {"top", "bottom"}, options(0.1f, 2));
  ASSERT_FALSE(database.materials()[1].impl().l1_basis[1].empty());
  database.write(dir / "db.btfz");
  const btf::VqDatabase back = btf::VqDatabase::read(dir / "db.btfz");
  EXPECT_EQ(back.materials()[1].impl().l1_coef[1], database.materials()[1].impl().l1_coef[1]);
  EXPECT_EQ(back.materials()[1].impl().l1[3], database.materials()[1].impl().l1[3]);
}

// A damaged basis section is a FileError naming the file, never a silent decode.
TEST(VqBasis, ReaderRejectsADamagedBasis) {
  btf::test::TempDir dir;
  const auto good = dir / "good.btfz";
  btf::compressVq(print48(), options(0.1f, 1)).write(good);
  auto expectError = [&](const std::string& name, const std::function<void(std::vector<btf::ContainerSection>&)>& change,
                         const std::string& words) {
    const auto path = btf::test::rewriteContainer(good, dir / (name + ".btfz"), change);
    try {
      btf::VqBtf::read(path);
      ADD_FAILURE() << name << " accepted";
    } catch (const btf::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
    }
  };
  auto onBasis = [](auto&& f) {
    return [f](std::vector<btf::ContainerSection>& sections) {
      for (auto& s : sections)
        if (s.name == "level1/basis3") f(s);
    };
  };
  expectError("nan", onBasis([](btf::ContainerSection& s) {
                const float nan = std::nanf("");
                std::memcpy(s.data.data() + 8, &nan, sizeof nan);
              }),
              "out of range");
  expectError("step", onBasis([](btf::ContainerSection& s) {
                const float zero = 0.0f;
                std::memcpy(s.data.data(), &zero, sizeof zero);
              }),
              "out of range");
  expectError("short", onBasis([](btf::ContainerSection& s) { s.data.resize(s.data.size() - 4); }), "basis");
}

}  // namespace
