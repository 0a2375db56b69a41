#include "btf/material/abc.h"

#include <cmath>
#include <numbers>

#include "analytic_support.h"

namespace btf {

namespace {

constexpr double kPiD = std::numbers::pi;
constexpr float kMinDiffuseProbability = 0.1f;

// E(z) = int_0^z e^((1 - C) w) dw: int_0^u (1 + B v)^-C dv = E(log(1 + B u)) / B. Written with
// expm1 so that C close to 1 (where E(z) -> z) keeps its digits.
double integralInLog(double one_minus_c, double z) {
  const double x = one_minus_c * z;
  return std::abs(x) < 1e-12 ? z : std::expm1(x) / one_minus_c;
}

}  // namespace

double Abc::fresnelDielectric(double cos_theta, double ior) {
  const double c = std::clamp(cos_theta, 0.0, 1.0);
  const double g = std::sqrt(ior * ior + c * c - 1.0);
  const double a = (g - c) / (g + c);
  const double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

Abc::Abc(const AbcParameters& parameters, std::string label) : parameters_(parameters), label_(std::move(label)) {
  detail::requireDiffuseAlbedo("abc", "kd", parameters_.kd);
  detail::requireAlbedo("abc", "A", parameters_.a);
  if (!std::isfinite(parameters_.b) || !(parameters_.b > 0))
    throw Error("abc: B must be finite and > 0, got " + std::to_string(parameters_.b));
  if (!std::isfinite(parameters_.c)) throw Error("abc: C must be finite, got " + std::to_string(parameters_.c));
  if (!std::isfinite(parameters_.ior) || !(parameters_.ior >= 1))
    throw Error("abc: ior must be finite and >= 1, got " + std::to_string(parameters_.ior));
  log1p_b_ = std::log1p(parameters_.b);
  normalizer_ = 2.0 * kPiD * integralInLog(1.0 - parameters_.c, log1p_b_) / parameters_.b;
  // Specular strength at normal incidence: int f_s cos dwi ~ (4 / pi) F(1) int D cos_h dh,
  // bounded by int D dh = A normalizer.
  const double specular = 4.0 / kPiD * fresnelDielectric(1.0, parameters_.ior) * parameters_.a.average() * normalizer_;
  const double diffuse = parameters_.kd.average();
  const double share = diffuse + specular > 0 && std::isfinite(specular) ? diffuse / (diffuse + specular) : 1.0;
  diffuse_probability_ = std::max(float(share), kMinDiffuseProbability);
}

Rgb Abc::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  const glm::dvec3 i(wi), o(wo), sum = i + o;
  const double length = glm::length(sum);
  const glm::dvec3 h = sum / length;
  // h.wi = h.wo = |wi + wo| / 2, used for both so that f is reciprocal to the bit.
  const double cos_d = std::clamp(0.5 * length, 0.0, 1.0);
  const double one_minus_cos_h = (h.x * h.x + h.y * h.y) / (1.0 + h.z);  // 1 - cos without cancellation
  const double g = std::min({1.0, 2.0 * h.z * i.z / cos_d, 2.0 * h.z * o.z / cos_d});
  const double fresnel = fresnelDielectric(cos_d, parameters_.ior);
  const double shape = std::pow(1.0 + parameters_.b * one_minus_cos_h, -parameters_.c);
  const double specular = fresnel * shape * g / (kPiD * (i.z * o.z));
  Rgb f;
  for (int c = 0; c < 3; ++c) f[c] = float(parameters_.kd[c] / kPiD + parameters_.a[c] * specular);
  return f;
}

double Abc::halfVectorPdf(const glm::vec3& h) const {
  if (h.z <= 0.0f) return 0.0;
  const double u = (double(h.x) * h.x + double(h.y) * h.y) / (1.0 + h.z);
  return std::exp(-parameters_.c * std::log1p(parameters_.b * u)) / normalizer_;
}

glm::vec3 Abc::sampleHalfVector(glm::vec2 u) const {
  // Invert E(log(1 + B u)) = xi E(log(1 + B)) for z = log(1 + B u), then u = expm1(z) / B.
  const double one_minus_c = 1.0 - parameters_.c, xi = u.x;
  const double x = one_minus_c * log1p_b_;
  const double z = std::abs(x) < 1e-12 ? xi * log1p_b_ : std::log1p(xi * std::expm1(x)) / one_minus_c;
  const double one_minus_cos = std::clamp(std::expm1(z) / parameters_.b, 0.0, 1.0);
  const double cos_theta = 1.0 - one_minus_cos;
  const double sin_theta = std::sqrt(one_minus_cos * (2.0 - one_minus_cos));
  const double phi = 2.0 * kPiD * u.y;
  return {float(sin_theta * std::cos(phi)), float(sin_theta * std::sin(phi)), float(cos_theta)};
}

float Abc::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const glm::vec3 sum = wi + wo;
  const float length = glm::length(sum);
  // Reflection Jacobian 1 / (4 wo.h) with wo.h = |wi + wo| / 2.
  const double specular = halfVectorPdf(sum / length) / (2.0 * length);
  return float(diffuse_probability_ * cosineHemispherePdf(wi) + (1.0 - diffuse_probability_) * specular);
}

std::optional<BsdfSample> Abc::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  glm::vec3 wi;
  if (detail::chooseFirst(diffuse_probability_, u.x)) {
    wi = squareToCosineHemisphere(u);
  } else {
    const glm::vec3 h = sampleHalfVector(u);
    if (glm::dot(wo, h) <= 0.0f) return std::nullopt;  // facing away from wo: a lost draw
    wi = reflect(wo, h);
  }
  if (wi.z <= 0.0f) return std::nullopt;
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

std::string Abc::name() const {
  if (!label_.empty()) return "abc(" + label_ + ")";
  return "abc(kd=" + detail::formatRgb(parameters_.kd) + ", A=" + detail::formatRgb(parameters_.a) +
         ", B=" + std::to_string(parameters_.b) + ", C=" + std::to_string(parameters_.c) +
         ", ior=" + std::to_string(parameters_.ior) + ")";
}

}  // namespace btf
