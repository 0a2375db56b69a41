#include "btf/fit/analytic_fit.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <optional>
#include <sstream>

#include "btf/core/error.h"
#include "btf/core/half_diff.h"
#include "btf/core/progress.h"
#include "btf/core/math.h"
#include "btf/material/abc.h"
#include "btf/material/albedo.h"
#include "btf/material/ggx.h"
#include "btf/material/ggx_two_lobes.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "fit_models.h"

namespace btf {
namespace {

using fit::FitSample;

// The sampling grid of the objective (analytic_fit.h): every theta_h cell, where highlights live
// (MERL's theta_h axis is already dense near the normal), and every 3rd theta_d and 6th phi_d
// cell, which vary slowly in every model fitted here.
constexpr int kThetaDiffStride = 3;
constexpr int kPhiDiffStride = 6;
constexpr double kRobustScale = 0.1;  // SoftLOneLoss scale, in units of the log residual
// The rel_rmse measures (and the linear objective, which minimizes them) count directions within
// 80 degrees of the normal, as the tabulation errors do (analytic_fit.h, tableRelRmse): tabulated
// RGL files hold outliers in a few cells at grazing angles, which would otherwise be the whole
// measure.
const float kCos80 = std::cos(80.0f * float(fit::kFitPi) / 180.0f);

FitSample makeSample(const glm::vec3& wi, const glm::vec3& wo, const Rgb& f) {
  FitSample s = fit::geometryOf(wi, wo);
  for (int c = 0; c < 3; ++c) {
    s.value[c] = s.cos_i * double(f[c]);
    s.target[c] = std::log1p(s.value[c]);
  }
  return s;
}

// The energy term (analytic_fit.h): at one view angle, the pairs of a half-vector quadrature of
// the directional albedo, with their weights (solid angle times cos(theta_i)), and the data's albedo
// by the same quadrature, so that the discretization is the same on both sides.
struct AlbedoQuadrature {
  float theta_o_deg = 0;
  std::vector<FitSample> pairs;
  std::vector<double> weights;
  double data[3] = {};
};

struct SampleSet {
  std::vector<FitSample> samples;
  std::size_t excluded = 0;
  Rgb diffuse_guess;  // pi times the mean f of samples far from the highlight: a start for kd
  std::vector<AlbedoQuadrature> albedo;  // tables only; empty: no energy term
};

// theta_h = pi/2 t^2 at kEnergyThetaSteps midpoints in t (dense near the normal, where highlights
// are), phi_h at kEnergyPhiSteps midpoints over [0, pi] (the models are symmetric about the plane
// of incidence, so the other half doubles the weight).
constexpr int kEnergyThetaSteps = 48;
constexpr int kEnergyPhiSteps = 24;

AlbedoQuadrature albedoQuadrature(const Material& data, float theta_o_deg) {
  AlbedoQuadrature q;
  q.theta_o_deg = theta_o_deg;
  const glm::vec3 wo = sphericalDirection(theta_o_deg * float(fit::kFitPi) / 180.0f, 0.0f);
  const double dt = 1.0 / kEnergyThetaSteps, dphi = fit::kFitPi / kEnergyPhiSteps;
  for (int i = 0; i < kEnergyThetaSteps; ++i) {
    const double t = (i + 0.5) * dt, theta_h = 0.5 * fit::kFitPi * t * t;
    for (int j = 0; j < kEnergyPhiSteps; ++j) {
      const glm::vec3 h = sphericalDirection(float(theta_h), float((j + 0.5) * dphi));
      const float wo_dot_h = glm::dot(wo, h);
      if (wo_dot_h <= 0.0f) continue;
      const glm::vec3 wi = 2.0f * wo_dot_h * h - wo;
      if (wi.z <= 1e-4f) continue;
      // d(omega_i) cos(theta_i) = 4 (wo.h) sin(theta_h) dtheta_h dphi_h cos(theta_i), dtheta_h = pi t dt.
      const double w = 2.0 * 4.0 * wo_dot_h * std::sin(theta_h) * fit::kFitPi * t * dt * dphi * wi.z;
      q.pairs.push_back(fit::geometryOf(wi, wo));
      q.weights.push_back(w);
      const Rgb f = data.eval(wi, wo);
      for (int c = 0; c < 3; ++c) q.data[c] += w * double(std::max(f[c], 0.0f));
    }
  }
  return q;
}

// Collects the samples of either kind of data, and the diffuse start from those whose half vector
// lies beyond 40 degrees from the normal.
class SampleSetBuilder {
 public:
  void add(const glm::vec3& wi, const glm::vec3& wo, const Rgb& f) {
    if (!(wi.z > 1e-4f) || !(wo.z > 1e-4f)) {
      ++set_.excluded;
      return;
    }
    set_.samples.push_back(makeSample(wi, wo, f));
    if (set_.samples.back().h_z2 < kFarCos2) {
      for (int c = 0; c < 3; ++c) far_sum_[c] += f[c];
      ++far_count_;
    }
  }
  void exclude() { ++set_.excluded; }
  SampleSet finish() {
    for (int c = 0; c < 3; ++c)
      set_.diffuse_guess[c] = far_count_ > 0 ? float(std::clamp(fit::kFitPi * far_sum_[c] / far_count_, 0.02, 0.95)) : 0.3f;
    return std::move(set_);
  }

