#include "btf/material/rgl_brdf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <span>

#include "btf/core/cie.h"
#include "btf/core/error.h"
#include "btf/core/fast_atan.h"
#include "btf/core/math.h"
#include "btf/material/registry.h"

namespace btf {
namespace {

// Unit coordinates of the file: theta through a square root (dense near the pole, where glossy
// lobes are), phi over [-pi, pi).
float thetaToUnit(float theta) { return std::sqrt(std::max(theta, 0.0f) * (2.0f / kPi)); }
float unitToTheta(float u) { return u * u * kHalfPi; }
float phiToUnit(float phi) {
  const float u = (phi + kPi) * kInv2Pi;
  return u - std::floor(u);  // relative azimuths span (-2 pi, 2 pi); wrap onto [0, 1)
}

// d(solid angle of m) / d(u_m) = sin(theta_m) dtheta/du_x dphi/du_y = sin(theta_m) (pi u_x) (2 pi).
// It vanishes like u_x^3 at the pole, where the warps keep a finite density over the square, so
// the solid-angle density grows without bound there; like the reference loader, the Jacobian is
// held at 1e-6 or more. That makes the pdf finite (a draw at u_x = 0, the mirror direction, is a
// valid draw) and changes the density only within ~1e-5 rad of the pole, where it understates it:
// the estimator's bias is at most 1e-6 times the u_x-width of that cap (~3e-3) times f cos.
float unitToSolidAngleJacobian(float u_x, float sin_theta_m) {
  return std::max(2.0f * kPi * kPi * u_x * sin_theta_m, 1e-6f);
}

// The range of every table's values. Finite floats beyond it pass the reader's NaN check but
// overflow once multiplied (rgb x ndf / sigma) or summed by the warps: 3.4e38 in one rgb entry
// gave an albedo of inf. No measured quantity comes near; sigma (a projected area, about 1) may
// not come near 0 either.
constexpr float kMaxMagnitude = 1e10f;
constexpr float kMinSigma = 1e-10f;

std::vector<float> floatsOf(const TensorFile& file, const TensorField& field) {
  std::vector<float> values = field.toFloats();
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!(std::abs(values[i]) <= kMaxMagnitude)) {
      char text[160];
      std::snprintf(text, sizeof text, "field '%s' holds %g at element %zu, beyond the range of measured values (|value| <= %g)",
                    field.name.c_str(), double(values[i]), i, double(kMaxMagnitude));
      throw FileError(file.path, text);
    }
  return values;
}

// The `spectra` table [1, theta, wavelength, R, R] as linear sRGB [theta, channel, R, R].
std::vector<float> spectraAsRgb(const TensorFile& file, std::int64_t n_theta, std::int64_t res_y, std::int64_t res_x) {
  const TensorField& wavelengths = file.require("wavelengths", TensorDtype::Float32, {-1});
  const auto nw = static_cast<std::int64_t>(wavelengths.shape[0]);
  const TensorField& spectra = file.require("spectra", TensorDtype::Float32, {1, n_theta, nw, res_y, res_x});
  std::vector<float> wl = floatsOf(file, wavelengths);
  std::optional<SpectrumToRgb> projection;
  try {
    projection.emplace(wl);
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(file.path, std::string("field 'wavelengths': ") + e.what());
  }
  const std::vector<float> values = floatsOf(file, spectra);
  const std::size_t slice = std::size_t(res_y) * std::size_t(res_x), nws = std::size_t(nw);
  std::vector<float> rgb(std::size_t(n_theta) * 3 * slice);
  for (std::size_t t = 0; t < std::size_t(n_theta); ++t)
    for (std::size_t node = 0; node < slice; ++node) {
      const Rgb c = projection->strided(&values[t * nws * slice + node], slice);
      for (std::size_t ch = 0; ch < 3; ++ch) rgb[(t * 3 + ch) * slice + node] = c[int(ch)];
    }
  return rgb;
}

}  // namespace

RglBrdf::RglBrdf(const std::filesystem::path& path, RglChannels channels) : RglBrdf(readTensorFile(path), channels) {}

