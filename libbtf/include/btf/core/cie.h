// Colorimetry of reflectance spectra: the CIE 1931 2-degree standard observer and CIE standard
// illuminant D65, and the projection of a sampled reflectance spectrum to linear sRGB.
//
// The tables (cie_tables.cpp) are the CIE's published values at 5 nm from 360 to 830 nm:
// - x_bar, y_bar, z_bar: CIE 1931 standard colorimetric observer, CIE 015:2018 "Colorimetry"
//   (4th ed.), Table 1 sampled at 5 nm; the same values as the Colour & Vision Research
//   Laboratory's file ciexyz31.csv. Their y_bar sums to 21.37314 (times 5 nm: 106.857).
// - D65: CIE standard illuminant D65, ISO 11664-2:2007 / CIE S 014-2/E:2006, Table 1 (relative
//   spectral power, 100 at 560 nm), 5 nm.
// Both are public standard data; tests/unit/test_cie.cpp checks their sums and the white point.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "btf/core/rgb.h"

namespace btf {

inline constexpr int kCieFirstNm = 360, kCieStepNm = 5, kCieCount = 95;  // 360, 365, ..., 830 nm
inline constexpr float kCieLastNm = float(kCieFirstNm + kCieStepNm * (kCieCount - 1));

struct CieSample {
  float x, y, z;
};
extern const std::array<CieSample, kCieCount> kCie1931;  // colour-matching functions at 360 + 5 k nm
extern const std::array<float, kCieCount> kCieD65;       // D65 relative power at 360 + 5 k nm

// The linear sRGB colour of reflectance spectra sampled at `wavelengths` (nm, strictly
// increasing), seen under D65 by the CIE 1931 observer: the spectrum is taken piecewise linear
// between its samples (constant beyond the first and last, as a renderer interpolating a
// wavelength parameter clamps it), XYZ = sum over the 5 nm table of s D65 cmf / sum D65 y_bar,
// then IEC 61966-2-1's XYZ -> linear sRGB matrix. The matrix's rows are then scaled so that a
// constant reflectance of 1 gives RGB (1, 1, 1) exactly (the table's D65 white and the matrix's
// rounded one differ by ~1e-3). Linear in the spectrum: a 3 x n matrix, built once.
class SpectrumToRgb {
 public:
  // Throws btf::Error for fewer than 2 wavelengths, non-increasing or non-finite ones, or a grid
  // that does not cover [380, 780] nm (a spectrum must be known where the observer sees: the
  // colour-matching functions hold less than 1e-4 of their weight outside it).
  explicit SpectrumToRgb(std::span<const float> wavelengths);
  // values[k] is the reflectance at wavelengths[k]; values.size() must equal the wavelength count.
  Rgb operator()(std::span<const float> values) const;
  // The same with a stride between the values (a spectra tensor holds one wavelength per slice).
  Rgb strided(const float* first, std::size_t stride) const;
  std::size_t size() const { return weights_.size() / 3; }
  // The weight of sample k in channel c: rgb[c] = sum_k weight(c, k) values[k].
  double weight(int c, std::size_t k) const { return weights_[k * 3 + std::size_t(c)]; }

 private:
  std::vector<double> weights_;  // per wavelength: r, g, b
};

// The wavelengths spectral .bsdf files are written at: 360 to 830 nm in 10 nm steps (every other
// node of the CIE table; the range pbrt-v4 samples wavelengths from). The sigmoid spectra are
// smooth, so 5 nm would double the file for no visible change (the colour round trip is exact
// either way: SpectrumToRgb interpolates the samples as a renderer does).
std::vector<float> bsdfWavelengths();

}  // namespace btf
