#include "btf/io/merl.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <system_error>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"

namespace btf {
namespace fs = std::filesystem;

// The format is little-endian and we copy it to and from memory in bulk (one read of 35 MB rather
// than 4.4 million conversions). Byte swapping would be an untested code path on every machine we
// build on, so a big-endian host is refused at compile time instead.
static_assert(std::endian::native == std::endian::little, "MERL I/O assumes a little-endian host");
static_assert(sizeof(double) == 8 && std::numeric_limits<double>::is_iec559, "MERL stores IEEE doubles");

namespace {

constexpr double kHalfPi = std::numbers::pi / 2.0;
constexpr double kPiDouble = std::numbers::pi;
constexpr std::array<std::int32_t, 3> kDims = {MerlTable::kThetaHalfRes, MerlTable::kThetaDiffRes,
                                               MerlTable::kPhiDiffRes};
constexpr std::array<const char*, 3> kDimNames = {"theta_h", "theta_d", "phi_d"};
constexpr std::array<const char*, 3> kChannelNames = {"R", "G", "B"};
constexpr std::uintmax_t kHeaderBytes = 3 * sizeof(std::int32_t);
constexpr std::uintmax_t kValueBytes = 3 * MerlTable::kEntriesPerChannel * sizeof(double);
constexpr std::uintmax_t kFileBytes = kHeaderBytes + kValueBytes;

// "entry 1234 (channel G, theta_h 0, theta_d 6, phi_d 154)": where a bad value sits, for the user.
std::string describeEntry(std::size_t flat) {
  const std::size_t channel = flat / MerlTable::kEntriesPerChannel;
  const std::size_t i = flat % MerlTable::kEntriesPerChannel;
  const std::size_t phi_d = i % MerlTable::kPhiDiffRes;
  const std::size_t theta_d = (i / MerlTable::kPhiDiffRes) % MerlTable::kThetaDiffRes;
  const std::size_t theta_h = i / (std::size_t(MerlTable::kPhiDiffRes) * MerlTable::kThetaDiffRes);
  return "entry " + std::to_string(i) + " (channel " + kChannelNames[channel] + ", theta_h index " +
         std::to_string(theta_h) + ", theta_d index " + std::to_string(theta_d) + ", phi_d index " +
         std::to_string(phi_d) + ")";
}

// The largest magnitude a stored value may have. The tables are evaluated in float, and sums of
// values (albedo, statistics) must stay finite: a double like 1e308 passes the finite check yet
// becomes inf as a float. Measured MERL values (BRDF times the channel's scale inverse, about 1500)
// stay many orders of magnitude below this.
constexpr double kMerlMaxMagnitude = 1e20;

// Index of the first NaN, infinite or out-of-range value, or values.size() if there is none.
std::size_t firstNonFinite(const std::vector<double>& values) {
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]) || std::abs(values[k]) > kMerlMaxMagnitude) return k;
  return values.size();
}

std::string nonFiniteProblem(const std::vector<double>& values, std::size_t k) {
  if (std::isfinite(values[k])) {
    // The shortest text that reads back as the value: %g would print 1.0000001e20 as the limit.
    char value[40];
    const auto end = std::to_chars(value, value + sizeof value, values[k]).ptr;
    char text[120];
    std::snprintf(text, sizeof text, "value %.*s beyond the range a measured table can hold (|value| <= %g)",
                  int(end - value), value, kMerlMaxMagnitude);
    return std::string(text) + " at " + describeEntry(k);
  }
  return std::string(std::isnan(values[k]) ? "NaN" : "infinite value") + " at " + describeEntry(k);
}

void checkHeader(const fs::path& path, const std::array<std::int32_t, 3>& dims) {
  for (int a = 0; a < 3; ++a) {
    if (dims[a] != kDims[a])
      throw FileError(path, std::string("wrong header dims: ") + kDimNames[a] + " count is " +
                                std::to_string(dims[a]) + ", expected " + std::to_string(kDims[a]) +
                                " (dims " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
                                " x " + std::to_string(dims[2]) + ", expected 90 x 90 x 180)");
  }
}

}  // namespace

