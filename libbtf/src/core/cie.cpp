#include "btf/core/cie.h"

#include <cmath>
#include <string>

#include "btf/core/error.h"

namespace btf {

SpectrumToRgb::SpectrumToRgb(std::span<const float> wl) {
  const std::size_t n = wl.size();
  if (n < 2) throw Error("a sampled spectrum needs at least 2 wavelengths, not " + std::to_string(n));
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(wl[k]) || (k > 0 && !(wl[k] > wl[k - 1])))
      throw Error("the wavelengths of a spectrum must be finite and increase strictly (element " + std::to_string(k) + ")");
  if (wl.front() > 380.0f || wl.back() < 780.0f)
    throw Error("the wavelengths of a spectrum must cover 380 to 780 nm, not " + std::to_string(wl.front()) + " to " +
                std::to_string(wl.back()) + " nm");
  // XYZ weights of each sample: the CIE node's weight shared between the two samples around it
  // by linear interpolation.
  std::vector<double> xyz(n * 3, 0.0);
  double y_white = 0;
  for (int j = 0; j < kCieCount; ++j) {
    const double lambda = kCieFirstNm + kCieStepNm * j, d65 = kCieD65[std::size_t(j)];
    const CieSample& c = kCie1931[std::size_t(j)];
    y_white += d65 * c.y;
    std::size_t k = 0;
    while (k + 2 < n && wl[k + 1] <= lambda) ++k;
    const double t = std::clamp((lambda - wl[k]) / (double(wl[k + 1]) - wl[k]), 0.0, 1.0);
    const double cmf[3] = {c.x, c.y, c.z};
    for (int a = 0; a < 3; ++a) {
      xyz[k * 3 + a] += (1 - t) * d65 * cmf[a];
      xyz[(k + 1) * 3 + a] += t * d65 * cmf[a];
    }
  }
  weights_.assign(n * 3, 0.0);
  double white[3] = {0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    const Rgb rgb = xyzToLinearRec709(Rgb(float(xyz[k * 3] / y_white), float(xyz[k * 3 + 1] / y_white),
                                          float(xyz[k * 3 + 2] / y_white)));
    for (int c = 0; c < 3; ++c) {
      weights_[k * 3 + std::size_t(c)] = rgb[c];
      white[c] += rgb[c];
    }
  }
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) weights_[k * 3 + std::size_t(c)] /= white[c];
}

Rgb SpectrumToRgb::strided(const float* first, std::size_t stride) const {
  double rgb[3] = {0, 0, 0};
  const std::size_t n = size();
  for (std::size_t k = 0; k < n; ++k) {
    const double v = first[k * stride];
    for (int c = 0; c < 3; ++c) rgb[c] += weights_[k * 3 + std::size_t(c)] * v;
  }
  return Rgb(float(rgb[0]), float(rgb[1]), float(rgb[2]));
}

Rgb SpectrumToRgb::operator()(std::span<const float> values) const {
  if (values.size() != size())
    throw Error("a spectrum of " + std::to_string(values.size()) + " values for " + std::to_string(size()) + " wavelengths");
  return strided(values.data(), 1);
}

std::vector<float> bsdfWavelengths() {
  std::vector<float> wl;
  for (int nm = kCieFirstNm; nm <= int(kCieLastNm); nm += 10) wl.push_back(float(nm));
  return wl;
}

}  // namespace btf