 private:
  static constexpr double kFarCos2 = 0.584984;  // cos^2(0.7 rad)
  SampleSet set_;
  double far_sum_[3] = {}, far_count_ = 0;
};

SampleSet sampleTable(const MerlTable& table) {
  SampleSetBuilder builder;
  for (int i = 0; i < MerlTable::kThetaHalfRes; ++i)
    for (int j = 0; j < MerlTable::kThetaDiffRes; j += kThetaDiffStride)
      for (int k = 0; k < MerlTable::kPhiDiffRes; k += kPhiDiffStride) {
        const std::size_t cell = MerlTable::index(i, j, k);
        if (!table.isMeasured(cell)) {
          builder.exclude();
          continue;
        }
        const DirectionPair d = MerlTable::directionsOf(i, j, k);
        builder.add(d.wi, d.wo, table.reflectance(cell));
      }
  return builder.finish();
}

bool isUsable(const MeasuredReflectance& m) {
  for (int c = 0; c < 3; ++c)
    if (!(m.f[c] >= 0) || !std::isfinite(m.f[c])) return false;
  return std::isfinite(m.wi.x + m.wi.y + m.wi.z + m.wo.x + m.wo.y + m.wo.z);
}

SampleSet sampleMeasurements(std::span<const MeasuredReflectance> data) {
  SampleSetBuilder builder;
  for (const MeasuredReflectance& m : data) {
    if (isUsable(m)) builder.add(m.wi, m.wo, m.f);
    else builder.exclude();
  }
  return builder.finish();
}

// One sample's residuals per channel, for the log objective: ln(1 + cos_i f_model) - ln(1 + cos_i
// f_data).
template <int kChannels, class Eval>
struct LogResidual {
  const FitSample* sample;
  int channel;  // the data channel of a one-channel fit; ignored for kChannels == 3
  Eval eval;
  template <class T>
  bool operator()(const T* p, T* r) const {
    using std::log;
    T f[kChannels];
    eval(p, *sample, f);
    for (int c = 0; c < kChannels; ++c)
      r[c] = log(T(1) + T(sample->cos_i) * f[c]) - T(sample->target[kChannels == 3 ? c : channel]);
    return true;
  }
};

// The same for the linear objective: cos_i (f_model - f_data).
template <int kChannels, class Eval>
struct LinearResidual {
  const FitSample* sample;
  int channel;
  Eval eval;
  template <class T>
  bool operator()(const T* p, T* r) const {
    T f[kChannels];
    eval(p, *sample, f);
    for (int c = 0; c < kChannels; ++c) r[c] = T(sample->cos_i) * f[c] - T(sample->value[kChannels == 3 ? c : channel]);
    return true;
  }
};

// The energy term of one view angle: (albedo_model,c - albedo_data,c) / max(albedo_data,c, 0.01),
// times `scale` (analytic_fit.h).
template <int kChannels, class Eval>
struct EnergyResidual {
  const AlbedoQuadrature* quadrature;
  int channel;
  double scale;
  Eval eval;
  template <class T>
  bool operator()(const T* p, T* r) const {
    T sum[kChannels];
    for (int c = 0; c < kChannels; ++c) sum[c] = T(0);
    T f[kChannels];
    for (std::size_t k = 0; k < quadrature->pairs.size(); ++k) {
      eval(p, quadrature->pairs[k], f);
      for (int c = 0; c < kChannels; ++c) sum[c] += T(quadrature->weights[k]) * f[c];
    }
    for (int c = 0; c < kChannels; ++c) {
      const double data = quadrature->data[kChannels == 3 ? c : channel];
      r[c] = T(scale) * (sum[c] - T(data)) / T(std::max(data, kEnergyFloor));
    }
    return true;
  }
  static constexpr double kEnergyFloor = 0.01;
};

// Every sample's residual block, of the objective's functor.
template <template <int, class> class Residual, int kChannels, int kParameters, class Eval>
void addResiduals(ceres::Problem& problem, const std::vector<FitSample>& samples, int channel, Eval eval,
                  ceres::LossFunction* loss, double* p) {
  for (const FitSample& s : samples)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Residual<kChannels, Eval>, kChannels, kParameters>(
                                 new Residual<kChannels, Eval>{&s, channel, eval}),
                             loss, p);
}

// A parameter's range in the search. name: what a warning calls it ("" for a parameter whose
// ends are the model's own limits, e.g. an albedo, and not checked); log: the parameter is the
// logarithm of what is named; check_lower / check_upper: which ends are limits of the search only.
struct Bound {
  double lower, upper;
  const char* name = "";
  bool log = false, check_lower = true, check_upper = true;
};

// Each checked parameter of `p` that ended at a bound (within 1e-4 of its range), as
// "B 1e+08, its upper bound"; channel names are appended for RGB triples by the caller's names.
void recordBounds(AnalyticFitReport& report, const std::vector<double>& p, const std::vector<Bound>& bounds,
                  const std::string& prefix = "") {
  for (std::size_t i = 0; i < bounds.size() && i < p.size(); ++i) {
    const Bound& b = bounds[i];
    if (!*b.name) continue;
    const double slack = 1e-4 * (b.upper - b.lower);
    const bool lower = b.check_lower && p[i] <= b.lower + slack, upper = b.check_upper && p[i] >= b.upper - slack;
    if (!lower && !upper) continue;
    char text[160];
    std::snprintf(text, sizeof text, "%s%s %.4g, its %s bound", prefix.c_str(), b.name, b.log ? std::exp(p[i]) : p[i],
                  lower ? "lower" : "upper");
    report.at_bound.push_back(text);
  }
}

// The energy residuals' scale (analytic_fit.h): so that a relative albedo error e at every angle
// costs energy_weight^2 times what the sample residuals cost when each is off by e of its typical
// size (e in log space; for the linear objective, e times the RMS data value), whatever the number
// of samples: sqrt(samples x channels / energy residuals), times the typical size.
double energyScale(const std::vector<FitSample>& samples, std::size_t energy_residuals, double energy_weight,
                   FitObjective objective, int channel, int channels) {
  double typical = 1.0;
  if (objective == FitObjective::Linear) {
    double sum2 = 0;
    std::size_t n = 0;
    for (const FitSample& s : samples)
      for (int c = 0; c < channels; ++c, ++n) sum2 += s.value[channels == 3 ? c : channel] * s.value[channels == 3 ? c : channel];
    typical = n ? std::sqrt(sum2 / double(n)) : 1.0;
  }
  return energy_weight * typical * std::sqrt(double(samples.size() * std::size_t(channels)) / double(energy_residuals));
}

// One start of one problem: its initial parameters and bounds.
struct StartResult {
  std::vector<double> parameters;
  ceres::Solver::Summary summary;
};

template <int kChannels, int kParameters, class Eval>
StartResult solveStart(const std::vector<FitSample>& samples, const std::vector<AlbedoQuadrature>& albedo,
                       double energy_weight, int channel, Eval eval, std::vector<double> initial,
                       const std::vector<Bound>& bounds, int max_iterations, FitObjective objective) {
  StartResult result;
  result.parameters = std::move(initial);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::SoftLOneLoss robust(kRobustScale);
  double* p = result.parameters.data();
  if (objective == FitObjective::Linear)  // plain least squares, as the measure
    addResiduals<LinearResidual, kChannels, kParameters>(problem, samples, channel, eval, nullptr, p);
  else
    addResiduals<LogResidual, kChannels, kParameters>(problem, samples, channel, eval, &robust, p);
  if (energy_weight > 0 && !albedo.empty()) {
    const double scale = energyScale(samples, albedo.size() * kChannels, energy_weight, objective, channel, kChannels);
    for (const AlbedoQuadrature& q : albedo)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<EnergyResidual<kChannels, Eval>, kChannels, kParameters>(
                                   new EnergyResidual<kChannels, Eval>{&q, channel, scale, eval}),
                               nullptr, p);
  }
  for (int i = 0; i < kParameters; ++i) {
    problem.SetParameterLowerBound(p, i, bounds[std::size_t(i)].lower);
    problem.SetParameterUpperBound(p, i, bounds[std::size_t(i)].upper);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;  // the starts run in parallel instead
  options.logging_type = ceres::SILENT;
  ceres::Solve(options, &problem, &result.summary);
  return result;
}

// Two stages. Every start first runs a few iterations on a fifth of the samples (every 5th): which
// basin a start falls into shows early, at a fifth of the cost. The start with the lowest cost
// there then continues on all samples, to convergence or max_iterations. The screening runs in
// parallel, each start deterministic; ties go to the earlier start.
constexpr int kScreeningStride = 5;
constexpr int kScreeningIterations = 15;

template <int kChannels, int kParameters, class Eval>
StartResult bestOfStarts(const SampleSet& set, int channel, Eval eval, const std::vector<std::vector<double>>& starts,
                         const std::vector<Bound>& bounds, const AnalyticFitOptions& options, Progress& progress,
                         int& screening_converged) {
  std::vector<FitSample> screening;
  for (std::size_t i = 0; i < set.samples.size(); i += kScreeningStride) screening.push_back(set.samples[i]);
  std::vector<StartResult> results(starts.size());
  tbb::parallel_for(std::size_t(0), starts.size(), [&](std::size_t k) {
    results[k] = solveStart<kChannels, kParameters>(screening, set.albedo, options.energy_weight, channel, eval, starts[k],
                                                    bounds, std::min(options.max_iterations, kScreeningIterations),
                                                    options.objective);
    progress.advance();
  });
  std::size_t best = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    if (results[k].summary.termination_type == ceres::CONVERGENCE) ++screening_converged;
    if (results[k].summary.final_cost < results[best].summary.final_cost) best = k;
  }
  return solveStart<kChannels, kParameters>(set.samples, set.albedo, options.energy_weight, channel, eval,
                                            results[best].parameters, bounds, options.max_iterations, options.objective);
}

