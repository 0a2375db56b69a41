// MERL .binary reading and writing: bit-exact round trips, the on-disk layout, the index and angle
// helpers, and one clear message per kind of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/io/merl.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kN = MerlTable::kEntriesPerChannel;
constexpr std::uintmax_t kFileBytes = 12 + 3 * kN * 8;

std::vector<char> fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Writes a MERL-like file byte by byte, so tests can produce what writeMerl refuses to.
void writeRaw(const fs::path& path, const std::vector<std::int32_t>& dims, const std::vector<double>& values) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(dims.data()), std::streamsize(dims.size() * 4));
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * 8));
}

// Random stored values spanning many magnitudes, about 5% negative (unmeasured) of varied sign
// patterns, plus values whose bits a text or float round trip would change.
MerlTable randomTable() {
  MerlTable table;
  Rng rng(2003);
  for (double& v : table.values) {
    const double u = rng.uniformDouble();
    v = u < 0.05 ? -1.0 - u : std::ldexp(rng.uniformDouble(), int(rng.uniformInt(40)) - 20);
  }
  table.values[17] = -0.0;
  table.values[18] = std::numeric_limits<double>::denorm_min();
  table.values[19] = 1e20;  // the largest magnitude a table may hold (merl.cpp)
  table.values[20] = 0.1;  // not representable as float
  return table;
}

