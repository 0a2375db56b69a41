// The isotropic models of analytic_fit.h written once more, templated on the scalar, so that
// Ceres' Jets differentiate them. The Material classes (material/ggx.h, ward.h, lafortune.h) are
// float, virtual and general (anisotropic); a test (test_analytic_fit.cpp) holds these formulas to
// them at random parameters and directions.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

namespace btf::fit {

// Everything the models need of one direction pair, computed once in double.
struct FitSample {
  double cos_i = 0, cos_o = 0;
  double tan2_i = 0, tan2_o = 0;  // tan^2 of theta_i and theta_o
  double h_z2 = 0, h_xy2 = 0;     // squared components of the unit half vector along / across the normal
  double half_length = 0;         // |wi + wo| / 2 = wi.h = wo.h
  double sum_length2 = 0;         // |wi + wo|^2
  double product_xy = 0;          // wi.x wo.x + wi.y wo.y
  double product_z = 0;           // wi.z wo.z
  double target[3] = {};          // ln(1 + cos_i f_data) per channel
  double value[3] = {};           // cos_i f_data per channel (the linear objective's target)
};

// The geometry of a direction pair as the formulas below read it (target left at 0).
inline FitSample geometryOf(const glm::vec3& wi, const glm::vec3& wo) {
  FitSample s;
  s.cos_i = wi.z;
  s.cos_o = wo.z;
  s.tan2_i = (1.0 - s.cos_i * s.cos_i) / (s.cos_i * s.cos_i);
  s.tan2_o = (1.0 - s.cos_o * s.cos_o) / (s.cos_o * s.cos_o);
  const glm::dvec3 sum = glm::dvec3(wi) + glm::dvec3(wo);
  s.sum_length2 = glm::dot(sum, sum);
  const double length = std::sqrt(s.sum_length2);
  s.half_length = 0.5 * length;
  s.h_z2 = (sum.z / length) * (sum.z / length);
  s.h_xy2 = std::max(0.0, 1.0 - s.h_z2);
  s.product_xy = double(wi.x) * wo.x + double(wi.y) * wo.y;
  s.product_z = double(wi.z) * wo.z;
  return s;
}

inline constexpr double kFitPi = std::numbers::pi;

template <class T>
T pow5(const T& x) {
  const T x2 = x * x;
  return x2 * x2 * x;
}

// Parameters: kd[3], f0[3], ln(alpha).
template <class T>
void evalGgx(const T* p, const FitSample& s, T* f) {
  using std::exp;
  using std::sqrt;
  const T alpha = exp(p[6]);
  const T a2 = alpha * alpha;
  const T q = T(s.h_xy2) / a2 + T(s.h_z2);
  const T d = T(1) / (T(kFitPi) * a2 * q * q);
  const T lambda_i = T(0.5) * (sqrt(T(1) + a2 * T(s.tan2_i)) - T(1));
  const T lambda_o = T(0.5) * (sqrt(T(1) + a2 * T(s.tan2_o)) - T(1));
  const T specular = d / (T(1) + (lambda_i + lambda_o)) / T(4 * s.cos_i * s.cos_o);
  const double m_h = pow5(1.0 - std::min(s.half_length, 1.0));
  const double m_i = pow5(1.0 - s.cos_i), m_o = pow5(1.0 - s.cos_o);
  for (int c = 0; c < 3; ++c) {
    const T& kd = p[c];
    const T& f0 = p[3 + c];
    const T fresnel_h = f0 + (T(1) - f0) * T(m_h);
    const T transmit_i = (T(1) - f0) * T(1 - m_i);  // 1 - F(cos_i)
    const T transmit_o = (T(1) - f0) * T(1 - m_o);
    f[c] = fresnel_h * specular + kd / T(kFitPi) * transmit_i * transmit_o;
  }
}

// Parameters: kd[3], f0[3], ln(alpha), f0_2[3], ln(alpha_2): evalGgx plus a second GGX lobe
// without a diffuse term (material/ggx_two_lobes.h).
template <class T>
void evalGgx2(const T* p, const FitSample& s, T* f) {
  evalGgx(p, s, f);
  T second[7] = {T(0), T(0), T(0), p[7], p[8], p[9], p[10]};
  T g[3];
  evalGgx(second, s, g);
  for (int c = 0; c < 3; ++c) f[c] += g[c];
}

// ABC (material/abc.h, Löw et al. 2012). Parameters: kd[3], ln A[3], ln B, C, ior. The shadowing,
// the half vector and cos_d depend on the directions alone and stay double.
template <class T>
void evalAbc(const T* p, const FitSample& s, T* f) {
  using std::exp;
  using std::log;
  using std::sqrt;
  const double cos_h = std::sqrt(s.h_z2);
  const double one_minus_cos_h = s.h_xy2 / (1.0 + cos_h);  // without cancellation near the normal
  const double cos_d = std::min(s.half_length, 1.0);
  const double g = std::min({1.0, 2.0 * cos_h * s.cos_i / cos_d, 2.0 * cos_h * s.cos_o / cos_d});
  const T shape = exp(-p[7] * log(T(1) + exp(p[6]) * T(one_minus_cos_h)));
  const T& ior = p[8];
  const T root = sqrt(ior * ior + T(cos_d * cos_d - 1.0));
  const T a = (root - T(cos_d)) / (root + T(cos_d));
  const T b = (T(cos_d) * (root + T(cos_d)) - T(1)) / (T(cos_d) * (root - T(cos_d)) + T(1));
  const T fresnel = T(0.5) * a * a * (T(1) + b * b);
  const T specular = fresnel * shape * T(g / (kFitPi * s.cos_i * s.cos_o));
  for (int c = 0; c < 3; ++c) f[c] = p[c] / T(kFitPi) + exp(p[3 + c]) * specular;
}

// The SGD (material/sgd.h, Bagher et al. 2012) with one lobe shape for the three channels and its
// shadowing written as G1 = clamp(1 + lambda (1 - exp((theta / w)^k)), 0, 1) with k = kSgdFitK and
// theta0 = 0 (the published form with c = w^-k): the published c spans forty decades and k a hundred,
// a range no local solver crosses, while w is an angle in radians. kap is 1 (rho_s kap is one
// degree of freedom). Parameters: rho_d[3], ln rho_s[3], ln alpha, p, f0, f1, lambda, w.
inline constexpr double kSgdFitK = 25.0;

template <class T>
T sgdShadowing(const T& lambda, const T& w, double theta) {
  using std::exp;
  using std::log;
  if (theta <= 0.0) return T(1);
  const T t = exp(T(kSgdFitK) * (T(std::log(theta)) - log(w)));
  if (t > T(40)) return lambda > T(0) ? T(0) : T(1);  // exp(t) would overflow; G1 is clamped to 0 there
  const T g = T(1) + lambda * (T(1) - exp(t));
  return g < T(0) ? T(0) : g;
}

template <class T>
void evalSgd(const T* p, const FitSample& s, T* f) {
  using std::exp;
  using std::log;
  const T alpha = exp(p[6]);
  const T& power = p[7];
  const T& f0 = p[8];
  const T& f1 = p[9];
  const double tan2_h = s.h_xy2 / s.h_z2;
  const T ax = alpha + T(tan2_h) / alpha;
  const T e = exp(-ax);
  const T d = e > T(0) ? e / (T(kFitPi) * exp(power * log(ax)) * T(s.h_z2 * s.h_z2)) : T(0);
  const double theta_i = std::acos(std::clamp(s.cos_i, -1.0, 1.0)), theta_o = std::acos(std::clamp(s.cos_o, -1.0, 1.0));
  const T g = sgdShadowing(p[10], p[11], theta_i) * sgdShadowing(p[10], p[11], theta_o);
  const double cos_d = std::min(s.half_length, 1.0);
  const T fresnel = f0 - T(cos_d) * f1 + T(pow5(1.0 - cos_d)) * (T(1) - f0);
  const T lobe = fresnel * d * g / T(s.cos_i * s.cos_o);
  for (int c = 0; c < 3; ++c) {
    const T value = (p[c] + exp(p[3 + c]) * lobe) / T(kFitPi);
    f[c] = value > T(0) ? value : T(0);  // as the material clamps
  }
}

// Parameters: kd[3], ks[3], ln(alpha).
template <class T>
void evalWard(const T* p, const FitSample& s, T* f) {
  using std::exp;
  const T alpha = exp(p[6]);
  const T a2 = alpha * alpha;
  const T d = exp(-(T(s.h_xy2) / a2) / T(s.h_z2)) / (T(kFitPi) * a2 * T(s.h_z2 * s.h_z2));
  for (int c = 0; c < 3; ++c) f[c] = p[c] / T(kFitPi) + p[3 + c] * d / T(s.sum_length2);
}

// kChannels 3 (shared lobes, RGB weights) or 1 (one channel of a per-channel fit). Parameters:
// kd[kChannels], then per lobe: beta, ln(n), rho[kChannels], with c = (cos beta, cos beta, sin beta).
template <int kChannels>
constexpr int lafortuneParameterCount(int lobes) {
  return kChannels + lobes * (2 + kChannels);
}

template <int kChannels, int kLobes, class T>
void evalLafortune(const T* p, const FitSample& s, T* f) {
  using std::abs;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  for (int c = 0; c < kChannels; ++c) f[c] = p[c] / T(kFitPi);
  for (int l = 0; l < kLobes; ++l) {
    const T* lobe = p + kChannels + l * (2 + kChannels);
    const T cxy = cos(lobe[0]), cz = sin(lobe[0]);
    const T max_c = abs(cxy) > abs(cz) ? abs(cxy) : abs(cz);
    const T d = (cxy * T(s.product_xy) + cz * T(s.product_z)) / max_c;
    if (!(d > T(0))) continue;
    const T n = exp(lobe[1]);
    const T shape = (n + T(2)) / T(2 * kFitPi) * exp(n * log(d));
    for (int c = 0; c < kChannels; ++c) f[c] += lobe[2 + c] * shape;
  }
}

}  // namespace btf::fit
