#include "btf/material/sgd.h"

#include <cmath>
#include <numbers>

#include "analytic_support.h"
#include "half_vector_lobe.h"

namespace btf {

namespace {

constexpr double kPiD = std::numbers::pi;
// Proposal widths below this are widened: a narrower proposal only makes the density harder to
// integrate in float, and the widened lobe still covers the peak (the weight f cos / pdf rises).
constexpr float kMinProposalAlpha = 1e-3f;
constexpr float kMinDiffuseProbability = 0.1f;

double shadowing1(const SgdChannel& s, double theta) {
  // No shadowing without lambda; and where exp overflows (a large c), 0 * inf would be NaN.
  if (s.lambda == 0) return 1.0;
  const double excess = std::max(0.0, theta - s.theta0);
  return std::clamp(1.0 + s.lambda * (1.0 - std::exp(s.c * std::pow(excess, s.k))), 0.0, 1.0);
}

// Integral of y^-p e^-y over [from, to] by Simpson's rule in log y (the integrand spans decades
// near small alpha). Used only to weigh the sampling proposals, so a few hundred nodes suffice.
double shiftedGammaMass(double p, double from, double to) {
  constexpr int n = 400;  // even
  const double a = std::log(from), b = std::log(to), h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double y = std::exp(a + i * h);
    const double g = std::pow(y, 1.0 - p) * std::exp(-y);  // dy = y d(log y)
    sum += g * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return sum * h / 3.0;
}

void requireFinite(int channel, const char* parameter, double value) {
  if (!std::isfinite(value))
    throw Error("sgd: channel " + std::to_string(channel) + " " + parameter + " must be finite, got " +
                std::to_string(value));
}

}  // namespace

Sgd::Sgd(const SgdParameters& parameters, std::string label) : parameters_(parameters), label_(std::move(label)) {
  std::array<double, 3> strength{};
  for (int c = 0; c < 3; ++c) {
    const SgdChannel& s = parameters_.channel[c];
    const std::pair<const char*, double> all[] = {{"rho_d", s.rho_d}, {"rho_s", s.rho_s}, {"alpha", s.alpha},
                                                  {"p", s.p},         {"f0", s.f0},       {"f1", s.f1},
                                                  {"kap", s.kap},     {"lambda", s.lambda}, {"c", s.c},
                                                  {"k", s.k},         {"theta0", s.theta0}};
    for (const auto& [parameter, value] : all) requireFinite(c, parameter, value);
    if (s.rho_d < 0 || s.rho_s < 0 || s.kap < 0)
      throw Error("sgd: channel " + std::to_string(c) + " rho_d, rho_s and kap must be >= 0");
    if (!(s.alpha > 0)) throw Error("sgd: channel " + std::to_string(c) + " alpha must be > 0, got " + std::to_string(s.alpha));

    // int D cos(theta_h) dh = kap alpha int_alpha^inf y^-p e^-y dy (substituting y = alpha + t^2/alpha);
    // a specular lobe reflects about 4/pi rho_s times that at normal incidence.
    const double total = shiftedGammaMass(s.p, s.alpha, s.alpha + 60.0);
    const double core = shiftedGammaMass(s.p, s.alpha, 10.0 * s.alpha);
    strength[c] = 4.0 / kPiD * s.rho_s * s.kap * s.alpha * total;
    const double core_share = std::clamp(total > 0 ? core / total : 0.5, 0.05, 0.95);
    lobe_alpha_[2 * c] = std::max(float(s.alpha), kMinProposalAlpha);
    lobe_alpha_[2 * c + 1] = std::max(float(std::sqrt(s.alpha)), kMinProposalAlpha);
    lobe_probability_[2 * c] = float(core_share);
    lobe_probability_[2 * c + 1] = float(1.0 - core_share);
  }
  const double diffuse = (parameters_.channel[0].rho_d + parameters_.channel[1].rho_d + parameters_.channel[2].rho_d) / 3.0;
  const double specular = (strength[0] + strength[1] + strength[2]) / 3.0;
  const double share = diffuse + specular > 0 && std::isfinite(specular) ? diffuse / (diffuse + specular) : 1.0;
  diffuse_probability_ = std::max(float(share), kMinDiffuseProbability);
  const double strength_sum = strength[0] + strength[1] + strength[2];
  for (int c = 0; c < 3; ++c) {
    const double channel_share = strength_sum > 0 && std::isfinite(strength_sum) ? strength[c] / strength_sum : 1.0 / 3.0;
    for (int j = 0; j < 2; ++j) lobe_probability_[2 * c + j] *= float((1.0 - diffuse_probability_) * channel_share);
  }
}

Rgb Sgd::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  const glm::dvec3 i(wi), o(wo), sum = i + o;
  const double length = glm::length(sum);
  const glm::dvec3 h = sum / length;
  // i.h = o.h = |i + o| / 2: one expression for both keeps f reciprocal to the bit.
  const double cos_d = std::clamp(0.5 * length, 0.0, 1.0);
  const double tan2_h = (h.x * h.x + h.y * h.y) / (h.z * h.z);
  const double cos2_h = h.z * h.z;
  const double theta_i = std::atan2(std::hypot(i.x, i.y), i.z), theta_o = std::atan2(std::hypot(o.x, o.y), o.z);
  const double cos_io = i.z * o.z;
  Rgb f;
  for (int c = 0; c < 3; ++c) {
    const SgdChannel& s = parameters_.channel[c];
    const double ax = s.alpha + tan2_h / s.alpha;
    const double e = std::exp(-ax);
    // Far from the peak exp underflows to 0 while cos^4 may vanish too: D is 0 there, not 0/0.
    const double d = e > 0 ? s.kap * e / (kPiD * std::pow(ax, s.p) * cos2_h * cos2_h) : 0.0;
    const double g = shadowing1(s, theta_i) * shadowing1(s, theta_o);
    const double fresnel = s.f0 - cos_d * s.f1 + std::pow(1.0 - cos_d, 5.0) * (1.0 - s.f0);
    const double value = (s.rho_d + s.rho_s * fresnel * d * g / cos_io) / kPiD;
    f[c] = float(std::max(value, 0.0));
  }
  return f;
}

