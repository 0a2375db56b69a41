// Multi-level VQ compression (compress/vq_btf.h) on tiny analytic BTFs (btf_test_data.h): error
// within the bound the tolerance implies, near-lossless at epsilon 0, thread-count independence,
// .btfz round trip and the reader's rejections.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/container.h"
#include "btf_test_data.h"
#include "support/test_support.h"

namespace {

using btf::test::vqLuminanceBound;

using btf::test::expectSameDecode;

const btf::BtfData& constantChromaBtf() {
  static const btf::BtfData data = btf::test::makeGgxBtf(8, 8, true);
  return data;
}
const btf::BtfData& varyingChromaBtf() {
  static const btf::BtfData data = btf::test::makeGgxBtf(8, 8, false);
  return data;
}

}  // namespace

TEST(VqBtf, RoundTripErrorWithinTheToleranceBoundAtEveryLevel) {
  for (int levels = 1; levels <= 3; ++levels)
    for (float epsilon : {0.01f, 0.05f}) {
      btf::VqOptions options;
      options.epsilon = epsilon;
      options.levels = levels;
      const btf::VqBtf vq = btf::compressVq(constantChromaBtf(), options);
      const double lum = btf::test::luminanceRelRmse(constantChromaBtf(), vq);
      EXPECT_LE(lum, vqLuminanceBound(epsilon, levels)) << "levels " << levels << ", epsilon " << epsilon;
      // Constant chromaticity per texel: RGB adds at most ~0.79 chroma_epsilon (vq_btf.h).
      const btf::BtfErrorStats rgb = btf::compareBtf(constantChromaBtf(), vq);
      EXPECT_LE(rgb.rel_rmse, vqLuminanceBound(epsilon, levels) + 3.0 * options.chroma_epsilon);
      ASSERT_EQ(vq.stats().codebook_entries.size(), std::size_t(levels));
      EXPECT_GT(vq.stats().ratio_u8, 1.0);
      // value() decodes the same entries as loadView().
      std::vector<btf::Rgb> view;
      vq.loadView(40, view);
      for (int l : {0, 5, 30, 80})
        for (int t : {0, 9, 63})
          EXPECT_EQ(vq.value(t % 8, t / 8, 40, l), view[std::size_t(l) * 64 + std::size_t(t)]);
    }
}

TEST(VqBtf, LargerToleranceGivesFewerEntries) {
  btf::VqOptions fine, coarse;
  fine.epsilon = 0.01f;
  coarse.epsilon = 0.1f;
  const auto a = btf::compressVq(varyingChromaBtf(), fine), b = btf::compressVq(varyingChromaBtf(), coarse);
  // Level 1 sees the data itself; the upper levels see reconstructions that change with epsilon,
  // so only the level-1 count and the total size are monotone.
  EXPECT_LT(b.stats().codebook_entries[0], a.stats().codebook_entries[0]);
  EXPECT_GT(b.stats().ratio_u8, a.stats().ratio_u8);
}

TEST(VqBtf, ScaledCopiesOfOneTexelShareEveryEntry) {
  // Every texel is texel (0, 0) times a factor: one texel's worth of entries at each level.
  const btf::BtfData& src = constantChromaBtf();
  btf::BtfData copies(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int v = 0; v < btf::kBtfDirectionCount; ++v)
        for (int l = 0; l < btf::kBtfDirectionCount; ++l) copies.at(x, y, v, l) = src.at(0, 0, v, l) * (0.5f + 0.25f * float(x + 4 * y));
  btf::VqOptions options;
  options.epsilon = 0.01f;
  options.energy_floor = 0.0f;  // purely relative: invariant under scaling
  const auto vq = btf::compressVq(copies, options);
  EXPECT_EQ(vq.stats().codebook_entries[2], 2u);  // the seed (uniform texel) + one
  const auto single = btf::compressVq(btf::test::makeGgxBtf(1, 1, true), options);
  EXPECT_EQ(vq.stats().codebook_entries[1], single.stats().codebook_entries[1]);
  EXPECT_LE(btf::test::luminanceRelRmse(copies, vq), vqLuminanceBound(0.01f, 3, 0.0f));
}

TEST(VqBtf, PurelyRelativeToleranceHasTheTighterBound) {
  btf::VqOptions options;
  options.epsilon = 0.02f;
  options.energy_floor = 0.0f;
  const btf::VqBtf strict = btf::compressVq(constantChromaBtf(), options);
  EXPECT_LE(btf::test::luminanceRelRmse(constantChromaBtf(), strict), vqLuminanceBound(0.02f, 3, 0.0f));
  options.energy_floor = 1.0f;
  const btf::VqBtf floored = btf::compressVq(constantChromaBtf(), options);
  EXPECT_LE(floored.stats().codebook_entries[0], strict.stats().codebook_entries[0]);
}