// Evenly spaced in log between lo and hi over the starts (the geometric mean for one start).
double logSpread(double lo, double hi, int k, int count) {
  const double t = count > 1 ? double(k) / double(count - 1) : 0.5;
  return std::log(lo) + t * (std::log(hi) - std::log(lo));
}

void recordStart(AnalyticFitReport& report, const StartResult& best, const std::string& label) {
  report.converged = report.converged && best.summary.termination_type == ceres::CONVERGENCE;
  report.iterations = std::max(report.iterations, int(best.summary.iterations.size()) - 1);
  report.cost += best.summary.final_cost;
  if (!report.ceres_report.empty()) report.ceres_report += '\n';
  report.ceres_report += label + best.summary.BriefReport();
}

// The bounds of kd[3], then per lobe f0 or ks[3] and ln(alpha): albedos in [0, 1], alpha in [1e-3, 2].
std::vector<Bound> microfacetBounds(int lobes) {
  std::vector<Bound> bounds(3, Bound{0.0, 1.0});
  for (int l = 0; l < lobes; ++l) {
    for (int c = 0; c < 3; ++c) bounds.push_back({0.0, 1.0});
    bounds.push_back({std::log(1e-3), std::log(2.0), l == 0 ? "alpha" : "alpha_2", true});
  }
  return bounds;
}

// GGX or Ward: kd[3], f0 or ks[3], ln(alpha).
template <class Eval>
void fitMicrofacet(const SampleSet& set, const AnalyticFitOptions& options, Eval eval, double specular_start,
                   AnalyticParameters& out, AnalyticFitReport& report) {
  std::vector<std::vector<double>> starts;
  for (int k = 0; k < options.starts; ++k) {
    const Rgb& kd = set.diffuse_guess;
    // Alternate weak (dielectric) and strong (metallic) specular starts across the roughnesses.
    const double ks = k % 2 == 0 ? specular_start : 0.5;
    starts.push_back({0.8 * kd.r, 0.8 * kd.g, 0.8 * kd.b, ks, ks, ks, logSpread(0.01, 0.6, k, options.starts)});
  }
  const std::vector<Bound> bounds = microfacetBounds(1);
  Progress progress("fit", std::uint64_t(options.starts));
  const StartResult best = bestOfStarts<3, 7>(set, 0, eval, starts, bounds, options, progress, report.screening_converged);
  recordStart(report, best, "");
  recordBounds(report, best.parameters, bounds);
  const std::vector<double>& p = best.parameters;
  out.diffuse = Rgb(float(p[0]), float(p[1]), float(p[2]));
  out.specular = Rgb(float(p[3]), float(p[4]), float(p[5]));
  out.alpha = float(std::exp(p[6]));
}

