#include "btf/material/rgl_acquisition.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>

#include "btf/core/bilinear_warp2d.h"
#include "btf/core/cie.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rgb_to_spectrum.h"

namespace btf {
namespace {

constexpr double kPiDouble = std::numbers::pi;
// The smallest cos(theta) a direction is evaluated at (see the header).
constexpr float kMinEvalCos = 1e-3f;
// D is held at this fraction of its peak or more: a material whose back-scattering vanishes at
// some angles (a table with unmeasured cells there) would otherwise get a VNDF that never reaches
// those half vectors, and its reflection there would be lost from the file.
constexpr double kNdfFloor = 1e-6;
// Quadrature points per node interval of the theta_m integral of sigma.
constexpr int kSigmaSubsteps = 8;
constexpr int kMaxPowerIterations = 200;

double acquisitionTheta(double u) { return u * u * (kPiDouble / 2); }
float acquisitionUnit(float theta) { return std::sqrt(std::max(theta, 0.0f) * (2.0f / kPi)); }

glm::vec3 clampToHemisphere(glm::vec3 w) {
  return w.z >= kMinEvalCos ? w : glm::normalize(glm::vec3(w.x, w.y, kMinEvalCos));
}

// int_0^{2 pi} max(0, cos(theta_w) cos(theta_m) + sin(theta_w) sin(theta_m) cos(phi)) dphi: the
// azimuthal integral of the projected-area kernel, in closed form.
double azimuthalCosineIntegral(double theta_w, double theta_m) {
  const double a = std::cos(theta_w) * std::cos(theta_m), b = std::sin(theta_w) * std::sin(theta_m);
  if (a >= b) return 2 * kPiDouble * a;
  if (a <= -b) return 0.0;
  const double phi0 = std::acos(-a / b);
  return 2 * (a * phi0 + b * std::sin(phi0));
}

// sigma(theta_j) = sum_k kernel[j][k] D_k for D linear in u between its nodes.
std::vector<double> projectedAreaKernel(int n) {
  std::vector<double> kernel(std::size_t(n) * n, 0.0);
  const double h = 1.0 / (n - 1);
  for (int j = 0; j < n; ++j) {
    const double theta_w = acquisitionTheta(j * h);
    for (int k = 0; k + 1 < n; ++k)
      for (int s = 0; s < kSigmaSubsteps; ++s) {
        const double t = (s + 0.5) / kSigmaSubsteps, u = (k + t) * h, theta_m = acquisitionTheta(u);
        // dm = sin(theta_m) dtheta_m dphi, dtheta_m = pi u du.
        const double w = azimuthalCosineIntegral(theta_w, theta_m) * std::sin(theta_m) * kPiDouble * u * h / kSigmaSubsteps;
        kernel[std::size_t(j) * n + k] += (1 - t) * w;
        kernel[std::size_t(j) * n + k + 1] += t * w;
      }
  }
  return kernel;
}

std::vector<double> applyKernel(const std::vector<double>& kernel, const std::vector<double>& x) {
  const std::size_t n = x.size();
  std::vector<double> y(n, 0.0);
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = 0; k < n; ++k) y[j] += kernel[j * n + k] * x[k];
  return y;
}

std::string degrees(const glm::vec3& w) {
  char text[64];
  std::snprintf(text, sizeof text, "(theta %.2f, phi %.2f deg)", double(sphericalTheta(w)) * 180 / kPiDouble,
                double(sphericalPhi(w)) * 180 / kPiDouble);
  return text;
}

// f(wi, wo), refused unless finite and non-negative: a file of such values would be read as
// corrupt, or sample a negative density.
Rgb measure(const Material& material, const glm::vec3& wi, const glm::vec3& wo) {
  const Rgb f = material.eval(wi, wo);
  if (!f.isFinite() || f.r < 0 || f.g < 0 || f.b < 0) {
    char text[96];
    std::snprintf(text, sizeof text, "(%g, %g, %g)", double(f.r), double(f.g), double(f.b));
    throw Error(material.name() + " returns f = " + text + " at wi " + degrees(wi) + ", wo " + degrees(wo) +
                "; a measured material must be finite and non-negative");
  }
  return f;
}

struct Microfacets {
  std::vector<double> ndf, sigma;  // on the theta nodes u_k = k / (n - 1)
};

// Steps 1 and 2 of the header.
Microfacets retrieveMicrofacets(const Material& material, int n) {
  std::vector<double> retro(n);
  for (int k = 0; k < n; ++k) {
    const glm::vec3 w = clampToHemisphere(sphericalDirection(float(acquisitionTheta(double(k) / (n - 1))), 0.0f));
    retro[k] = double(measure(material, w, w).luminance()) * w.z;
  }
  const double retro_peak = *std::max_element(retro.begin(), retro.end());
  // A material that reflects nothing back (black, or a mirror away from the normal) gives the
  // iteration nothing to find; a uniform retro-reflection gives the NDF of a Lambertian surface,
  // and the RGB tables carry the material.
  if (!(retro_peak > 0)) std::fill(retro.begin(), retro.end(), 1.0);

  const std::vector<double> kernel = projectedAreaKernel(n);
  std::vector<double> d(n, 1.0);
  for (int it = 0; it < kMaxPowerIterations; ++it) {
    std::vector<double> next = applyKernel(kernel, d);
    for (int k = 0; k < n; ++k) next[k] *= retro[k];
    const double peak = *std::max_element(next.begin(), next.end());
    double change = 0;
    for (int k = 0; k < n; ++k) {
      next[k] /= peak;
      change = std::max(change, std::abs(next[k] - d[k]));
    }
    d = std::move(next);
    if (change < 1e-10) break;
  }
  const double peak = *std::max_element(d.begin(), d.end());
  for (double& v : d) v = std::max(v, kNdfFloor * peak);
  std::vector<double> sigma = applyKernel(kernel, d);
  const double norm = 1.0 / sigma[0];
  for (double& v : d) v *= norm;
  for (double& v : sigma) v *= norm;
  return {std::move(d), std::move(sigma)};
}

// Step 3: theta_i uniform in sigma between sigma(0) and sigma(pi/2); uniform in u_theta where
// sigma does not fall monotonically enough to place them (a projected area that barely changes).
std::vector<float> incidenceAngles(const std::vector<double>& sigma, int count) {
  const int n = int(sigma.size());
  std::vector<float> theta(count);
  const double lowest = sigma.back();
  bool placed = sigma[0] - lowest > 1e-3;
  for (int i = 0; placed && i < count; ++i) {
    const double x = 1.0 - double(i) / (count - 1) * (sigma[0] - lowest);
    double u = 0;
    if (i == count - 1) u = 1;
    else if (i > 0) {
      int k = 1;
      while (k < n - 1 && sigma[k] > x) ++k;
      const double a = sigma[k], b = sigma[k - 1];
      u = (k - (a == b ? 0.0 : (x - a) / (b - a))) / (n - 1);
    }
    theta[i] = float(acquisitionTheta(u));
    placed = i == 0 || theta[i] > theta[i - 1] + 1e-4f;
  }
  if (!placed)
    for (int i = 0; i < count; ++i) theta[i] = float(acquisitionTheta(double(i) / (count - 1)));
  return theta;
}

// A grid of the file: height rows of width values (per parameter slice, slices outermost).
struct Grid {
  int width = 0, height = 0;
  std::vector<float> values;
};

// What the tables are measured on: the incidence angles, the NDF and projected area, the VNDF.
struct Parameterization {
  std::vector<float> theta_i;
  Grid ndf, sigma, vndf;
};

// Steps 1 to 4 of the header.
Parameterization derive(const Material& material, const RglAcquisitionOptions& o) {
  const int n = o.ndf_resolution, nv = o.vndf_resolution;
  const Microfacets mf = retrieveMicrofacets(material, n);
  Parameterization pz;
  pz.theta_i = incidenceAngles(mf.sigma, o.theta_i_count);
  // Isotropic: two identical rows, at phi = -pi and pi.
  pz.ndf = {n, 2, std::vector<float>(2 * n)};
  pz.sigma = {n, 2, std::vector<float>(2 * n)};
  for (int k = 0; k < 2 * n; ++k) pz.ndf.values[k] = float(mf.ndf[k % n]), pz.sigma.values[k] = float(mf.sigma[k % n]);
  const BilinearWarp2D ndf(n, 2, pz.ndf.values, {}, BilinearWarp2D::Mode::Interpolant);
  const BilinearWarp2D sigma(n, 2, pz.sigma.values, {}, BilinearWarp2D::Mode::Interpolant);
  // Slice by slice: rows are u_phi (m's azimuth relative to wi's, which is 0 here), columns u_theta.
  const int nt = int(pz.theta_i.size());
  pz.vndf = {nv, nv, std::vector<float>(std::size_t(nt) * nv * nv)};
  for (int t = 0; t < nt; ++t) {
    const glm::vec3 wi = sphericalDirection(pz.theta_i[t], 0.0f);
    const float sigma_i = sigma.eval({acquisitionUnit(pz.theta_i[t]), 0.5f});
    for (int row = 0; row < nv; ++row)
      for (int col = 0; col < nv; ++col) {
        const float ux = float(col) / float(nv - 1), uy = float(row) / float(nv - 1);
        const float theta_m = float(acquisitionTheta(ux));
        const glm::vec3 m = sphericalDirection(theta_m, kTwoPi * uy - kPi);
        const double jacobian = 2 * kPiDouble * kPiDouble * ux * std::sin(theta_m);
        pz.vndf.values[(std::size_t(t) * nv + row) * nv + col] =
            float(jacobian * std::max(0.0f, glm::dot(wi, m)) * ndf.eval({ux, 0.0f}) / sigma_i);
      }
  }
  return pz;
}

// The RGB table of the file whose parameterization is reused, when it has the resolution written.
std::vector<float> storedRgb(const TensorFile* file, int nt, int r) {
  if (!file) return {};
  const TensorField* rgb = file->find("rgb");
  const std::vector<std::uint64_t> shape = {1, std::uint64_t(nt), 3, std::uint64_t(r), std::uint64_t(r)};
  if (!rgb || rgb->dtype != TensorDtype::Float32 || rgb->shape != shape) return {};
  return rgb->toFloats();
}

// An RGL file's own parameterization (RglAcquisitionOptions::parameterization), checked as the
// reader checks it.
Parameterization parameterizationOf(const TensorFile& file) {
  const TensorField& theta = file.require("theta_i", TensorDtype::Float32, {-1});
  const auto nt = std::int64_t(theta.shape[0]);
  const TensorField& ndf = file.require("ndf", TensorDtype::Float32, {-1, -1});
  const TensorField& sigma = file.require("sigma", TensorDtype::Float32, {-1, -1});
  const TensorField& vndf = file.require("vndf", TensorDtype::Float32, {1, nt, -1, -1});
  auto grid = [](const TensorField& f) {
    return Grid{int(f.shape[f.shape.size() - 1]), int(f.shape[f.shape.size() - 2]), f.toFloats()};
  };
  return {theta.toFloats(), grid(ndf), grid(sigma), grid(vndf)};
}

// The RGB values of the nodes whose reflection leaves the hemisphere, copied from the nearest
// valid node of their row (the same m azimuth; where none, they stay 0). The reader never
// evaluates there, but interpolates towards them from the valid nodes beside them, and a 0 there
// would darken every direction in between. Measuring at the horizon instead does not work: where
// the NDF is small there, the weight f cos / D is orders of magnitude above its neighbours'. The
// luminance keeps its 0 there, so that the sampling warp does not draw them.
void extendIntoInvalidNodes(const std::vector<bool>& measured, int r, std::span<double> rgb) {
  const std::size_t slice = std::size_t(r) * r;
  for (int row = 0; row < r; ++row)
    for (int col = 0; col < r; ++col) {
      if (measured[std::size_t(row) * r + col]) continue;
      for (int step = 1; step < r; ++step) {
        int from = -1;
        if (col - step >= 0 && measured[std::size_t(row) * r + col - step]) from = col - step;
        else if (col + step < r && measured[std::size_t(row) * r + col + step]) from = col + step;
        if (from < 0) continue;
        for (int c = 0; c < 3; ++c)
          rgb[c * slice + std::size_t(row) * r + col] = rgb[c * slice + std::size_t(row) * r + from];
        break;
      }
    }
}

// Step 6: the spectra of the RGB table ([theta_i][channel][node] -> [theta_i][wavelength][node]).
std::vector<double> upsampledSpectra(const std::vector<double>& rgb, int nt, std::size_t slice,
                                     const std::vector<float>& wavelengths) {
  const SpectrumToRgb projection(wavelengths);
  const std::size_t nw = wavelengths.size();
  std::vector<double> spectra(std::size_t(nt) * nw * slice);
  for (int t = 0; t < nt; ++t)
    for (std::size_t node = 0; node < slice; ++node) {
      const std::size_t base = std::size_t(t) * 3 * slice + node;
      const Rgb value{float(rgb[base]), float(rgb[base + slice]), float(rgb[base + 2 * slice])};
      const SigmoidSpectrum s = fitSigmoidSpectrum(value, projection, wavelengths);
      for (std::size_t w = 0; w < nw; ++w) spectra[(std::size_t(t) * nw + w) * slice + node] = s(wavelengths[w]);
    }
  return spectra;
}

void checkRange(const char* name, int value, int low, int high) {
  if (value < low || value > high)
    throw Error(std::string(name) + " must be in [" + std::to_string(low) + ", " + std::to_string(high) + "], not " +
                std::to_string(value));
}

}  // namespace

