// Multi-level VQ on data recorded through a camera (synthetic/camera_btf.h: registration jitter,
// sensor noise, 8-bit codes), as measured BTFs are: texels of the same print share level-3
// entries within the bounds of vq_btf.h, near-twins derive their entries from another's in a few
// exception views (stored as such, read back whole), and no codebook keeps an entry nothing
// references.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/io/btf_quality.h"
#include "btf/io/container.h"
#include "support/test_support.h"
#include "btf_test_data.h"
#include "compress/vq_impl.h"
#include "compress/vq_sections.h"
#include "btf_patterns.h"
#include "camera_btf.h"
#include "synthetic_btf.h"

namespace {

// The calibrated stand-in for a measured BTF (docs/design-notes.md#a-generator-calibrated-to-real-data)
// at 16 x 16 texels: the print motif repeats every 8-24 texels, so texels have noisy near-twins.
struct CameraPrint {
  std::unique_ptr<btf::synthetic::SyntheticBtf> print =
      btf::synthetic::makeSyntheticBtf(btf::synthetic::BtfPattern::Print, 16, 16, 1);
  btf::synthetic::CameraBtf camera{*print, btf::synthetic::measuredCameraOptions(*print, 1)};
  btf::BtfData data{btf::BtfData::copyOf(camera)};
};
const btf::BtfData& cameraPrint() {
  static const CameraPrint btf;
  return btf.data;
}

btf::VqOptions printOptions(int levels) {
  btf::VqOptions options;
  options.epsilon = 0.2f;
  options.chroma_epsilon = 0.25f;
  options.levels = levels;
  return options;
}

// Every entry but the seed (entry 0) of each of the shared codebooks is reached from some
// material's codes.
void expectEveryEntryReferenced(const btf::VqBtf::Impl& books, const std::vector<const btf::VqBtf::Impl*>& materials) {
  const int levels = books.options.levels;
  std::vector<bool> used2(books.l2Count(), false);
  if (levels >= 2) {
    for (const auto* m : materials)
      for (std::uint32_t e : levels == 3 ? m->l3_index : m->top_index) used2.at(e) = true;
    for (std::size_t e = 1; e < used2.size(); ++e) EXPECT_TRUE(used2[e]) << "level-2 entry " << e << " of " << used2.size();
  }
  for (int r = 0; r < btf::kBtfRingCount; ++r) {
    std::vector<bool> used1(books.l1Count(r), false), used_c(books.chromaCount(r), false);
    auto mark = [&](const std::vector<std::uint32_t>& index, const std::vector<std::uint32_t>& chroma) {
      for (std::size_t k = std::size_t(r); k < index.size(); k += btf::kBtfRingCount) {
        used1.at(index[k]) = true;
        used_c.at(chroma[k]) = true;
      }
    };
    if (levels >= 2)
      mark(books.l2_index, books.l2_chroma);
    else
      for (const auto* m : materials) mark(m->top_index, m->top_chroma);
    for (std::size_t e = 1; e < used1.size(); ++e) EXPECT_TRUE(used1[e]) << "ring " << r << ", level-1 entry " << e;
    for (std::size_t e = 1; e < used_c.size(); ++e) EXPECT_TRUE(used_c[e]) << "ring " << r << ", chroma entry " << e;
  }
}

}  // namespace