// Two GGX lobes: kd[3], f0[3], ln(alpha), f0_2[3], ln(alpha_2). The starts pair a broad lobe
// (alpha 0.15 to 0.6) with a narrow one (0.005 to 0.08), the second's strength alternating weak
// and strong as in fitMicrofacet; the bounds are ggx's for both lobes.
void fitGgxTwoLobes(const SampleSet& set, const AnalyticFitOptions& options, AnalyticParameters& out,
                    AnalyticFitReport& report) {
  auto eval = [](const auto* p, const FitSample& s, auto* f) { fit::evalGgx2(p, s, f); };
  std::vector<std::vector<double>> starts;
  for (int k = 0; k < options.starts; ++k) {
    const Rgb& kd = set.diffuse_guess;
    const double coat = k % 2 == 0 ? 0.04 : 0.5;
    starts.push_back({0.8 * kd.r, 0.8 * kd.g, 0.8 * kd.b, 0.05, 0.05, 0.05, logSpread(0.15, 0.6, k, options.starts), coat,
                      coat, coat, logSpread(0.005, 0.08, k, options.starts)});
  }
  const std::vector<Bound> bounds = microfacetBounds(2);
  Progress progress("fit", std::uint64_t(options.starts));
  const StartResult best = bestOfStarts<3, 11>(set, 0, eval, starts, bounds, options, progress, report.screening_converged);
  recordStart(report, best, "");
  recordBounds(report, best.parameters, bounds);
  const std::vector<double>& p = best.parameters;
  out.diffuse = Rgb(float(p[0]), float(p[1]), float(p[2]));
  out.specular = Rgb(float(p[3]), float(p[4]), float(p[5]));
  out.alpha = float(std::exp(p[6]));
  out.specular_2 = Rgb(float(p[7]), float(p[8]), float(p[9]));
  out.alpha_2 = float(std::exp(p[10]));
}

// ABC: kd[3], ln A[3], ln B, C, ior. The starts spread B (the peak's sharpness) over the range of
// the published fits, with A and C in their middle and the ior of glass.
void fitAbc(const SampleSet& set, const AnalyticFitOptions& options, AnalyticParameters& out, AnalyticFitReport& report) {
  auto eval = [](const auto* p, const FitSample& s, auto* f) { fit::evalAbc(p, s, f); };
  std::vector<std::vector<double>> starts;
  for (int k = 0; k < options.starts; ++k) {
    const Rgb& kd = set.diffuse_guess;
    const double log_a = std::log(k % 2 == 0 ? 10.0 : 300.0);
    starts.push_back({0.8 * kd.r, 0.8 * kd.g, 0.8 * kd.b, log_a, log_a, log_a, logSpread(50.0, 1e6, k, options.starts), 1.0, 1.5});
  }
  std::vector<Bound> bounds(3, Bound{0.0, 1.0});
  // A at its lower end is no lobe in that channel (a matte material's answer), not checked.
  for (const char* a : {"A (red)", "A (green)", "A (blue)"}) bounds.push_back({std::log(1e-6), std::log(1e6), a, true, false, true});
  bounds.push_back({std::log(1e-3), std::log(1e8), "B", true});
  bounds.push_back({0.01, 100.0, "C"});
  bounds.push_back({1.01, 10.0, "ior"});
  Progress progress("fit", std::uint64_t(options.starts));
  const StartResult best = bestOfStarts<3, 9>(set, 0, eval, starts, bounds, options, progress, report.screening_converged);
  recordStart(report, best, "");
  recordBounds(report, best.parameters, bounds);
  const std::vector<double>& p = best.parameters;
  out.diffuse = Rgb(float(p[0]), float(p[1]), float(p[2]));
  out.specular = Rgb(float(std::exp(p[3])), float(std::exp(p[4])), float(std::exp(p[5])));
  out.abc_b = std::exp(p[6]);
  out.abc_c = p[7];
  out.abc_ior = p[8];
}

// SGD: rho_d[3], ln rho_s[3], ln alpha, p, f0, f1, lambda, w (fit_models.h). The starts spread alpha
// over the published fits' range with p, f0 and the shadowing at their medians; rho_s alternates
// between a weak and a strong lobe (kap = 1 puts the published rho_s kap, tens, into rho_s).
void fitSgd(const SampleSet& set, const AnalyticFitOptions& options, AnalyticParameters& out, AnalyticFitReport& report) {
  auto eval = [](const auto* p, const FitSample& s, auto* f) { fit::evalSgd(p, s, f); };
  std::vector<std::vector<double>> starts;
  for (int k = 0; k < options.starts; ++k) {
    const Rgb& kd = set.diffuse_guess;
    const double log_rho_s = std::log(k % 2 == 0 ? 1.0 : 30.0);
    starts.push_back({0.8 * kd.r, 0.8 * kd.g, 0.8 * kd.b, log_rho_s, log_rho_s, log_rho_s,
                      logSpread(1e-3, 0.3, k, options.starts), 0.45, 0.07, 0.0, 3.0, 1.6});
  }
  std::vector<Bound> bounds(3, Bound{0.0, 1.0});
  for (const char* r : {"rho_s (red)", "rho_s (green)", "rho_s (blue)"})  // as ABC's A
    bounds.push_back({std::log(1e-8), std::log(1e5), r, true, false, true});
  bounds.push_back({std::log(1e-5), std::log(2.0), "alpha", true});
  bounds.push_back({0.0, 2.0, "p"});
  bounds.push_back({0.0, 10.0, "f0", false, false, true});    // f0 0: no Fresnel rise of its own
  bounds.push_back({-1.0, 10.0, "f1"});
  bounds.push_back({0.0, 100.0, "lambda", false, false, true});  // lambda 0: no shadowing
  bounds.push_back({0.5, 3.0, "w"});
  Progress progress("fit", std::uint64_t(options.starts));
  const StartResult best = bestOfStarts<3, 12>(set, 0, eval, starts, bounds, options, progress, report.screening_converged);
  recordStart(report, best, "");
  recordBounds(report, best.parameters, bounds);
  const std::vector<double>& p = best.parameters;
  out.diffuse = Rgb(float(p[0]), float(p[1]), float(p[2]));
  out.specular = Rgb(float(std::exp(p[3])), float(std::exp(p[4])), float(std::exp(p[5])));
  SgdChannel& shape = out.sgd_shape;
  shape.alpha = std::exp(p[6]);
  shape.p = p[7];
  shape.f0 = p[8];
  shape.f1 = p[9];
  shape.kap = 1.0;
  shape.lambda = p[10];
  shape.k = fit::kSgdFitK;
  shape.c = std::pow(p[11], -fit::kSgdFitK);
  shape.theta0 = 0.0;
}

