#include "btf/core/rgb_to_spectrum.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace btf {
namespace {

constexpr double kMidNm = 0.5 * (kCieFirstNm + kCieLastNm), kHalfRangeNm = 0.5 * (kCieLastNm - kCieFirstNm);
constexpr int kMaxIterations = 100;

double sigmoid(double z) { return 0.5 + z / (2.0 * std::sqrt(1.0 + z * z)); }
double sigmoidSlope(double z) { return 0.5 / std::pow(1.0 + z * z, 1.5); }

// Solves the 3 x 3 system a x = b by Gaussian elimination with partial pivoting; false if singular.
bool solve3(double a[3][3], double b[3], double x[3]) {
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 3; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    if (!(std::abs(a[pivot][col]) > 1e-300)) return false;
    std::swap(a[col], a[pivot]);
    std::swap(b[col], b[pivot]);
    for (int r = col + 1; r < 3; ++r) {
      const double f = a[r][col] / a[col][col];
      for (int k = col; k < 3; ++k) a[r][k] -= f * a[col][k];
      b[r] -= f * b[col];
    }
  }
  for (int r = 2; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < 3; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return true;
}

}  // namespace

double SigmoidSpectrum::operator()(double lambda_nm) const {
  if (scale == 0) return 0.0;
  const double x = (lambda_nm - kMidNm) / kHalfRangeNm;
  return scale * sigmoid((c0 * x + c1) * x + c2);
}

SigmoidSpectrum fitSigmoidSpectrum(const Rgb& rgb_in, const SpectrumToRgb& projection, std::span<const float> wl) {
  const Rgb rgb(std::max(rgb_in.r, 0.0f), std::max(rgb_in.g, 0.0f), std::max(rgb_in.b, 0.0f));
  SigmoidSpectrum s;
  const double peak = rgb.maxComponent();
  if (!(peak > 0)) return s;
  s.scale = 2.0 * peak;
  const double target[3] = {rgb.r / s.scale, rgb.g / s.scale, rgb.b / s.scale};
  const std::size_t n = wl.size();
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = (wl[k] - kMidNm) / kHalfRangeNm;

  // Residual and Jacobian of the colour of S(poly(x)) against the target.
  auto evaluate = [&](const double c[3], double residual[3], double jac[3][3]) {
    for (int a = 0; a < 3; ++a) {
      residual[a] = -target[a];
      if (jac) jac[a][0] = jac[a][1] = jac[a][2] = 0;
    }
    for (std::size_t k = 0; k < n; ++k) {
      const double z = (c[0] * x[k] + c[1]) * x[k] + c[2];
      const double v = sigmoid(z), dv = jac ? sigmoidSlope(z) : 0.0;
      const double basis[3] = {x[k] * x[k], x[k], 1.0};
      for (int a = 0; a < 3; ++a) {
        const double w = projection.weight(a, k);
        residual[a] += w * v;
        if (jac)
          for (int b = 0; b < 3; ++b) jac[a][b] += w * dv * basis[b];
      }
    }
    return residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2];
  };

  // Levenberg-Marquardt from the grey of the target's mean (c0 = c1 = 0).
  const double mean = std::clamp((target[0] + target[1] + target[2]) / 3.0, 1e-4, 1.0 - 1e-4);
  double c[3] = {0, 0, (mean - 0.5) / std::sqrt(mean * (1.0 - mean))};  // S^-1(mean)
  double residual[3], jac[3][3];
  double error = evaluate(c, residual, jac), mu = 1e-3;
  for (int it = 0; it < kMaxIterations && error > 1e-16; ++it) {
    double jtj[3][3], jtr[3];
    for (int a = 0; a < 3; ++a) {
      jtr[a] = 0;
      for (int b = 0; b < 3; ++b) {
        jtj[a][b] = 0;
        for (int r = 0; r < 3; ++r) jtj[a][b] += jac[r][a] * jac[r][b];
      }
      for (int r = 0; r < 3; ++r) jtr[a] -= jac[r][a] * residual[r];
    }
    for (int a = 0; a < 3; ++a) jtj[a][a] *= 1.0 + mu, jtj[a][a] += 1e-12;
    double step[3];
    if (!solve3(jtj, jtr, step)) break;
    const double trial[3] = {c[0] + step[0], c[1] + step[1], c[2] + step[2]};
    double trial_residual[3];
    const double trial_error = evaluate(trial, trial_residual, nullptr);
    if (trial_error < error) {
      std::copy(trial, trial + 3, c);
      error = evaluate(c, residual, jac);
      mu = std::max(mu * 0.3, 1e-9);
    } else {
      mu *= 10;
      if (mu > 1e12) break;
    }
  }
  s.c0 = c[0], s.c1 = c[1], s.c2 = c[2];
  return s;
}

}  // namespace btf