TEST(VqBtf, EpsilonZeroIsNearLossless) {
  btf::VqOptions options;
  options.epsilon = 0.0f;
  options.chroma_epsilon = btf::kVqMinChromaEpsilon;
  const btf::VqBtf vq = btf::compressVq(constantChromaBtf(), options);
  EXPECT_LT(btf::test::luminanceRelRmse(constantChromaBtf(), vq), 2e-3);
  EXPECT_LT(btf::compareBtf(constantChromaBtf(), vq).rel_rmse, 2e-3);
}

// RGB rel_rmse of the exact luminance with one chromaticity per ring (the energy-weighted mean):
// the floor of a one-chroma-per-ring scheme, which the bound must be below for the test to bite.
static double ringMeanChromaRelRmse(const btf::BtfSource& data) {
  std::vector<btf::Rgb> values;
  double err = 0, ref = 0;
  const std::size_t T = data.texelCount();
  for (int v = 0; v < btf::kBtfDirectionCount; ++v) {
    data.loadView(v, values);
    for (std::size_t t = 0; t < T; ++t)
      for (int r = 0; r < btf::kBtfRingCount; ++r) {
        double sr = 0, sg = 0, sb = 0, sy = 0;
        for (int a = 0; a < btf::btfRingSize(r); ++a) {
          const btf::Rgb& c = values[std::size_t(btf::btfRingStart(r) + a) * T + t];
          sr += c.r, sg += c.g, sb += c.b, sy += c.luminance();
        }
        for (int a = 0; a < btf::btfRingSize(r); ++a) {
          const btf::Rgb& c = values[std::size_t(btf::btfRingStart(r) + a) * T + t];
          const double y = c.luminance(), k = sy > 0 ? y / sy : 0.0;
          const double dr = k * sr - c.r, dg = k * sg - c.g, db = k * sb - c.b;
          err += dr * dr + dg * dg + db * db;
          ref += double(c.r) * c.r + double(c.g) * c.g + double(c.b) * c.b;
        }
      }
  }
  return std::sqrt(err / ref);
}

TEST(VqBtf, RgbErrorOfDirectionDependentColourFollowsBothTolerances) {
  // A white specular lobe on a coloured base: the chromaticity varies along the rings.
  const btf::BtfData& data = varyingChromaBtf();
  const double one_chroma_per_ring = ringMeanChromaRelRmse(data);
  std::printf("one chroma per ring with exact luminance: rgb rel_rmse %.4f\n", one_chroma_per_ring);
  struct Case {
    int levels;
    float epsilon, chroma_epsilon;
  };
  for (const Case& c : {Case{3, 0.0f, 0.01f}, Case{3, 0.02f, 0.01f}, Case{3, 0.02f, 0.05f}, Case{1, 0.02f, 0.01f}}) {
    btf::VqOptions options;
    options.epsilon = c.epsilon;
    options.chroma_epsilon = c.chroma_epsilon;
    options.levels = c.levels;
    const btf::VqBtf vq = btf::compressVq(data, options);
    const double lum = btf::test::luminanceRelRmse(data, vq);
    const double rgb = btf::compareBtf(data, vq).rel_rmse;
    const double bound = btf::test::vqRgbBound(vq, lum, c.chroma_epsilon, options.energy_floor, c.levels);
    std::printf("levels %d, epsilon %.2f, chroma_epsilon %.2f: rgb rel_rmse %.4f <= bound %.4f (luminance %.4f)\n",
                c.levels, double(c.epsilon), double(c.chroma_epsilon), rgb, bound, lum);
    EXPECT_LE(lum, vqLuminanceBound(c.epsilon, c.levels));
    EXPECT_LE(rgb, bound) << "levels " << c.levels << ", epsilon " << c.epsilon << ", chroma_epsilon " << c.chroma_epsilon;
    // One chromaticity per ring could not meet the bound even with exact luminance.
    if (c.chroma_epsilon == 0.01f) {
      EXPECT_GT(one_chroma_per_ring, bound);
    }
  }
}

TEST(VqBtf, OutputDoesNotDependOnTheThreadCount) {
  btf::VqOptions options;
  options.epsilon = 0.02f;
  std::optional<btf::VqBtf> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = btf::compressVq(varyingChromaBtf(), options);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = btf::compressVq(varyingChromaBtf(), options);
  }
  options.threads = 2;
  const btf::VqBtf arena = btf::compressVq(varyingChromaBtf(), options);
  EXPECT_EQ(one->stats().codebook_entries, two->stats().codebook_entries);
  EXPECT_EQ(one->stats().compressed_bytes, two->stats().compressed_bytes);
  expectSameDecode(*one, *two);
  expectSameDecode(*one, arena);
  btf::test::TempDir dir;
  one->write(dir / "one.btfz");
  two->write(dir / "two.btfz");
  std::ifstream a(dir / "one.btfz", std::ios::binary), b(dir / "two.btfz", std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(bytes_a == bytes_b, true);
}