TEST(VqCamera, NoisyTexelsOfOnePrintShareLevelThreeEntriesWithinTheTolerance) {
  const btf::BtfData& data = cameraPrint();
  const btf::VqBtf two = btf::compressVq(data, printOptions(2));
  const btf::VqBtf three = btf::compressVq(data, printOptions(3));
  const auto& entries = three.stats().codebook_entries;
  ASSERT_EQ(entries.size(), 3u);
  const double rgb2 = btf::compareBtf(data, two).rel_rmse, rgb3 = btf::compareBtf(data, three).rel_rmse;
  // Level 3 works on the level-2 reconstruction, which is the 2-level file's (levels 1 and 2 do
  // not depend on the level count): it adds at most the tolerance of one level to the luminance.
  const double added = btf::test::luminanceRelRmse(two, three);
  std::printf("16 x 16 print through the camera, epsilon 0.2, chroma 0.25: entries %zu %zu %zu, ratio_u8 %.1f "
              "(2 levels %.1f); rgb rel_rmse %.4f (2 levels %.4f); level 3 adds luminance %.4f\n",
              entries[0], entries[1], entries[2], three.stats().ratio_u8, two.stats().ratio_u8, rgb3, rgb2, added);
  // With a chroma test per ring and view every one of the 256 texels was its own entry.
  EXPECT_LT(entries[2], 256u / 2);
  EXPECT_GT(three.stats().ratio_u8, 1.3 * two.stats().ratio_u8);
  EXPECT_LE(added, btf::test::vqLuminanceBound(0.2f, 1));
  // The colour: taking texels of the other ink (no chroma test at all) raises the RGB error well
  // above level 2's on the print; the whole-texel test keeps it near level 2's.
  EXPECT_LT(rgb3, 1.25 * rgb2);
}

TEST(VqCamera, NoCodebookKeepsAnEntryNothingReferences) {
  const btf::BtfData& data = cameraPrint();
  for (int levels = 1; levels <= 3; ++levels) {
    SCOPED_TRACE("levels " + std::to_string(levels));
    const btf::VqBtf vq = btf::compressVq(data, printOptions(levels));
    expectEveryEntryReferenced(vq.impl(), {&vq.impl()});
  }
  // A database: the shared codebooks are pruned against all its materials at once.
  const btf::BtfData ggx = btf::test::makeGgxBtf(8, 8, false);
  const btf::BtfSource* sources[] = {&data, &ggx};
  const btf::VqDatabase database = btf::compressVqDatabase(sources, {"print", "ggx"}, printOptions(3));
  const auto& first = database.materials()[0].impl();
  expectEveryEntryReferenced(first, {&first, &database.materials()[1].impl()});
  // Each material decodes within its bound after the renumbering.
  const btf::VqBtf& g = database.material("ggx");
  EXPECT_LE(btf::test::luminanceRelRmse(ggx, g), btf::test::vqLuminanceBound(0.2f, 3));
}

// The compressor stores codes at the precision its tolerance allows (vq_impl.h): every scale code
// and every level-1 value it wrote (the seeds, entry 0, excepted) is a multiple of its step.
TEST(VqCamera, StoredCodesKeepThePrecisionTheToleranceAllows) {
  const btf::VqBtf vq = btf::compressVq(cameraPrint(), printOptions(3));
  const btf::VqBtf::Impl& m = vq.impl();
  const btf::VqPrecision p = btf::vqPrecisionFor(0.2f, btf::BtfRingLayout::ubo2003().maxSize());
  ASSERT_GT(p.scale_shift, 0);
  ASSERT_GT(p.value_shift, 0);
  auto expectMultiples = [](const std::vector<std::uint16_t>& codes, std::size_t skip, int shift, const char* what) {
    std::size_t off = 0;
    for (std::size_t i = skip; i < codes.size(); ++i) off += codes[i] % (1u << shift) != 0 && codes[i] != 65535;
    EXPECT_EQ(off, 0u) << what << ": " << off << " of " << codes.size() - skip << " codes off the step 2^" << shift;
  };
  for (int r = 1; r < btf::kBtfRingCount; ++r)
    expectMultiples(m.l1[std::size_t(r)], std::size_t(btf::btfRingSize(r)), p.value_shift, "level-1 values");
  expectMultiples(m.l2_scale, btf::kBtfRingCount, p.scale_shift, "level-2 scales");
  expectMultiples(m.l3_scale, m.viewCount(), p.scale_shift, "level-3 scales");
  expectMultiples(m.top_scale, 0, p.scale_shift, "texel scales");
  EXPECT_LE(btf::test::luminanceRelRmse(cameraPrint(), vq), btf::test::vqLuminanceBound(0.2f, 3));
}

