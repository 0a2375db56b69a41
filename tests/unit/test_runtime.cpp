// The engine runtime (runtime/, libbtf::runtime) against the full library: the runtime file
// written from a VqBtf (compress/vq_runtime_export.h) gives the same value, eval, sample and pdf
// as BtfMaterial on that VqBtf, bit for bit (compared as float bits, not within a tolerance), on
// every codec path the runtime has: VQ with 1, 2 and 3 levels, level 3 packed (<= 2^16 level-2
// entries, as the writer stores every test BTF) and as float codes (rewritten), bilinear and
// nearest texels, a full BTF and one whose views are the rings up to 30 degrees. And bad files are refused with their name and problem.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "btf/compress/vq_runtime_export.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/core/warp.h"
#include "btf/material/btf_material.h"
#include "btf_runtime/file_layout.h"
#include "btf_runtime/material.h"
#include "btf_test_data.h"
#include "support/test_support.h"

namespace {

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }
btfrt::Vec3 toRt(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// Empty when the colours are the same floats, else both.
std::string difference(const btf::Rgb& a, const btfrt::Rgb& b) {
  if (bits(a.r) == bits(b.r) && bits(a.g) == bits(b.g) && bits(a.b) == bits(b.b)) return {};
  std::ostringstream s;
  s.precision(9);
  s << "library (" << a.r << ", " << a.g << ", " << a.b << "), runtime (" << b.r << ", " << b.g << ", " << b.b << ")";
  return s.str();
}

// A GGX pattern BTF compressed with `levels`, over the views `views`.
std::shared_ptr<const btf::VqBtf> compressed(int levels, const btf::BtfViewSet& views) {
  const btf::BtfData full = btf::test::makeGgxBtf(8, 8, false);
  btf::BtfData data(8, 8, "ggx-pattern", views);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int v : views.views())
        for (int l = 0; l < btf::kBtfDirectionCount; ++l) data.at(x, y, v, l) = full.at(x, y, v, l);
  btf::VqOptions options;
  options.levels = levels;
  return std::make_shared<const btf::VqBtf>(btf::compressVq(data, options));
}

std::vector<unsigned char> runtimeFileBytes(const std::filesystem::path& file) {
  std::vector<unsigned char> bytes(std::filesystem::file_size(file));
  std::ifstream(file, std::ios::binary).read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  return bytes;
}

// The same file with level 3 stored as (entry, float scale) records, the form the writer uses past
// 2^16 level-2 entries (more than a test BTF has): each packed code's scale decoded by the
// library's own decodeVqScale, which equals the packed form's table lookup (test_vq_btf.cpp).
void rewriteLevel3AsFloatCodes(const std::filesystem::path& file) {
  namespace rf = btfrt::file;
  const std::vector<unsigned char> bytes = runtimeFileBytes(file);
  rf::Header h;
  std::memcpy(&h, bytes.data(), sizeof h);
  std::vector<rf::Section> table(h.section_count);
  std::memcpy(table.data(), bytes.data() + rf::kHeaderBytes, table.size() * sizeof(rf::Section));
  std::vector<std::vector<unsigned char>> sections(table.size());
  for (std::size_t s = 0; s < table.size(); ++s)
    sections[s].assign(bytes.begin() + std::ptrdiff_t(table[s].offset), bytes.begin() + std::ptrdiff_t(table[s].offset + table[s].bytes));
  const std::size_t n = sections[rf::kL3Packed].size() / sizeof(rf::PackedCode);
  ASSERT_GT(n, 0u);
  std::vector<rf::SliceCode> codes(n);
  for (std::size_t k = 0; k < n; ++k) {
    rf::PackedCode p;
    std::memcpy(&p, sections[rf::kL3Packed].data() + k * sizeof p, sizeof p);
    codes[k] = {p.entry, p.scale == 0 ? 0.0f : float(std::exp2(double(p.scale) / 1024.0 - 40.0))};
  }
  sections[rf::kL3Codes].resize(n * sizeof(rf::SliceCode));
  std::memcpy(sections[rf::kL3Codes].data(), codes.data(), sections[rf::kL3Codes].size());
  sections[rf::kL3Packed].clear();
  std::uint64_t offset = rf::kHeaderBytes + table.size() * sizeof(rf::Section);
  for (std::size_t s = 0; s < table.size(); ++s) {
    offset = (offset + 15) / 16 * 16;
    table[s] = {offset, sections[s].size()};
    offset += sections[s].size();
  }
  h.file_bytes = offset;
  std::vector<unsigned char> out(offset, 0);
  std::memcpy(out.data(), &h, sizeof h);
  std::memcpy(out.data() + rf::kHeaderBytes, table.data(), table.size() * sizeof(rf::Section));
  for (std::size_t s = 0; s < table.size(); ++s)
    if (!sections[s].empty()) std::memcpy(out.data() + table[s].offset, sections[s].data(), sections[s].size());
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
}