RglBrdf::RglBrdf(const TensorFile& file, RglChannels channels) : stem_(file.path.stem().string()) {
  const auto& path = file.path;
  const bool from_spectra = channels == RglChannels::Spectra || !file.find("rgb");
  if (from_spectra && !file.find("spectra"))
    throw FileError(path, channels == RglChannels::Spectra ? "has no field 'spectra' (an RGB-only file)"
                                                           : "has neither field 'rgb' nor field 'spectra'");
  const TensorField& phi_i = file.require("phi_i", TensorDtype::Float32, {-1});
  if (phi_i.shape[0] != 1)
    throw FileError(path, "anisotropic RGL file (phi_i has " + std::to_string(phi_i.shape[0]) +
                              " values): only isotropic files (one phi_i) are supported");
  const TensorField& theta_i = file.require("theta_i", TensorDtype::Float32, {-1});
  theta_o_ = floatsOf(file, theta_i);
  const auto n_theta = static_cast<std::int64_t>(theta_o_.size());
  if (n_theta < 2) throw FileError(path, "field 'theta_i' needs at least 2 values");
  for (std::size_t k = 0; k < theta_o_.size(); ++k)
    if (theta_o_[k] < 0.0f || theta_o_[k] > kHalfPi + 1e-4f || (k > 0 && !(theta_o_[k] > theta_o_[k - 1])))
      throw FileError(path, "field 'theta_i' must increase strictly within [0, pi/2]");

  const TensorField& ndf = file.require("ndf", TensorDtype::Float32, {-1, -1});
  const TensorField& sigma = file.require("sigma", TensorDtype::Float32, {-1, -1});
  const TensorField& vndf = file.require("vndf", TensorDtype::Float32, {1, n_theta, -1, -1});
  const TensorField& luminance = file.require("luminance", TensorDtype::Float32, {1, n_theta, -1, -1});
  const auto res_y = static_cast<std::int64_t>(luminance.shape[2]), res_x = static_cast<std::int64_t>(luminance.shape[3]);
  const TensorField* rgb = from_spectra ? nullptr : &file.require("rgb", TensorDtype::Float32, {1, n_theta, 3, res_y, res_x});
  const TensorField& jacobian = file.require("jacobian", TensorDtype::UInt8, {1});
  jacobian_ = std::to_integer<int>(jacobian.bytes[0]) != 0;
  if (const TensorField* d = file.find("description")) {
    if (d->dtype != TensorDtype::UInt8 || d->shape.size() != 1)
      throw FileError(path, "field 'description' must be u8 text of rank 1");
    description_ = d->toText();
  }

  const std::vector<float> sigma_values = floatsOf(file, sigma);
  for (const float s : sigma_values)
    if (!(s >= kMinSigma)) throw FileError(path, "field 'sigma' (projected area) holds a value <= 0 or below 1e-10");
  const std::vector<float> ndf_values = floatsOf(file, ndf);
  for (const float d : ndf_values)
    if (d < 0.0f) throw FileError(path, "field 'ndf' holds a negative value");

  // Build each grid; a construction error names the field (slice k is theta_i[k], times 3 + channel
  // for rgb).
  auto buildFrom = [&](const char* name, const TensorField& field, std::vector<float> values, int w, int h,
                       std::vector<std::vector<float>> params, BilinearWarp2D::Mode mode) {
    try {
      return BilinearWarp2D(w, h, std::move(values), std::move(params), mode);
    } catch (const FileError&) {
      throw;
    } catch (const Error& e) {
      throw FileError(path, "field '" + std::string(name) + "' " + field.shapeString() + ": " + e.what());
    }
  };
  auto build = [&](const char* name, const TensorField& field, int w, int h, std::vector<std::vector<float>> params,
                   BilinearWarp2D::Mode mode) {
    return buildFrom(name, field, floatsOf(file, field), w, h, std::move(params), mode);
  };
  using Mode = BilinearWarp2D::Mode;
  auto dim = [](const TensorField& f, std::size_t i) { return static_cast<int>(f.shape[i]); };
  ndf_ = build("ndf", ndf, dim(ndf, 1), dim(ndf, 0), {}, Mode::Interpolant);
  sigma_ = build("sigma", sigma, dim(sigma, 1), dim(sigma, 0), {}, Mode::Interpolant);
  vndf_ = build("vndf", vndf, dim(vndf, 3), dim(vndf, 2), {theta_o_}, Mode::Distribution);
  luminance_ = build("luminance", luminance, dim(luminance, 3), dim(luminance, 2), {theta_o_}, Mode::Distribution);
  std::vector<std::vector<float>> rgb_params = {theta_o_, {0.0f, 1.0f, 2.0f}};
  if (rgb)
    rgb_ = build("rgb", *rgb, int(res_x), int(res_y), std::move(rgb_params), Mode::Interpolant);
  else
    rgb_ = buildFrom("spectra", *file.find("spectra"), spectraAsRgb(file, n_theta, res_y, res_x), int(res_x), int(res_y),
                     std::move(rgb_params), Mode::Interpolant);
}