DirectionPair MerlTable::directionsOf(int theta_h, int theta_d, int phi_d) {
  HalfDiff hd;
  hd.theta_h = float(thetaHalfOf(theta_h));
  hd.theta_d = float(thetaDiffOf(theta_d));
  hd.phi_d = float(phiDiffOf(phi_d));
  return fromHalfDiff(hd);
}

double MerlTable::thetaHalfOf(int i) {
  const double t = double(i) / kThetaHalfRes;
  return t * t * kHalfPi;
}
double MerlTable::thetaDiffOf(int j) { return double(j) * kHalfPi / kThetaDiffRes; }
double MerlTable::phiDiffOf(int k) { return double(k) * kPiDouble / kPhiDiffRes; }

double MerlTable::thetaHalfCoordinate(double theta_h) {
  // Negative angles only arise from rounding; treat them as the pole rather than returning NaN.
  return std::sqrt(std::max(theta_h, 0.0) / kHalfPi) * kThetaHalfRes;
}
double MerlTable::thetaDiffCoordinate(double theta_d) { return theta_d / kHalfPi * kThetaDiffRes; }
double MerlTable::phiDiffCoordinate(double phi_d) {
  // Reciprocity: f is unchanged under phi_d -> phi_d + pi, so only [0, pi) is stored.
  double folded = std::fmod(phi_d, kPiDouble);
  if (folded < 0) folded += kPiDouble;
  return folded / kPiDouble * kPhiDiffRes;
}

MerlTable readMerl(const fs::path& path) {
  requireReadableFile(path);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw FileError(path, "cannot determine the file size: " + ec.message());
  if (size == 0) throw FileError(path, "empty file, expected a MERL .binary table of " + std::to_string(kFileBytes) + " bytes");
  if (size < kHeaderBytes)
    throw FileError(path, "truncated header: expected " + std::to_string(kHeaderBytes) + " bytes, found " +
                              std::to_string(size));

  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot be opened for reading");
  std::array<std::int32_t, 3> dims{};
  in.read(reinterpret_cast<char*>(dims.data()), kHeaderBytes);
  if (in.gcount() != std::streamsize(kHeaderBytes)) throw FileError(path, "read failed in the header");
  checkHeader(path, dims);

  if (size < kFileBytes)
    throw FileError(path, "truncated file: expected " + std::to_string(kFileBytes) + " bytes, found " +
                              std::to_string(size) + " (" + std::to_string(kFileBytes - size) + " missing)");
  if (size > kFileBytes)
    throw FileError(path, "trailing bytes: expected " + std::to_string(kFileBytes) + " bytes, found " +
                              std::to_string(size) + " (" + std::to_string(size - kFileBytes) + " extra)");

  MerlTable table;
  in.read(reinterpret_cast<char*>(table.values.data()), std::streamsize(kValueBytes));
  // The size was checked above, but the file may change underneath us; trust only what was read.
  if (in.gcount() != std::streamsize(kValueBytes))
    throw FileError(path, "truncated file: expected " + std::to_string(kFileBytes) + " bytes, read only " +
                              std::to_string(kHeaderBytes + std::uintmax_t(in.gcount())));
  if (const std::size_t bad = firstNonFinite(table.values); bad != table.values.size())
    throw FileError(path, nonFiniteProblem(table.values, bad));
  return table;
}

void writeMerl(const fs::path& path, const MerlTable& table) {
  if (table.values.size() != 3 * MerlTable::kEntriesPerChannel)
    throw Error("cannot write " + path.string() + ": the table holds " + std::to_string(table.values.size()) +
                " values, expected " + std::to_string(3 * MerlTable::kEntriesPerChannel));
  if (const std::size_t bad = firstNonFinite(table.values); bad != table.values.size())
    throw Error("cannot write " + path.string() + ": " + nonFiniteProblem(table.values, bad));
  writeFileAtomically(path, [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(kDims.data()), kHeaderBytes);
    out.write(reinterpret_cast<const char*>(table.values.data()), std::streamsize(kValueBytes));
  });
}

}  // namespace btf