TEST(VqBtf, OutputDoesNotDependOnTheThreadCountAcrossChunksAndSegments) {
  // 12 x 12 texels: two chunks per batch (the compressor's kChunk is 128), and codebooks of
  // thousands of entries, so that kd-tree segments are built and merged (codebook.h) while the
  // ring jobs, the chunk searches and the loading of the next view run in parallel.
  static const btf::BtfData data = btf::test::makeGgxBtf(12, 12, false);
  btf::VqOptions options;
  options.epsilon = 0.02f;
  options.threads = 1;
  const btf::VqBtf one = btf::compressVq(data, options);
  options.threads = 2;
  const btf::VqBtf two = btf::compressVq(data, options);
  ASSERT_EQ(one.stats().codebook_entries.size(), 3u);
  EXPECT_GT(one.stats().codebook_entries[0], 1000u);
  btf::test::TempDir dir;
  one.write(dir / "one.btfz");
  two.write(dir / "two.btfz");
  std::ifstream a(dir / "one.btfz", std::ios::binary), b(dir / "two.btfz", std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_FALSE(bytes_a.empty());
  EXPECT_EQ(bytes_a == bytes_b, true);
}

TEST(VqBtf, WriteReadRoundTripDecodesBitIdentically) {
  btf::test::TempDir dir;
  for (int levels = 1; levels <= 3; ++levels) {
    btf::VqOptions options;
    options.levels = levels;
    const btf::VqBtf vq = btf::compressVq(varyingChromaBtf(), options);
    const auto path = dir / (levels == 1 ? "l1.btfz" : levels == 2 ? "l2.btfz" : "l3.btfz");
    vq.write(path);
    EXPECT_EQ(vq.stats().compressed_bytes, std::filesystem::file_size(path));
    const btf::VqBtf back = btf::VqBtf::read(path);
    EXPECT_EQ(back.options().levels, levels);
    EXPECT_EQ(back.stats().codebook_entries, vq.stats().codebook_entries);
    expectSameDecode(vq, back);
  }
}

TEST(VqBtf, ReaderRejectsCorruptAndSemanticallyInvalidFiles) {
  btf::test::TempDir dir;
  const btf::VqBtf vq = btf::compressVq(varyingChromaBtf(), {});
  const auto good = dir / "good.btfz";
  vq.write(good);
  // A flipped byte in the payload: the container's checksum.
  {
    std::string bytes;
    {
      std::ifstream in(good, std::ios::binary);
      bytes.assign((std::istreambuf_iterator<char>(in)), {});
    }
    bytes[bytes.size() - 10] = char(bytes[bytes.size() - 10] ^ 0x40);
    std::ofstream(dir / "flipped.btfz", std::ios::binary) << bytes;
    EXPECT_THROW(btf::VqBtf::read(dir / "flipped.btfz"), btf::FileError);
    std::ofstream(dir / "truncated.btfz", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    EXPECT_THROW(btf::VqBtf::read(dir / "truncated.btfz"), btf::FileError);
  }
  // Valid containers with invalid VQ content: an empty codebook, an index beyond its codebook, a
  // partial chroma entry, a missing section.
  auto rewrite = [&](const std::string& name, const std::function<void(std::vector<btf::ContainerSection>&)>& change) {
    return btf::test::rewriteContainer(good, dir / (name + ".btfz"), change);
  };
  auto find = [](std::vector<btf::ContainerSection>& sections, const std::string& name) -> btf::ContainerSection& {
    for (auto& s : sections)
      if (s.name == name) return s;
    throw std::runtime_error("no section " + name);
  };
  const auto empty = rewrite("empty", [&](auto& sections) { find(sections, "level2/index").data = {std::byte(1)}; });
  try {
    btf::VqBtf::read(empty);
    ADD_FAILURE() << "empty codebook accepted";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  const auto beyond = rewrite("beyond", [&](auto& sections) {
    auto& top = find(sections, "top/index");
    const int width = int(top.data[0]);
    top.data[1 + std::size_t(width - 1) * ((top.data.size() - 1) / std::size_t(width))] = std::byte(0xff);
  });
  try {
    btf::VqBtf::read(beyond);
    ADD_FAILURE() << "index outside its codebook accepted";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("outside its codebook"), std::string::npos) << e.what();
  }
  const auto partial = rewrite("partial", [&](auto& sections) { find(sections, "chroma/ring2").data = {std::byte(1), std::byte(5)}; });
  try {
    btf::VqBtf::read(partial);
    ADD_FAILURE() << "partial chroma entry accepted";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("partial entry"), std::string::npos) << e.what();
  }
  // A chromaticity beyond the 16-bit grid the decoder keeps: the section's byte planes (vq_io.cpp:
  // a width byte, then plane b holds byte b of every value) widened to three, the first value + 2^16.
  const auto wide = rewrite("wide", [&](auto& sections) {
    auto& chroma = find(sections, "chroma/ring1");
    ASSERT_EQ(int(chroma.data[0]), 2);
    const std::size_t count = (chroma.data.size() - 1) / 2;
    chroma.data[0] = std::byte(3);
    chroma.data.resize(1 + 3 * count, std::byte(0));
    chroma.data[1 + 2 * count] = std::byte(1);
  });
  try {
    btf::VqBtf::read(wide);
    ADD_FAILURE() << "chromaticity beyond 16 bits accepted";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("16-bit grid"), std::string::npos) << e.what();
  }
  const auto missing = rewrite("missing", [&](auto& sections) {
    std::erase_if(sections, [](const btf::ContainerSection& s) { return s.name == "level3/scale"; });
  });
  EXPECT_THROW(btf::VqBtf::read(missing), btf::FileError);
}