float Sgd::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const glm::vec3 sum = wi + wo;
  const float length = glm::length(sum);
  const glm::vec3 h = sum / length;
  double lobes = 0;
  for (int j = 0; j < kLobes; ++j) {
    if (lobe_probability_[j] <= 0.0f) continue;
    const detail::SlopeShape shape = j % 2 == 0 ? detail::SlopeShape::Ggx : detail::SlopeShape::Beckmann;
    lobes += lobe_probability_[j] * detail::halfVectorPdf({shape, lobe_alpha_[j]}, h);
  }
  // Reflection Jacobian dwh / dwi = 1 / (4 wo.h), with wo.h = |wi + wo| / 2.
  return float(diffuse_probability_ * cosineHemispherePdf(wi) + lobes / (2.0 * length));
}

std::optional<BsdfSample> Sgd::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  glm::vec3 wi;
  if (detail::chooseFirst(diffuse_probability_, u.x)) {
    wi = squareToCosineHemisphere(u);
  } else {
    // u.x is uniform again; pick the lobe in proportion to its share of the non-diffuse probability.
    float x = u.x * (1.0f - diffuse_probability_);
    int chosen = -1;
    for (int j = 0; j < kLobes; ++j) {
      if (lobe_probability_[j] <= 0.0f) continue;
      chosen = j;  // the last lobe with weight absorbs rounding at the top
      if (x < lobe_probability_[j]) break;
      x -= lobe_probability_[j];
    }
    if (chosen < 0) return std::nullopt;
    u.x = std::clamp(x / lobe_probability_[chosen], 0.0f, 0x1.fffffep-1f);
    const detail::SlopeShape shape = chosen % 2 == 0 ? detail::SlopeShape::Ggx : detail::SlopeShape::Beckmann;
    const glm::vec3 h = detail::sampleHalfVector({shape, lobe_alpha_[chosen]}, u);
    // A normal facing away from wo reflects nothing; its draw is lost (pdf integrates below 1).
    if (glm::dot(wo, h) <= 0.0f) return std::nullopt;
    wi = reflect(wo, h);
  }
  if (wi.z <= 0.0f) return std::nullopt;
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

std::string Sgd::name() const {
  if (!label_.empty()) return "sgd(" + label_ + ")";
  const auto& ch = parameters_.channel;
  return "sgd(alpha=" + detail::formatRgb(Rgb(float(ch[0].alpha), float(ch[1].alpha), float(ch[2].alpha))) + ")";
}

}  // namespace btf