void checkRglAcquisitionOptions(const RglAcquisitionOptions& o) {
  checkRange("the number of incidence angles (theta_i)", o.theta_i_count, 2, 90);
  checkRange("the NDF resolution", o.ndf_resolution, 8, 1024);
  checkRange("the VNDF resolution", o.vndf_resolution, 8, 1024);
  checkRange("the luminance/RGB resolution", o.resolution, 4, 256);
}

std::vector<TensorField> acquireRglFields(const Material& material, const RglAcquisitionOptions& o) {
  checkRglAcquisitionOptions(o);
  if (material.isAnisotropic())
    throw Error(material.name() + " is anisotropic; an RGL file written here is isotropic (one phi_i) and would keep "
                "only one azimuth of it (average it over phi_h first: {\"type\": \"azimuthal-average\"})");
  const Parameterization pz = o.parameterization ? parameterizationOf(*o.parameterization) : derive(material, o);
  const std::vector<float>& theta_i = pz.theta_i;
  const int r = o.resolution, nt = int(theta_i.size());

  // The interpolants exactly as a reader builds them, so that the tables below are measured where
  // the reader will look them up.
  using Mode = BilinearWarp2D::Mode;
  const BilinearWarp2D ndf(pz.ndf.width, pz.ndf.height, pz.ndf.values, {}, Mode::Interpolant);
  const BilinearWarp2D sigma(pz.sigma.width, pz.sigma.height, pz.sigma.values, {}, Mode::Interpolant);
  const BilinearWarp2D vndf_warp(pz.vndf.width, pz.vndf.height, pz.vndf.values, {theta_i}, Mode::Distribution);
  const std::vector<float> stored_rgb = storedRgb(o.parameterization, nt, r);
  std::vector<float> sigma_i(nt);
  for (int t = 0; t < nt; ++t) sigma_i[t] = sigma.eval({acquisitionUnit(theta_i[t]), 0.5f});

  // Step 5 and the valid bits (step 6).
  const std::size_t slice = std::size_t(r) * r;
  std::vector<double> luminance(nt * slice), rgb(nt * 3 * slice);
  std::vector<double> valid_bytes((nt * slice + 7) / 8, 0.0);
  for (int t = 0; t < nt; ++t) {
    const glm::vec3 wo = sphericalDirection(theta_i[t], 0.0f);  // the fixed direction (libbtf's wo)
    const float params[1] = {theta_i[t]};
    const BilinearWarp2D::Fixed warp = vndf_warp.fixed(params);
    double mass = 0;
    std::vector<bool> measured(slice), at_pole(slice);
    for (int row = 0; row < r; ++row)
      for (int col = 0; col < r; ++col) {
        const std::size_t node = std::size_t(row) * r + col;
        const glm::vec2 u_m = warp.sample({float(col) / float(r - 1), float(row) / float(r - 1)}).p;
        const glm::vec3 m = sphericalDirection(float(acquisitionTheta(u_m.x)), kTwoPi * u_m.y - kPi);
        const float wo_dot_m = glm::dot(wo, m);
        const glm::vec3 wr = 2.0f * wo_dot_m * m - wo;
        // A reflection closer to the horizon than the measurable cos(theta) >= 1e-3 is not
        // measured either: there f cos / D is the clamped f over a vanishing D, millions where its
        // neighbours hold 1.
        const bool valid = wo_dot_m > 0 && wr.z >= kMinEvalCos;
        Rgb weight;
        if (valid) {
          const glm::vec3 wi_eval = clampToHemisphere(wr), wo_eval = clampToHemisphere(wo);
          const Rgb f_cos = measure(material, wi_eval, wo_eval) * wi_eval.z;
          weight = f_cos * (4.0f * sigma_i[t] / ndf.eval(u_m));
        } else {
          const std::size_t bit = t * slice + node;
          valid_bytes[bit / 8] += double(0x80 >> (bit % 8));
        }
        measured[node] = valid;
        at_pole[node] = u_m.x < 1e-3f;
        for (int c = 0; c < 3; ++c) rgb[(std::size_t(t) * 3 + c) * slice + node] = weight[c];
        luminance[t * slice + node] = weight.luminance();
        mass += weight.luminance();
      }
    const std::span<double> rgb_slice = std::span(rgb).subspan(std::size_t(t) * 3 * slice, 3 * slice);
    if (stored_rgb.empty()) {
      extendIntoInvalidNodes(measured, r, rgb_slice);
    } else {
      // Re-measuring an RGL file on its own nodes gives back its values, except where it holds
      // what no measurement returns: nodes without a measurement, negative (out-of-gamut) values
      // that readers clip only after interpolating, and the nodes at the pole of m, which all
      // stand for the mirror direction and hold what the gonioreflectometer measured at each
      // azimuth there (a reader evaluates the mirror direction at one of them). Those keep the
      // file's values.
      for (std::size_t k = 0; k < 3 * slice; ++k) {
        const float v = stored_rgb[std::size_t(t) * 3 * slice + k];
        if (!measured[k % slice] || at_pole[k % slice] || v < 0) rgb_slice[k] = v;
      }
    }
    // Nothing reflected at this angle: a uniform luminance warp keeps the file readable (a warp
    // needs mass), and the zero RGB table still says that nothing is reflected.
    if (!(mass > 0)) std::fill(luminance.begin() + t * slice, luminance.begin() + (t + 1) * slice, 1.0);
  }

  const std::string description = o.description.empty() ? "virtual acquisition of " + material.name() : o.description;
  const std::vector<double> version = {1, 0}, phi_i = {0}, jacobian = {1};
  const std::vector<double> theta_values(theta_i.begin(), theta_i.end());
  const auto u = [](int v) { return std::uint64_t(v); };
  const auto doubles = [](const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); };
  std::vector<TensorField> fields;
  fields.push_back(tensorField("version", TensorDtype::UInt32, {2}, version));
  fields.push_back(tensorTextField("description", description));
  fields.push_back(tensorField("phi_i", TensorDtype::Float32, {1}, phi_i));
  fields.push_back(tensorField("theta_i", TensorDtype::Float32, {u(nt)}, theta_values));
  fields.push_back(tensorField("sigma", TensorDtype::Float32, {u(pz.sigma.height), u(pz.sigma.width)}, doubles(pz.sigma.values)));
  fields.push_back(tensorField("ndf", TensorDtype::Float32, {u(pz.ndf.height), u(pz.ndf.width)}, doubles(pz.ndf.values)));
  fields.push_back(tensorField("vndf", TensorDtype::Float32, {1, u(nt), u(pz.vndf.height), u(pz.vndf.width)},
                               doubles(pz.vndf.values)));
  fields.push_back(tensorField("luminance", TensorDtype::Float32, {1, u(nt), u(r), u(r)}, luminance));
  fields.push_back(tensorField("rgb", TensorDtype::Float32, {1, u(nt), 3, u(r), u(r)}, rgb));
  if (o.spectral) {
    const std::vector<float> wavelengths = bsdfWavelengths();
    const auto nw = std::uint64_t(wavelengths.size());
    fields.push_back(tensorField("wavelengths", TensorDtype::Float32, {nw}, doubles(wavelengths)));
    fields.push_back(tensorField("spectra", TensorDtype::Float32, {1, u(nt), nw, u(r), u(r)},
                                 upsampledSpectra(rgb, nt, slice, wavelengths)));
  }
  fields.push_back(tensorField("jacobian", TensorDtype::UInt8, {1}, jacobian));
  fields.push_back(tensorField("valid", TensorDtype::UInt8, {valid_bytes.size()}, valid_bytes));
  return fields;
}

TensorFile inMemoryTensorFile(std::vector<TensorField> fields, const std::string& label) {
  TensorFile file;
  file.path = label;
  file.fields = std::move(fields);
  file.file_size = encodeTensorFile(file.fields).size();
  return file;
}

}  // namespace btf