RglBrdf::Outgoing RglBrdf::outgoing(const glm::vec3& wo) const {
  // Angles through fastAtan2Turns as in halfVectorUnit: every query sets wo up, and std::atan2
  // here is a noticeable share of an eval.
  const float theta_o = kTwoPi * fastAtan2Turns(std::hypot(wo.x, wo.y), wo.z);
  const float phi_o_turns = fastAtan2Turns(wo.y, wo.x), phi_o = kTwoPi * phi_o_turns;
  const float params[1] = {theta_o};
  const glm::vec2 u_o(thetaToUnit(theta_o), phiToUnit(phi_o));
  return {theta_o,
          phi_o_turns,
          u_o,
          vndf_.fixed(params),
          rgb_.fixedLeading(params),
          jacobian_ ? sigma_.eval(u_o) : 1.0f};
}

BilinearWarp2D::Fixed RglBrdf::luminanceAt(const Outgoing& o) const {
  const float params[1] = {o.theta_o};
  return luminance_.fixed(params);
}

Rgb RglBrdf::reflectanceTimesCos(glm::vec2 s, glm::vec2 u_m, const Outgoing& o) const {
  float channels[3];
  o.rgb.evalAtEveryLastValue(s, channels);
  Rgb f;
  // Negative values are spectral data outside the RGB gamut; the reference loader clips them.
  for (int c = 0; c < 3; ++c) f[c] = std::max(channels[c], 0.0f);
  if (jacobian_) f *= ndf_.eval(u_m) / (4.0f * o.sigma);
  return f;
}

glm::vec2 RglBrdf::halfVectorUnit(const glm::vec3& m, float sin_theta_m, const Outgoing& o) {
  // theta_m / (2 pi) is in [0, 1/2] (sin_theta_m >= 0), so theta_m (2 / pi) = 4 turns needs no
  // clamp at 0.
  const float theta_turns = fastAtan2Turns(sin_theta_m, m.z);
  float u_y = fastAtan2Turns(m.y, m.x) - o.phi_o_turns + 0.5f;
  u_y -= std::floor(u_y);  // relative azimuths span (-1, 1) turns; wrap onto [0, 1)
  // At the pole of m (u_m.x = 0, the mirror direction) the files' VNDF density over the square is
  // 0, so the mirror direction that a draw with u.x = 0 lands on would get pdf 0 and be dropped.
  // The warps are evaluated at u_m.x >= 1e-4 instead (theta_m >= 1.6e-8 rad, where they hold
  // ~1e-8 of their mass): the pdf stays positive and continuous up to the pole.
  // The operands go kPoleGuard first so that a NaN (m from a wi + wo too short to normalize, e.g.
  // wi and wo opposite just above the horizon) becomes the guard; a NaN u_y becomes 0. The
  // lookups then stay finite, where the old NaN made eval NaN.
  constexpr float kPoleGuard = 1e-4f;
  if (!(u_y >= 0.0f)) u_y = 0.0f;
  return {std::max(kPoleGuard, std::sqrt(theta_turns * 4.0f)), u_y};
}

RglBrdf::InverseMap RglBrdf::mapBack(const glm::vec3& wi, const glm::vec3& wo, const Outgoing& o,
                                     const BilinearWarp2D::Fixed* luminance) const {
  InverseMap r;
  const glm::vec3 m = glm::normalize(wi + wo);
  const float sin_theta_m = std::sqrt(m.x * m.x + m.y * m.y);
  r.u_m = halfVectorUnit(m, sin_theta_m, o);
  if (!luminance) {
    r.s = o.vndf.invert(r.u_m).p;
    return r;
  }
  const auto [s, vndf_pdf] = o.vndf.invert(r.u_m);
  r.s = s;
  const float jacobian = unitToSolidAngleJacobian(r.u_m.x, sin_theta_m) * 4.0f * glm::dot(wo, m);
  const float pdf = jacobian > 0.0f ? vndf_pdf * luminance->eval(s) / jacobian : 0.0f;
  r.pdf = std::isfinite(pdf) ? pdf : 0.0f;
  return r;
}