// Views in which level-3 entry e's codes differ from entry p's.
std::size_t differingViews(const btf::VqBtf::Impl& m, std::size_t e, std::size_t p) {
  const std::size_t V = m.viewCount();
  std::size_t n = 0;
  for (std::size_t v = 0; v < V; ++v)
    n += m.l3_index[e * V + v] != m.l3_index[p * V + v] || m.l3_scale[e * V + v] != m.l3_scale[p * V + v];
  return n;
}

// A texel no entry fits but one nearly does (a few views off) gets that entry with its own codes in
// those views, which the file stores alone (vq_impl.h).
TEST(VqCamera, NearTwinTexelsDeriveTheirEntryInAFewExceptionViews) {
  const btf::VqBtf vq = btf::compressVq(cameraPrint(), printOptions(3));
  const btf::VqBtf::Impl& m = vq.impl();
  ASSERT_EQ(m.l3_parent.size(), m.l3Count());
  const std::size_t V = m.viewCount();
  const std::size_t most = std::size_t(std::floor(btf::kVqMaxExceptionShare * double(V)));
  std::size_t derived = 0, exceptions = 0;
  for (std::size_t e = 0; e < m.l3Count(); ++e) {
    if (m.l3_parent[e] == 0) continue;
    const std::size_t p = m.l3_parent[e] - 1;
    ASSERT_LT(p, e);
    const std::size_t n = differingViews(m, e, p);
    EXPECT_GE(n, 1u) << "entry " << e << " repeats its parent " << p;
    EXPECT_LE(n, most) << "entry " << e;
    ++derived;
    exceptions += n;
  }
  std::printf("16 x 16 print: %zu of %zu level-3 entries derived, %.1f exception views each (at most %zu)\n", derived,
              m.l3Count(), derived ? double(exceptions) / double(derived) : 0.0, most);
  EXPECT_GT(derived, m.l3Count() / 4);
  EXPECT_LE(btf::test::luminanceRelRmse(cameraPrint(), vq), btf::test::vqLuminanceBound(0.2f, 3));
}

// The option off: every entry matched or whole, as files were before (format version 1), more
// bytes for the same data, fewer level-3 entries in the decoded tables.
TEST(VqCamera, WithoutExceptionsEveryLevelThreeEntryIsWhole) {
  btf::VqOptions options = printOptions(3);
  const btf::VqBtf with = btf::compressVq(cameraPrint(), options);
  options.level3_exceptions = false;
  const btf::VqBtf without = btf::compressVq(cameraPrint(), options);
  const btf::VqBtf::Impl& m = without.impl();
  EXPECT_TRUE(std::all_of(m.l3_parent.begin(), m.l3_parent.end(), [](std::uint32_t p) { return p == 0; }));
  EXPECT_FALSE(btf::hasDerivedLevel3(m));
  EXPECT_EQ(btf::vqSectionsVersion(m), 1);
  EXPECT_EQ(btf::vqSectionsVersion(with.impl()), 3);
  std::printf("16 x 16 print: ratio_u8 %.1f with exceptions, %.1f without; level-3 entries %zu and %zu\n",
              with.stats().ratio_u8, without.stats().ratio_u8, with.impl().l3Count(), m.l3Count());
  EXPECT_GT(with.stats().ratio_u8, without.stats().ratio_u8);
  EXPECT_LE(btf::test::luminanceRelRmse(cameraPrint(), without), btf::test::vqLuminanceBound(0.2f, 3));
}