// Expects readMerl(path) to throw FileError naming the file and containing every one of `parts`.
void expectReadError(const fs::path& path, const std::vector<std::string>& parts) {
  try {
    readMerl(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const FileError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

class MerlIo : public ::testing::Test {
 protected:
  test::TempDir dir;
  // A valid file, for tests that damage one.
  fs::path validFile() {
    const fs::path path = dir / "valid.binary";
    MerlTable table;
    for (std::size_t i = 0; i < table.values.size(); ++i) table.values[i] = double(i % 1000) / 7.0;
    writeMerl(path, table);
    return path;
  }
};

TEST_F(MerlIo, WriteThenReadIsBitExact) {
  const MerlTable table = randomTable();
  writeMerl(dir / "a.binary", table);
  const MerlTable back = readMerl(dir / "a.binary");
  ASSERT_EQ(back.values.size(), table.values.size());
  EXPECT_EQ(std::memcmp(back.values.data(), table.values.data(), table.values.size() * sizeof(double)), 0);
  EXPECT_TRUE(std::signbit(back.values[17]));
  // Rewriting what was read gives the same bytes: nothing is normalized on the way.
  writeMerl(dir / "b.binary", back);
  EXPECT_EQ(fileBytes(dir / "a.binary"), fileBytes(dir / "b.binary"));
  // The negative (unmeasured) markers survive as they are.
  std::size_t negative = 0;
  for (std::size_t i = 0; i < back.values.size(); ++i) negative += back.values[i] < 0 && back.values[i] == table.values[i];
  EXPECT_GT(negative, table.values.size() / 25);
}

TEST_F(MerlIo, FileLayoutIsHeaderThenChannelMajorLittleEndianDoubles) {
  MerlTable table;
  const std::size_t cell = MerlTable::index(2, 3, 4);
  ASSERT_EQ(cell, 4u + 180u * 3u + 180u * 90u * 2u);
  table.raw(1, cell) = 7.5;  // G channel
  table.setUnmeasured(MerlTable::index(89, 89, 179));
  writeMerl(dir / "t.binary", table);
  const std::vector<char> bytes = fileBytes(dir / "t.binary");
  ASSERT_EQ(bytes.size(), kFileBytes);
  const unsigned char header[12] = {90, 0, 0, 0, 90, 0, 0, 0, 180, 0, 0, 0};
  EXPECT_EQ(std::memcmp(bytes.data(), header, 12), 0);
  double g;
  std::memcpy(&g, bytes.data() + 12 + 8 * (kN + cell), 8);
  EXPECT_EQ(g, 7.5);
  double last;
  std::memcpy(&last, bytes.data() + bytes.size() - 8, 8);  // B of the last cell
  EXPECT_EQ(last, -1.0);
}

TEST_F(MerlIo, ReflectanceAppliesTheChannelScales) {
  MerlTable table;
  table.setReflectance(5, Rgb(0.25f, 0.5f, 1.0f));
  EXPECT_DOUBLE_EQ(table.raw(0, 5), 0.25 * 1500.0);
  EXPECT_DOUBLE_EQ(table.raw(1, 5), 0.5 * 1500.0 / 1.15);
  EXPECT_DOUBLE_EQ(table.raw(2, 5), 1.0 * 1500.0 / 1.66);
  EXPECT_FLOAT_EQ(table.reflectance(5).g, 0.5f);
  EXPECT_TRUE(table.isMeasured(5));
  table.raw(2, 5) = -0.5;  // one negative channel makes the whole cell unmeasured
  EXPECT_FALSE(table.isMeasured(5));
}

TEST_F(MerlIo, MissingFile) { expectReadError(dir / "nothing-here.binary", {"no such file"}); }

TEST_F(MerlIo, DirectoryInsteadOfFile) {
  fs::create_directory(dir / "folder.binary");
  expectReadError(dir / "folder.binary", {"directory"});
}

TEST_F(MerlIo, EmptyFile) {
  std::ofstream(dir / "empty.binary").close();
  expectReadError(dir / "empty.binary", {"empty"});
}

TEST_F(MerlIo, TruncatedHeader) {
  writeRaw(dir / "short.binary", {90}, {});
  expectReadError(dir / "short.binary", {"truncated", "expected 12 bytes", "found 4"});
}

TEST_F(MerlIo, TruncatedData) {
  const fs::path path = validFile();
  fs::resize_file(path, kFileBytes - 1000);
  expectReadError(path, {"truncated", std::to_string(kFileBytes), std::to_string(kFileBytes - 1000)});
}

TEST_F(MerlIo, TrailingBytes) {
  const fs::path path = validFile();
  std::ofstream(path, std::ios::binary | std::ios::app) << "extra";
  expectReadError(path, {"trailing", "5 extra"});
}

TEST_F(MerlIo, WrongHeaderDimsNameTheDimension) {
  writeRaw(dir / "dims.binary", {90, 91, 180}, std::vector<double>(3 * kN));
  expectReadError(dir / "dims.binary", {"wrong header dims", "theta_d", "91", "expected 90"});
  writeRaw(dir / "dims2.binary", {90, 90, 360}, std::vector<double>(3 * kN));
  expectReadError(dir / "dims2.binary", {"wrong header dims", "phi_d", "360"});
}

TEST_F(MerlIo, NaNEntryNamesIndexAndChannel) {
  std::vector<double> values(3 * kN, 1.0);
  const std::size_t cell = MerlTable::index(0, 6, 154);
  values[kN + cell] = std::numeric_limits<double>::quiet_NaN();
  writeRaw(dir / "nan.binary", {90, 90, 180}, values);
  expectReadError(dir / "nan.binary", {"NaN", "entry " + std::to_string(cell), "channel G", "theta_d index 6"});
}

TEST_F(MerlIo, InfiniteEntryNamesIndexAndChannel) {
  std::vector<double> values(3 * kN, 1.0);
  values[2 * kN + 77] = -std::numeric_limits<double>::infinity();
  writeRaw(dir / "inf.binary", {90, 90, 180}, values);
  expectReadError(dir / "inf.binary", {"infinite", "entry 77", "channel B"});
}

TEST_F(MerlIo, HugeFiniteEntryIsRefusedBeforeItOverflowsAFloat) {
  // A mutation probe's case: 1e308 passed the finite check and printed max inf, mean inf.
  std::vector<double> values(3 * kN, 1.0);
  values[123] = 1e308;
  writeRaw(dir / "huge.binary", {90, 90, 180}, values);
  expectReadError(dir / "huge.binary", {"1e+308", "beyond the range", "entry 123", "channel R"});
  values[123] = -1e25;
  writeRaw(dir / "huge2.binary", {90, 90, 180}, values);
  expectReadError(dir / "huge2.binary", {"beyond the range", "entry 123"});
}

TEST_F(MerlIo, WriterRefusesNonFiniteValuesAndLeavesNoFile) {
  MerlTable table;
  table.raw(0, 3) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(writeMerl(dir / "bad.binary", table), Error);
  EXPECT_FALSE(fs::exists(dir / "bad.binary"));
}

TEST(MerlAngles, IndexAndAngleHelpersAreInverseAtCellEdges) {
  for (int i = 0; i < MerlTable::kThetaHalfRes; ++i)
    EXPECT_NEAR(MerlTable::thetaHalfCoordinate(MerlTable::thetaHalfOf(i)), i, 1e-9) << i;
  for (int j = 0; j < MerlTable::kThetaDiffRes; ++j)
    EXPECT_NEAR(MerlTable::thetaDiffCoordinate(MerlTable::thetaDiffOf(j)), j, 1e-9) << j;
  for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) {
    EXPECT_NEAR(MerlTable::phiDiffCoordinate(MerlTable::phiDiffOf(k)), k, 1e-9) << k;
    // Reciprocity folds phi_d + pi and phi_d - pi onto the same coordinate.
    EXPECT_NEAR(MerlTable::phiDiffCoordinate(MerlTable::phiDiffOf(k) + std::numbers::pi), k, 1e-9) << k;
    EXPECT_NEAR(MerlTable::phiDiffCoordinate(MerlTable::phiDiffOf(k) - std::numbers::pi), k, 1e-9) << k;
  }
}

TEST(MerlAngles, DocumentedAnglesOfSamples) {
  EXPECT_DOUBLE_EQ(MerlTable::thetaHalfOf(0), 0.0);
  EXPECT_DOUBLE_EQ(MerlTable::thetaHalfOf(45), 0.25 * std::numbers::pi / 2);  // (45/90)^2 * pi/2
  EXPECT_DOUBLE_EQ(MerlTable::thetaDiffOf(45), std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(MerlTable::phiDiffOf(90), std::numbers::pi / 2);
  // The upper ends of the ranges map to the end of the last cell: 90 cells cover [0, pi/2].
  EXPECT_NEAR(MerlTable::thetaHalfCoordinate(std::numbers::pi / 2), 90, 1e-9);
  EXPECT_NEAR(MerlTable::thetaDiffCoordinate(std::numbers::pi / 2), 90, 1e-9);
  // Midway between two sample angles lies in the lower cell: truncation finds the cell.
  for (int i = 0; i + 1 < MerlTable::kThetaHalfRes; ++i) {
    const double mid = 0.5 * (MerlTable::thetaHalfOf(i) + MerlTable::thetaHalfOf(i + 1));
    EXPECT_EQ(int(MerlTable::thetaHalfCoordinate(mid)), i);
  }
}

}  // namespace
}  // namespace btf