Rgb RglBrdf::evalWith(const glm::vec3& wi, const glm::vec3& wo, const Outgoing& o) const {
  if (wi.z <= 0.0f) return {};
  const InverseMap r = mapBack(wi, wo, o, nullptr);
  // The tables hold f cos(theta_i) (what a renderer multiplies by anyway); f itself divides it out.
  return reflectanceTimesCos(r.s, r.u_m, o) / wi.z;
}

Rgb RglBrdf::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  return evalWith(wi, wo, outgoing(wo));
}

void RglBrdf::evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out, glm::vec2) const {
  checkEvalManySizes(wi, out);
  if (wo.z <= 0.0f) {
    std::fill(out.begin(), out.end(), Rgb{});
    return;
  }
  const Outgoing o = outgoing(wo);
  for (std::size_t k = evalLanes(wo, o, wi, out); k < wi.size(); ++k) out[k] = evalWith(wi[k], wo, o);
}

std::optional<RglBrdf::DirectionSample> RglBrdf::sampleDirection(const glm::vec3& wo, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const Outgoing o = outgoing(wo);
  const BilinearWarp2D::Fixed luminance = luminanceAt(o);
  const auto drawn = draw(wo, o, luminance, u);
  if (!drawn) return std::nullopt;
  return DirectionSample{drawn->first, drawn->second.pdf};
}

std::optional<std::pair<glm::vec3, RglBrdf::InverseMap>> RglBrdf::draw(const glm::vec3& wo, const Outgoing& o,
                                                                        const BilinearWarp2D::Fixed& luminance,
                                                                        glm::vec2 u) const {
  const glm::vec2 s = luminance.sample(u).p;
  const glm::vec2 u_m = o.vndf.sample(s).p;
  const glm::vec3 m = sphericalDirection(unitToTheta(u_m.x), u_m.y * kTwoPi - kPi + kTwoPi * o.phi_o_turns);
  const float wo_dot_m = glm::dot(wo, m);
  if (wo_dot_m <= 0.0f) return std::nullopt;  // back-facing m: interpolation leaked past the horizon
  const glm::vec3 wi = 2.0f * wo_dot_m * m - wo;
  if (wi.z <= 0.0f) return std::nullopt;
  // The pdf and the weight come from wi through the inverse maps, as pdf() and eval() compute
  // them, so that sample().pdf == pdf(wi, wo) exactly. The forward path's own density differs from
  // it by float round-off, except near the pole, where m's few significant bits after the
  // reflection make the two disagree by orders of magnitude (|u| < 1e-5 at grazing wo).
  const InverseMap r = mapBack(wi, wo, o, &luminance);
  if (!(r.pdf > 0.0f)) return std::nullopt;  // the edge of the support
  return std::make_pair(wi, r);
}

std::optional<BsdfSample> RglBrdf::sample(const glm::vec3& wo, glm::vec2, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const Outgoing o = outgoing(wo);
  const BilinearWarp2D::Fixed luminance = luminanceAt(o);
  const auto drawn = draw(wo, o, luminance, u);
  if (!drawn) return std::nullopt;
  const auto& [wi, r] = *drawn;
  const Rgb weight = reflectanceTimesCos(r.s, r.u_m, o) / r.pdf;
  // A weight beyond the float range means the file's values and the luminance its warp was built
  // from disagree by dozens of orders of magnitude (a damaged or forged file; a fuzzed one had f
  // 8e10 where the warp's density was 2e-32). Such a draw would poison any estimator, so it is
  // dropped like a draw where nothing reflects.
  if (!weight.isFinite()) return std::nullopt;
  return BsdfSample{wi, weight, r.pdf};
}

float RglBrdf::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const Outgoing o = outgoing(wo);
  const BilinearWarp2D::Fixed luminance = luminanceAt(o);
  return mapBack(wi, wo, o, &luminance).pdf;
}

std::string RglBrdf::name() const { return "rgl(" + stem_ + ")"; }

BTF_REGISTER_MATERIAL(rgl, {.name = "rgl",
                            .summary = "an RGL measured material, evaluated and sampled through its own warp",
                            .keys = {"file"},
                            .formats = {{.description = "RGL measured material (tensor_file, Dupuy & Jakob 2018)",
                                         .extensions = {".bsdf"},
                                         .sniff = [](std::span<const unsigned char> head, std::uintmax_t) {
                                           constexpr char magic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
                                           return head.size() >= sizeof magic && std::memcmp(head.data(), magic, sizeof magic) == 0;
                                         }}},
                            .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                              return std::make_shared<RglBrdf>(p.existingPath("file"));
                            }});

}  // namespace btf