template <int kChannels, int kLobes>
std::vector<double> lafortuneStart(const SampleSet& set, int channel, int k, int starts) {
  std::vector<double> p;
  for (int c = 0; c < kChannels; ++c) p.push_back(0.8 * set.diffuse_guess[kChannels == 3 ? c : channel]);
  // The sharpest lobe's exponent spreads over the starts; further lobes are 8x and 64x wider.
  // Their directions start forward (Phong-like, c = (-1, -1, 1): beta = 3 pi / 4), the extra
  // lobes tilted towards grazing and towards the normal.
  const double log_n = logSpread(5.0, 5000.0, k, starts);
  constexpr std::array<double, 3> kBetaOffset = {0.0, 0.3, -0.3};
  for (int l = 0; l < kLobes; ++l) {
    p.push_back(0.75 * fit::kFitPi + kBetaOffset[std::size_t(l)]);
    p.push_back(std::max(0.0, log_n - l * std::log(8.0)));
    for (int c = 0; c < kChannels; ++c) p.push_back(0.1);
  }
  return p;
}

template <int kChannels, int kLobes>
std::vector<Bound> lafortuneBounds() {
  std::vector<Bound> bounds(kChannels, Bound{0.0, 1.0});
  for (int l = 0; l < kLobes; ++l) {
    bounds.push_back({-fit::kFitPi, fit::kFitPi});  // an angle: its ends are one direction
    bounds.push_back({0.0, std::log(1e5), "n", true});
    for (int c = 0; c < kChannels; ++c) bounds.push_back({0.0, 1.0});
  }
  return bounds;
}

template <int kLobes>
void fitLafortune(const SampleSet& set, const AnalyticFitOptions& options, AnalyticParameters& out,
                  AnalyticFitReport& report) {
  out.lobes.clear();
  if (!options.per_channel) {
    constexpr int kParameters = fit::lafortuneParameterCount<3>(kLobes);
    auto eval = [](const auto* p, const FitSample& s, auto* f) { fit::evalLafortune<3, kLobes>(p, s, f); };
    std::vector<std::vector<double>> starts;
    for (int k = 0; k < options.starts; ++k) starts.push_back(lafortuneStart<3, kLobes>(set, 0, k, options.starts));
    Progress progress("fit", std::uint64_t(options.starts));
    const StartResult best = bestOfStarts<3, kParameters>(set, 0, eval, starts, lafortuneBounds<3, kLobes>(),
                                                          options, progress, report.screening_converged);
    recordStart(report, best, "");
    recordBounds(report, best.parameters, lafortuneBounds<3, kLobes>());
    const std::vector<double>& p = best.parameters;
    out.diffuse = Rgb(float(p[0]), float(p[1]), float(p[2]));
    for (int l = 0; l < kLobes; ++l) {
      const double* lobe = p.data() + 3 + l * 5;
      const float cxy = float(std::cos(lobe[0])), cz = float(std::sin(lobe[0]));
      out.lobes.push_back({Rgb(float(lobe[2]), float(lobe[3]), float(lobe[4])), glm::vec3(cxy, cxy, cz), float(std::exp(lobe[1]))});
    }
    return;
  }
  // Per channel: three independent one-channel fits; channel c's lobes carry weight in c only.
  constexpr int kParameters = fit::lafortuneParameterCount<1>(kLobes);
  auto eval = [](const auto* p, const FitSample& s, auto* f) { fit::evalLafortune<1, kLobes>(p, s, f); };
  Progress progress("fit", std::uint64_t(3 * options.starts));
  for (int channel = 0; channel < 3; ++channel) {
    std::vector<std::vector<double>> starts;
    for (int k = 0; k < options.starts; ++k) starts.push_back(lafortuneStart<1, kLobes>(set, channel, k, options.starts));
    const StartResult best = bestOfStarts<1, kParameters>(set, channel, eval, starts, lafortuneBounds<1, kLobes>(),
                                                          options, progress, report.screening_converged);
    recordStart(report, best, std::string("RGB").substr(std::size_t(channel), 1) + ": ");
    recordBounds(report, best.parameters, lafortuneBounds<1, kLobes>(), std::string("RGB").substr(std::size_t(channel), 1) + " ");
    const std::vector<double>& p = best.parameters;
    out.diffuse[channel] = float(p[0]);
    for (int l = 0; l < kLobes; ++l) {
      const double* lobe = p.data() + 1 + l * 3;
      const float cxy = float(std::cos(lobe[0])), cz = float(std::sin(lobe[0]));
      Rgb rho;
      rho[channel] = float(lobe[2]);
      out.lobes.push_back({rho, glm::vec3(cxy, cxy, cz), float(std::exp(lobe[1]))});
    }
  }
}

}  // namespace