TEST(VqBtf, RejectsInvalidOptionsAndData) {
  btf::VqOptions options;
  options.levels = 4;
  EXPECT_THROW(btf::compressVq(constantChromaBtf(), options), btf::Error);
  options = {};
  options.epsilon = -0.1f;
  EXPECT_THROW(btf::compressVq(constantChromaBtf(), options), btf::Error);
  options = {};
  options.chroma_epsilon = 0.5f * btf::kVqMinChromaEpsilon;  // its grid would not fit 16 bits
  EXPECT_THROW(btf::compressVq(constantChromaBtf(), options), btf::Error);
  btf::BtfData bad(2, 2, "bad");
  bad.at(1, 0, 3, 7) = btf::Rgb(-1.0f);
  try {
    btf::compressVq(bad, {});
    ADD_FAILURE() << "negative value accepted";
  } catch (const btf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("view 3, light 7"), std::string::npos) << e.what();
  }
}

TEST(VqBtf, ReaderRejectsNonsenseInTheHeader) {
  // A mutation probe: header JSON with correct CRCs but values of the wrong type or range
  // loaded with exit 0 (nlohmann converts booleans and floats without a word). Each is an error
  // naming the key now.
  btf::test::TempDir dir;
  const btf::VqBtf vq = btf::compressVq(varyingChromaBtf(), {});
  const auto good = dir / "good.btfz";
  vq.write(good);
  auto withHeader = [&](const std::string& name, const std::string& key, const std::string& value) {
    return btf::test::rewriteContainer(good, dir / (name + ".btfz"), [&](std::vector<btf::ContainerSection>& sections) {
      for (auto& s : sections) {
        if (s.name != "header") continue;
        auto header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(s.data.data()), s.data.size()));
        header[key] = nlohmann::json::parse(value);
        const std::string text = header.dump();
        s.data.assign(reinterpret_cast<const std::byte*>(text.data()), reinterpret_cast<const std::byte*>(text.data()) + text.size());
      }
    });
  };
  const struct {
    std::string key, value, words;
  } cases[] = {
      {"codebook_entries", "[-1, 1274, 17]", "codebook_entries"},
      {"chroma_entries", "null", "chroma_entries"},
      {"chroma_entries", "[\"x\", 1, 1, 1, 1, 1]", "chroma_entries"},
      {"chroma_entries", "[1, 1, 1, 1, 1, 1]", "chroma_entries disagree"},
      {"epsilon", "-1", "epsilon"},
      {"epsilon", "\"0.02\"", "epsilon"},
      {"energy_floor", "true", "energy_floor"},
      {"energy_floor", "-2", "energy_floor"},
      {"width", "8.5", "width"},
      {"levels", "\"3\"", "levels"},
  };
  int i = 0;
  for (const auto& c : cases) {
    const auto path = withHeader("case" + std::to_string(i++), c.key, c.value);
    try {
      btf::VqBtf::read(path);
      ADD_FAILURE() << c.key << " = " << c.value << " accepted";
    } catch (const btf::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos) << c.key << " = " << c.value << ": " << e.what();
    }
  }
  // The unedited header still reads.
  EXPECT_NO_THROW(btf::VqBtf::read(withHeader("same", "epsilon", std::to_string(vq.options().epsilon))));
}