TEST(VqCamera, DerivedEntriesAreStoredAsTheirExceptionsAndReadBackWhole) {
  btf::test::TempDir dir;
  const btf::VqBtf vq = btf::compressVq(cameraPrint(), printOptions(3));
  vq.write(dir / "derived.btfz");
  const btf::VqBtf back = btf::VqBtf::read(dir / "derived.btfz");
  EXPECT_EQ(back.impl().l3_parent, vq.impl().l3_parent);
  EXPECT_EQ(back.impl().l3_index, vq.impl().l3_index);
  EXPECT_EQ(back.impl().l3_scale, vq.impl().l3_scale);
  std::vector<btf::Rgb> a, b;
  for (int v : {0, 17, 80}) {
    vq.loadView(v, a);
    back.loadView(v, b);
    EXPECT_EQ(a, b) << "view " << v;
  }
  // The same entries stored whole: larger, and read back to the same rows.
  auto whole = std::make_shared<btf::VqBtf::Impl>(vq.impl());
  whole->l3_parent.clear();
  btf::VqBtf(whole).write(dir / "whole.btfz");
  const auto derived_bytes = std::filesystem::file_size(dir / "derived.btfz");
  const auto whole_bytes = std::filesystem::file_size(dir / "whole.btfz");
  std::printf("derived entries stored as exceptions: %ju bytes, stored whole: %ju bytes\n", std::uintmax_t(derived_bytes),
              std::uintmax_t(whole_bytes));
  EXPECT_LT(derived_bytes, whole_bytes);
  EXPECT_EQ(btf::VqBtf::read(dir / "whole.btfz").impl().l3_index, vq.impl().l3_index);
  // In a database too (per-material sections).
  const btf::BtfSource* sources[] = {&cameraPrint()};
  btf::VqDatabase database = btf::compressVqDatabase(sources, {"print"}, printOptions(3));
  database.write(dir / "db.btfz");
  const btf::VqBtf from_db = btf::VqBtf::read(dir / "db.btfz", "print");
  EXPECT_EQ(from_db.impl().l3_index, database.material("print").impl().l3_index);
}

TEST(VqCamera, ReaderRejectsInconsistentExceptions) {
  btf::test::TempDir dir;
  const btf::VqBtf vq = btf::compressVq(cameraPrint(), printOptions(3));
  const auto good = dir / "good.btfz";
  vq.write(good);
  const btf::VqBtf::Impl& m = vq.impl();
  std::size_t first_derived = 0;
  while (m.l3_parent.at(first_derived) == 0) ++first_derived;
  auto section = [](std::vector<btf::ContainerSection>& sections, const std::string& name) -> btf::ContainerSection& {
    for (auto& s : sections)
      if (s.name == name) return s;
    throw std::runtime_error("no section " + name);
  };
  // Each section holds one byte plane here (small values); its values start at byte 1.
  auto expectRejected = [&](const std::string& name, const std::string& message,
                            const std::function<void(std::vector<btf::ContainerSection>&)>& change) {
    const auto path = btf::test::rewriteContainer(good, dir / (name + ".btfz"), change);
    try {
      btf::VqBtf::read(path);
      ADD_FAILURE() << name << " accepted";
    } catch (const btf::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << name << ": " << e.what();
    }
  };
  expectRejected("forward", "not an earlier one", [&](auto& sections) {
    auto& parent = section(sections, "level3/parent");
    ASSERT_EQ(int(parent.data[0]), m.l3Count() < 256 ? 1 : 2);
    parent.data[1 + first_derived] = std::byte(first_derived + 1);  // itself
  });
  expectRejected("unordered", "not ascending", [&](auto& sections) {
    auto& views = section(sections, "level3/exception_view");
    ASSERT_EQ(int(views.data[0]), 1);
    views.data[1] = std::byte(0xff);
  });
  expectRejected("short", "ends before", [&](auto& sections) {
    auto& counts = section(sections, "level3/exception_count");
    counts.data.pop_back();
  });
  expectRejected("extra", "more exceptions or codes", [&](auto& sections) {
    auto& counts = section(sections, "level3/exception_count");
    counts.data.push_back(std::byte(1));
  });
  expectRejected("too many entries", "entries for", [&](auto& sections) {
    auto& parent = section(sections, "level3/parent");
    const int width = int(parent.data[0]);
    std::vector<std::byte> grown(1 + std::size_t(width) * 300, std::byte(0));
    grown[0] = std::byte(width);
    parent.data = grown;
  });
}