bool isDegenerateFit(const AnalyticFitReport& report) {
  return !report.at_bound.empty() || !(report.rel_rmse <= kFitRelRmseLimit);
}

double worstAlbedoError(const AnalyticFitReport& report) {
  double worst = 0;
  for (const AlbedoCheck& a : report.albedo) worst = std::max(worst, a.rel_error);
  return worst;
}

AlbedoCheck albedoCheck(float theta_o_deg, const Rgb& data, const Rgb& fit) {
  AlbedoCheck a{theta_o_deg, data, fit, 0.0};
  const double d = (double(data.r) + data.g + data.b) / 3.0, f = (double(fit.r) + fit.g + fit.b) / 3.0;
  a.rel_error = d > 1e-6 ? std::abs(f - d) / d : (f > 1e-6 ? INFINITY : 0.0);
  return a;
}

std::vector<std::string> fitWarnings(const AnalyticFitReport& r) {
  std::vector<std::string> w;
  char text[200];
  if (!r.converged) w.push_back("the final solve did not converge within its iterations");
  if (!(r.rel_rmse <= kFitRelRmseLimit)) {
    std::snprintf(text, sizeof text, "rel_rmse %.3g is above %g: the fit explains less than half of the data's f cos", r.rel_rmse,
                  kFitRelRmseLimit);
    w.push_back(text);
  }
  for (const std::string& b : r.at_bound) w.push_back("degenerate fit: " + b + " (the solver stopped at the model's range)");
  for (const AlbedoCheck& a : r.albedo)
    if (!(a.rel_error <= kFitAlbedoTolerance)) {
      std::snprintf(text, sizeof text, "albedo at theta_o %g deg is %.4f, the data's %.4f (%+.0f%%; more than %.0f%% off)",
                    double(a.theta_o_deg), (a.fit.r + a.fit.g + a.fit.b) / 3.0, (a.data.r + a.data.g + a.data.b) / 3.0,
                    100.0 * ((a.fit.r + a.fit.g + a.fit.b) / std::max(1e-9, double(a.data.r + a.data.g + a.data.b)) - 1.0),
                    100.0 * kFitAlbedoTolerance);
      w.push_back(text);
    }
  return w;
}

const char* fitObjectiveName(FitObjective objective) { return objective == FitObjective::Linear ? "linear" : "log"; }

FitObjective parseFitObjective(std::string_view text) {
  for (FitObjective o : {FitObjective::Log, FitObjective::Linear})
    if (text == fitObjectiveName(o)) return o;
  throw Error("unknown fit objective '" + std::string(text) + "' (expected log or linear)");
}

std::unique_ptr<Material> makeAnalyticMaterial(const AnalyticParameters& p) {
  switch (p.family) {
    case ModelFamily::Ggx: return std::make_unique<Ggx>(p.diffuse, p.specular, p.alpha, p.alpha);
    case ModelFamily::Ggx2: return std::make_unique<GgxTwoLobes>(p.diffuse, p.specular, p.alpha, p.specular_2, p.alpha_2);
    case ModelFamily::Abc: return std::make_unique<Abc>(AbcParameters{p.diffuse, p.specular, p.abc_b, p.abc_c, p.abc_ior});
    case ModelFamily::Sgd: {
      SgdParameters sgd;
      for (int c = 0; c < 3; ++c) {
        sgd.channel[std::size_t(c)] = p.sgd_shape;
        sgd.channel[std::size_t(c)].rho_d = p.diffuse[c];
        sgd.channel[std::size_t(c)].rho_s = p.specular[c];
      }
      return std::make_unique<Sgd>(sgd);
    }
    case ModelFamily::Ward: return std::make_unique<Ward>(p.diffuse, p.specular, p.alpha, p.alpha);
    case ModelFamily::Lafortune: return std::make_unique<Lafortune>(p.diffuse, p.lobes);
    default: break;
  }
  throw Error(std::string("no analytic parameters for the model ") + modelFamilyName(p.family));
}