void compareEverything(const std::shared_ptr<const btf::VqBtf>& vq, const std::string& label, bool float_level3 = false) {
  btf::test::TempDir dir;
  const auto file = dir / "material.btfrt";
  btf::writeVqRuntimeFile(*vq, file);
  if (float_level3) {
    rewriteLevel3AsFloatCodes(file);
    if (testing::Test::HasFatalFailure()) return;
  }
  for (const btf::BtfTexelFilter filter : {btf::BtfTexelFilter::Bilinear, btf::BtfTexelFilter::Nearest}) {
    const bool bilinear = filter == btf::BtfTexelFilter::Bilinear;
    const std::string where = label + (bilinear ? ", bilinear" : ", nearest");
    const btf::BtfMaterial library(vq, filter);
    const btfrt::Material runtime =
        btfrt::Material::open(file.string(), bilinear ? btfrt::TexelFilter::Bilinear : btfrt::TexelFilter::Nearest);
    ASSERT_EQ(runtime.width(), vq->width());
    ASSERT_EQ(runtime.height(), vq->height());
    // Every stored sample.
    if (bilinear) {
      for (int y = 0; y < vq->height(); ++y)
        for (int x = 0; x < vq->width(); ++x)
          for (int v : vq->views().views())
            for (int l = 0; l < btf::kBtfDirectionCount; ++l) {
              ASSERT_EQ(difference(vq->value(x, y, v, l), runtime.value(x, y, v, l)), "")
                  << where + " value(" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(v) +
                                 ", " + std::to_string(l) + ")";
            }
    }
    // eval, sample, pdf at random directions and uv, and pdf at the sampled directions.
    btf::Rng rng(91);
    int drawn = 0;
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 wi = btf::squareToUniformHemisphere(rng.uniform2D()), wo = btf::squareToUniformHemisphere(rng.uniform2D());
      const glm::vec2 uv = rng.uniform2D(), u = rng.uniform2D();
      const std::string at = where + " query " + std::to_string(i);
      ASSERT_EQ(difference(library.eval(wi, wo, uv), runtime.eval(toRt(wi), toRt(wo), uv.x, uv.y)), "") << at << " eval";
      ASSERT_EQ(bits(library.pdf(wi, wo, uv)), bits(runtime.pdf(toRt(wi), toRt(wo), uv.x, uv.y))) << at << " pdf";
      const std::optional<btf::BsdfSample> s = library.sample(wo, uv, u);
      btfrt::Sample r;
      const bool ok = runtime.sample(toRt(wo), uv.x, uv.y, u.x, u.y, r);
      ASSERT_EQ(s.has_value(), ok) << at << " sample drawn";
      if (!ok) continue;
      ++drawn;
      ASSERT_TRUE(bits(s->wi.x) == bits(r.wi.x) && bits(s->wi.y) == bits(r.wi.y) && bits(s->wi.z) == bits(r.wi.z)) << at << " sample wi";
      ASSERT_EQ(bits(s->pdf), bits(r.pdf)) << at << " sample pdf";
      ASSERT_EQ(difference(s->weight, r.weight), "") << at << " sample weight";
      ASSERT_EQ(bits(library.pdf(s->wi, wo, uv)), bits(runtime.pdf(r.wi, toRt(wo), uv.x, uv.y))) << at << " pdf of the sample";
    }
    EXPECT_GT(drawn, 19000) << where;  // every wo is above the surface: nearly every draw succeeds
  }
}

}  // namespace

TEST(Runtime, MatchesTheLibraryBitForBitOnEveryVqLevel) {
  for (int levels : {1, 2, 3}) compareEverything(compressed(levels, btf::BtfViewSet::all(btf::BtfDirectionSet::ubo2003())),
                                                 std::to_string(levels) + " levels");
}

TEST(Runtime, MatchesTheLibraryWithLevelThreeAsFloatCodes) {
  compareEverything(compressed(3, btf::BtfViewSet::all(btf::BtfDirectionSet::ubo2003())), "3 levels, float level-3 codes", true);
}

TEST(Runtime, MatchesTheLibraryOnViewsUpToThirtyDegrees) {
  for (int levels : {1, 3}) compareEverything(compressed(levels, btf::BtfViewSet::upToTheta(30.0f)),
                                              std::to_string(levels) + " levels, views to 30 degrees");
}

TEST(Runtime, ExportRefusesTheDome) {
  const btf::VqBtf dome = btf::compressVq(btf::test::makeGgxBtf(2, 2, false, btf::BtfDirectionSet::uboDome1()), {});
  btf::test::TempDir dir;
  try {
    btf::writeVqRuntimeFile(dome, dir / "dome.btfrt");
    ADD_FAILURE() << "a dome BTF was exported";
  } catch (const btf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("81-direction set only"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "dome.btfrt"));
}

TEST(Runtime, RefusesBadFilesNamingThem) {
  btf::test::TempDir dir;
  const auto file = dir / "m.btfrt";
  btf::writeVqRuntimeFile(*compressed(3, btf::BtfViewSet::all(btf::BtfDirectionSet::ubo2003())), file);
  const std::vector<unsigned char> bytes = runtimeFileBytes(file);
  auto expectRefused = [&](const std::vector<unsigned char>& b, const std::string& problem) {
    try {
      btfrt::Material::fromBytes(b.data(), b.size(), "bad.btfrt");
      ADD_FAILURE() << "accepted: " << problem;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.btfrt: ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  };
  expectRefused(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 40), "not a libbtf runtime file");
  expectRefused(std::vector<unsigned char>(bytes.begin(), bytes.end() - 8), "truncated");
  auto bad_magic = bytes;
  bad_magic[0] = 'X';
  expectRefused(bad_magic, "not a libbtf runtime file");
  // A top code pointing past the level-3 codebook.
  btfrt::file::Section top;
  std::memcpy(&top, bytes.data() + btfrt::file::kHeaderBytes + sizeof(top) * btfrt::file::kTopCodes, sizeof top);
  auto bad_index = bytes;
  const std::uint32_t huge = 0x7fffffffu;
  std::memcpy(bad_index.data() + top.offset, &huge, sizeof huge);
  expectRefused(bad_index, "top_codes code 0 is outside its codebook");
  // A NaN scale.
  auto bad_scale = bytes;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bad_scale.data() + top.offset + 4, &nan, sizeof nan);
  expectRefused(bad_scale, "invalid scale");
  try {
    btfrt::Material::open((dir / "missing.btfrt").string());
    ADD_FAILURE() << "a missing file opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.btfrt: cannot be opened"), std::string::npos) << e.what();
  }
}
