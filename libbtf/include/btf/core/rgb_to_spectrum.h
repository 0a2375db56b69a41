// Spectral upsampling of linear sRGB values: the sigmoid-polynomial spectra of Jakob & Hanika 2019
// ("A Low-Dimensional Function Space for Efficient Spectral Upsampling", Computer Graphics Forum
// 38(2)), the scheme pbrt-v4 and Mitsuba 3 use for their own RGB inputs:
//   s(lambda) = scale * S(c0 x^2 + c1 x + c2),  S(z) = 1/2 + z / (2 sqrt(1 + z^2)),
// smooth, non-negative and bounded by `scale`; x is the wavelength mapped linearly from
// [360, 830] nm onto [-1, 1] (a change of variable that leaves the function space as it is and
// keeps the fit well conditioned). Reflectance of a BRDF table (f cos over the VNDF density) is not
// bounded by 1, so, as pbrt-v4's RGBUnboundedSpectrum does, each value gets its own scale
// 2 max(r, g, b) and the polynomial is fitted to rgb / scale (largest component 1/2, well inside
// what S reaches). The fit differs from the paper's in two ways: the coefficients are solved per
// value by Levenberg-Marquardt (no precomputed 64^3 table), and the residual is the linear sRGB
// error under D65 (SpectrumToRgb) instead of CIELAB: the files' consumers integrate it linearly,
// so that is the error a round trip shows.
#pragma once

#include <span>

#include "btf/core/cie.h"
#include "btf/core/rgb.h"

namespace btf {

struct SigmoidSpectrum {
  double c0 = 0, c1 = 0, c2 = 0;  // over x in [-1, 1] (see above)
  double scale = 0;               // 0: black
  double operator()(double lambda_nm) const;
};

// The spectrum whose colour under `projection` is `rgb` (negative components are taken as 0: the
// colour a reader clips to). Deterministic. Over an 11^3 grid of the sRGB cube, primaries and
// greys included, at scales 0.01 to 40, the residual |projection(s) - rgb| stays below 1e-5 of
// max(r, g, b) (tests/unit/test_cie.cpp prints the largest).
SigmoidSpectrum fitSigmoidSpectrum(const Rgb& rgb, const SpectrumToRgb& projection, std::span<const float> wavelengths);

}  // namespace btf