namespace {

void checkOptions(const AnalyticFitOptions& options) {
  (void)parseModelFamily(modelFamilyName(options.family), kFittableFamilies);  // names the fittable ones
  if (options.lobes < 1 || options.lobes > kMaxFitLobes)
    throw Error("fit: lobes must be 1 to " + std::to_string(kMaxFitLobes) + ", got " + std::to_string(options.lobes));
  if (options.starts < 1) throw Error("fit: starts must be >= 1, got " + std::to_string(options.starts));
  if (options.max_iterations < 1) throw Error("fit: max_iterations must be >= 1");
  if (options.family != ModelFamily::Lafortune && (options.lobes != 1 || options.per_channel))
    throw Error(std::string("fit: lobes and per-channel fits are for lafortune only, not ") + modelFamilyName(options.family));
}

// The fit of a sample set; rel_rmse and seconds are the caller's.
AnalyticFit fitSamples(const SampleSet& all, const AnalyticFitOptions& options) {
  // The linear objective is the measure's own least squares, over the measure's samples.
  SampleSet within;
  if (options.objective == FitObjective::Linear) {
    within.diffuse_guess = all.diffuse_guess;
    within.excluded = all.excluded;
    within.albedo = all.albedo;
    for (const FitSample& s : all.samples)
      if (s.cos_i >= double(kCos80) && s.cos_o >= double(kCos80)) within.samples.push_back(s);
    if (within.samples.size() < kMinimumFitSamples)
      throw Error("fit: " + std::to_string(within.samples.size()) + " samples within 80 degrees of the normal, too few for " +
                  "the linear objective (it needs " + std::to_string(kMinimumFitSamples) + ")");
  }
  const SampleSet& set = options.objective == FitObjective::Linear ? within : all;
  AnalyticFit fit;
  AnalyticFitReport& report = fit.report;
  report.converged = true;
  report.samples = set.samples.size();
  report.excluded = set.excluded;
  report.starts = options.starts * (options.per_channel ? 3 : 1);
  fit.parameters.family = options.family;
  switch (options.family) {
    case ModelFamily::Ggx:
      fitMicrofacet(set, options, [](const auto* p, const FitSample& s, auto* f) { fit::evalGgx(p, s, f); }, 0.04,
                    fit.parameters, report);
      break;
    case ModelFamily::Ward:
      fitMicrofacet(set, options, [](const auto* p, const FitSample& s, auto* f) { fit::evalWard(p, s, f); }, 0.05,
                    fit.parameters, report);
      break;
    case ModelFamily::Ggx2: fitGgxTwoLobes(set, options, fit.parameters, report); break;
    case ModelFamily::Abc: fitAbc(set, options, fit.parameters, report); break;
    case ModelFamily::Sgd: fitSgd(set, options, fit.parameters, report); break;
    case ModelFamily::Lafortune:
      if (options.lobes == 1) fitLafortune<1>(set, options, fit.parameters, report);
      else if (options.lobes == 2) fitLafortune<2>(set, options, fit.parameters, report);
      else fitLafortune<3>(set, options, fit.parameters, report);
      break;
    default: break;  // refused by checkOptions
  }
  fit.material = makeAnalyticMaterial(fit.parameters);
  return fit;
}

// A fit needs something to fit: data that is 0 everywhere has no lobe and no energy, and every
// model would "fit" it exactly with its reflectances at 0.
void requireReflection(const SampleSet& set) {
  for (const FitSample& s : set.samples)
    if (s.value[0] > 0 || s.value[1] > 0 || s.value[2] > 0) return;
  throw Error("fit: the data reflects nothing (every usable value is 0); there is no lobe to fit");
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

namespace {

// fitAnalytic of a table for options.family alone (no fallback).
AnalyticFit fitTableFamily(const MerlTable& table, const AnalyticFitOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  SampleSet set = sampleTable(table);
  if (set.samples.size() < 100)
    throw Error("fit: the table has only " + std::to_string(set.samples.size()) +
                " measured cells above the horizon on the fitting grid (100 or more needed)");
  requireReflection(set);
  const TabulatedBrdf data(std::make_shared<const MerlTable>(table), TableLookup::Interpolated);
  if (options.energy_weight > 0)
    for (const float deg : kEnergyAnglesDeg) set.albedo.push_back(albedoQuadrature(data, deg));
  std::vector<Rgb> data_albedo;
  for (const float deg : kAlbedoCheckAnglesDeg) data_albedo.push_back(integrateAlbedoHalfVector(data, deg * float(fit::kFitPi) / 180.0f));
  auto measured = [&](AnalyticFitOptions o) {
    AnalyticFit f = fitSamples(set, o);
    f.report.energy_weight = o.energy_weight;
    f.report.rel_rmse = tableRelRmse(*f.material, table);
    for (std::size_t a = 0; a < kAlbedoCheckAnglesDeg.size(); ++a) {
      const float deg = kAlbedoCheckAnglesDeg[a];
      f.report.albedo.push_back(albedoCheck(deg, data_albedo[a], integrateAlbedoHalfVector(*f.material, deg * float(fit::kFitPi) / 180.0f)));
    }
    return f;
  };
  AnalyticFit fit = measured(options);
  // The energy term is a penalty; where the fit still misses the albedo tolerance, the penalty is
  // raised and the fit repeated from all its starts (the penalty method), and a repeat is kept
  // only when its albedo is closer. The first fit is the whole cost wherever the albedo holds.
  // (Continuing from the previous solution instead stays in its basin and mostly misses again.)
  AnalyticFitOptions raised = options;
  for (int k = 0; k < kEnergyRaises && options.energy_weight > 0 && worstAlbedoError(fit.report) > kFitAlbedoTolerance; ++k) {
    raised.energy_weight *= kEnergyRaiseFactor;
    AnalyticFit next = measured(raised);
    if (worstAlbedoError(next.report) < worstAlbedoError(fit.report)) fit = std::move(next);
  }
  fit.report.warnings = fitWarnings(fit.report);
  fit.report.seconds = secondsSince(start_time);
  return fit;
}

std::string degeneracyText(const AnalyticFitReport& r) {
  std::string text;
  for (const std::string& b : r.at_bound) text += (text.empty() ? "" : "; ") + b;
  if (!(r.rel_rmse <= kFitRelRmseLimit)) {
    char figure[80];
    std::snprintf(figure, sizeof figure, "rel_rmse %.4g above %g", r.rel_rmse, kFitRelRmseLimit);
    text += (text.empty() ? "" : "; ") + std::string(figure);
  }
  return text;
}

}  // namespace

AnalyticFit fitAnalytic(const MerlTable& table, const AnalyticFitOptions& options) {
  checkOptions(options);
  AnalyticFit fit = fitTableFamily(table, options);
  // The fallback is the default fit's, of ABC fits only: a fit of another family asked for is that family's.
  if (!options.fallback || options.family != ModelFamily::Abc || *options.fallback == options.family ||
      !isDegenerateFit(fit.report))
    return fit;
  AnalyticFitOptions other = options;
  other.family = *options.fallback;
  other.lobes = 1;
  other.per_channel = false;
  AnalyticFit second = fitTableFamily(table, other);
  const bool keep_second = second.report.rel_rmse < fit.report.rel_rmse;
  char figures[160];
  std::snprintf(figures, sizeof figures, "rel_rmse %.4g against %.4g", keep_second ? second.report.rel_rmse : fit.report.rel_rmse,
                keep_second ? fit.report.rel_rmse : second.report.rel_rmse);
  const std::string line = std::string(modelFamilyName(options.family)) + "'s fit was degenerate (" + degeneracyText(fit.report) +
                           "); " + modelFamilyName(other.family) + " fitted too, " + (keep_second ? "and kept: " : "and not kept: ") +
                           figures;
  const double seconds = fit.report.seconds + second.report.seconds;
  if (keep_second) fit = std::move(second);
  fit.report.fallback = line;
  fit.report.seconds = seconds;
  return fit;
}

AutoFit fitSmallestModel(const MerlTable& table, std::span<const AnalyticFitOptions> candidates, double tolerance) {
  if (candidates.empty()) throw Error("fit --model auto: the candidate list is empty");
  if (!(tolerance >= 0)) throw Error("fit --model auto: the tolerance must be >= 0");
  AutoFit result;
  for (const AnalyticFitOptions& c : candidates) result.tried.push_back(fitAnalytic(table, c));
  double best = INFINITY;
  for (const AnalyticFit& f : result.tried) best = std::min(best, f.report.rel_rmse);
  auto keepsAlbedo = [](const AnalyticFit& f) { return worstAlbedoError(f.report) <= kFitAlbedoTolerance; };
  const double limit = best * (1.0 + tolerance);
  std::optional<std::size_t> within;  // the first within the rel_rmse tolerance, whatever its albedo
  for (std::size_t k = 0; k < result.tried.size(); ++k) {
    const AnalyticFit& f = result.tried[k];
    if (!(f.report.rel_rmse <= limit)) continue;
    if (!within) within = k;
    if (keepsAlbedo(f)) {
      result.chosen_index = k;
      char text[200];
      std::snprintf(text, sizeof text,
                    "the smallest candidate within %.0f%% of the best rel_rmse (%.4g) whose albedo is within %.0f%% of the data's",
                    100.0 * tolerance, best, 100.0 * kFitAlbedoTolerance);
      result.reason = text;
      result.chosen = f;
      return result;
    }
  }
  result.chosen_index = *within;  // the best candidate itself is always within
  result.chosen = result.tried[*within];
  result.reason = "no candidate keeps the albedo within " + std::to_string(int(100 * kFitAlbedoTolerance)) +
                  "%: the smallest within the rel_rmse tolerance";
  return result;
}

AnalyticFit fitAnalytic(std::span<const MeasuredReflectance> data, const AnalyticFitOptions& options) {
  checkOptions(options);
  const auto start_time = std::chrono::steady_clock::now();
  const SampleSet set = sampleMeasurements(data);
  if (set.samples.size() < kMinimumFitSamples)
    throw Error("fit: only " + std::to_string(set.samples.size()) + " of " + std::to_string(data.size()) +
                " measurements are usable (finite, non-negative, both directions above the horizon); " +
                std::to_string(kMinimumFitSamples) + " or more needed");
  requireReflection(set);
  AnalyticFit fit = fitSamples(set, options);
  fit.report.rel_rmse = measuredRelRmse(*fit.material, data);
  fit.report.warnings = fitWarnings(fit.report);
  fit.report.seconds = secondsSince(start_time);
  return fit;
}

namespace {

// rel_rmse of f cos over the measured cells within 80 degrees of the normal, with `valueAt(i, j, k,
// directions)` giving the compared value of each cell.
template <class ValueAt>
double relRmseOverCells(const MerlTable& table, const ValueAt& valueAt) {
  // Sums per theta_h row in parallel, added in row order: the same result for any thread count.
  std::vector<std::array<double, 2>> rows(MerlTable::kThetaHalfRes, {0.0, 0.0});
  tbb::parallel_for(0, MerlTable::kThetaHalfRes, [&](int i) {
    double error = 0, reference = 0;
    for (int j = 0; j < MerlTable::kThetaDiffRes; ++j)
      for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) {
        const std::size_t cell = MerlTable::index(i, j, k);
        if (!table.isMeasured(cell)) continue;
        const DirectionPair d = MerlTable::directionsOf(i, j, k);
        if (!(d.wi.z >= kCos80) || !(d.wo.z >= kCos80)) continue;
        const Rgb data = table.reflectance(cell);
        const Rgb f = valueAt(i, j, k, d);
        for (int c = 0; c < 3; ++c) {
          const double e = double(d.wi.z) * (double(f[c]) - double(data[c]));
          const double r = double(d.wi.z) * double(data[c]);
          error += e * e;
          reference += r * r;
        }
      }
    rows[std::size_t(i)] = {error, reference};
  });
  double error = 0, reference = 0;
  for (const auto& row : rows) {
    error += row[0];
    reference += row[1];
  }
  return reference > 0 ? std::sqrt(error / reference) : 0.0;
}

}  // namespace

double tableRelRmse(const Material& model, const MerlTable& table) {
  return relRmseOverCells(table, [&](int, int, int, const DirectionPair& d) { return model.eval(d.wi, d.wo); });
}

double measuredRelRmse(const Material& model, std::span<const MeasuredReflectance> data) {
  double error = 0, reference = 0;
  for (const MeasuredReflectance& m : data) {
    if (!isUsable(m) || !(m.wi.z >= kCos80) || !(m.wo.z >= kCos80)) continue;
    const Rgb f = model.eval(m.wi, m.wo);
    for (int c = 0; c < 3; ++c) {
      const double e = double(m.wi.z) * (double(f[c]) - double(m.f[c]));
      const double r = double(m.wi.z) * double(m.f[c]);
      error += e * e;
      reference += r * r;
    }
  }
  return reference > 0 ? std::sqrt(error / reference) : 0.0;
}

double tableRelRmse(const MerlTable& stored, const MerlTable& table) {
  return relRmseOverCells(table, [&](int i, int j, int k, const DirectionPair&) {
    return stored.reflectance(MerlTable::index(i, j, k));
  });
}

}  // namespace btf
