// MERL measured isotropic BRDF tables (Matusik et al. 2003), `*.binary`.
//
// File layout: three int32 dims (90, 90, 180) = (theta_h, theta_d, phi_d) counts, then
// 3 x 1,458,000 float64 values, channel-major (all R, then G, then B), little-endian.
// Index = phi_d + 180 * theta_d + 180 * 90 * theta_h. theta_h is indexed non-linearly,
// i = sqrt(theta_h / (pi/2)) * 90; theta_d linearly over [0, pi/2); phi_d linearly over [0, pi)
// (reciprocity folds [pi, 2 pi) onto it). Stored values times the channel scale
// (R 1/1500, G 1.15/1500, B 1.66/1500) give f in 1/sr. Negative values mark unmeasured samples.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <vector>

#include "btf/core/half_diff.h"
#include "btf/core/rgb.h"

namespace btf {

struct MerlTable {
  static constexpr int kThetaHalfRes = 90;
  static constexpr int kThetaDiffRes = 90;
  static constexpr int kPhiDiffRes = 180;
  static constexpr std::size_t kEntriesPerChannel =
      std::size_t(kThetaHalfRes) * kThetaDiffRes * kPhiDiffRes;  // 1,458,000
  static constexpr std::array<double, 3> kChannelScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

  // Raw stored values (not yet multiplied by kChannelScale), channel-major, exactly as on disk.
  std::vector<double> values = std::vector<double>(3 * kEntriesPerChannel, 0.0);

  static constexpr std::size_t index(int theta_h, int theta_d, int phi_d) {
    return std::size_t(phi_d) + std::size_t(kPhiDiffRes) * (std::size_t(theta_d) + std::size_t(kThetaDiffRes) * theta_h);
  }
  // Raw value of one channel at one table cell.
  double raw(int channel, std::size_t i) const { return values[channel * kEntriesPerChannel + i]; }
  double& raw(int channel, std::size_t i) { return values[channel * kEntriesPerChannel + i]; }
  // True when every channel of the cell is measured (non-negative).
  bool isMeasured(std::size_t i) const {
    return raw(0, i) >= 0 && raw(1, i) >= 0 && raw(2, i) >= 0;
  }
  // f in 1/sr at one table cell (scales applied); meaningful only where isMeasured(i).
  Rgb reflectance(std::size_t i) const {
    return {float(raw(0, i) * kChannelScale[0]), float(raw(1, i) * kChannelScale[1]),
            float(raw(2, i) * kChannelScale[2])};
  }
  // Stores f (1/sr) at one table cell, dividing by the channel scales.
  void setReflectance(std::size_t i, const Rgb& f) {
    for (int c = 0; c < 3; ++c) raw(c, i) = double(f[c]) / kChannelScale[c];
  }
  // Marks one table cell unmeasured (-1 in every channel, as the MERL files do).
  void setUnmeasured(std::size_t i) {
    for (int c = 0; c < 3; ++c) raw(c, i) = -1.0;
  }

  // Angles of a table sample: the cell's lower edge in each coordinate, as MERL's own lookup
  // (which truncates) assumes. theta_h(i) = (i / 90)^2 * pi/2, theta_d(j) = j * pi/180,
  // phi_d(k) = k * pi/180.
  static double thetaHalfOf(int i);
  static double thetaDiffOf(int j);
  static double phiDiffOf(int k);
  // The light and view directions a cell stands for (its angles above, phi_h = 0): what
  // tabulation evaluates and fitting compares against. May lie below the horizon at grazing cells.
  static DirectionPair directionsOf(int theta_h, int theta_d, int phi_d);
  // Continuous table coordinates of angles (inverse of the above), unclamped.
  static double thetaHalfCoordinate(double theta_h);
  static double thetaDiffCoordinate(double theta_d);
  static double phiDiffCoordinate(double phi_d);  // phi_d folded into [0, pi) first
};

// Reads a MERL `.binary` file. Throws FileError naming the file and the problem for: missing file,
// directory, empty or truncated file, dims other than (90, 90, 180), trailing bytes, NaN or
// infinite values. Negative values are kept (they mark unmeasured samples).
MerlTable readMerl(const std::filesystem::path& path);

// Writes a MERL `.binary` file bit-exactly (atomically: temporary file, then rename).
// Throws Error if the table holds NaN or infinite values.
void writeMerl(const std::filesystem::path& path, const MerlTable& table);

}  // namespace btf
