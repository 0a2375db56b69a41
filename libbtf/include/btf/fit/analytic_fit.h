// Fitting an analytic model to a tabulated isotropic BRDF (a MERL-layout table: a MERL file, or any
// material tabulated into one) or to scattered measurements (a BTF texel's direction pairs) with
// Ceres' Levenberg–Marquardt, from several starts: each start is screened by 15 iterations on
// every 5th sample, and the best one continues on all samples.
//
// The objective. Samples of a table are its cells: every theta_h cell, every 3rd theta_d and every
// 6th phi_d cell (81,000 cells before the exclusions), at the cell's angles as the table stores
// them; scattered data gives one sample per measurement. A sample is left out when it is
// unmeasured (negative in any channel) or when either direction lies below the horizon. Each
// sample s gives one residual per channel c,
//   r_sc = ln(1 + cos(theta_i) f_model,c) - ln(1 + cos(theta_i) f_data,c),
// the log-compressed, cosine-weighted difference of Löw et al. 2012: a highlight of 1000/sr and a
// diffuse 0.1/sr both count, and grazing light (where measurements are least reliable) counts
// less. The three residuals of a sample form one block under Ceres' SoftLOneLoss with scale 0.1
// (rho(s) = 2 a^2 (sqrt(1 + s / a^2) - 1), a = 0.1): a sample off by more than about 10% in log
// space counts linearly, not squared, so a few corrupt cells cannot pull the whole fit.
// The linear objective instead minimizes the measure the fit is judged by (tableRelRmse): plain
// least squares of r_sc = cos(theta_i) (f_model,c - f_data,c) over the samples within 80 degrees
// of the normal. It follows a narrow, tall highlight that the log objective, being robust, treats
// as a few outlying cells, and in turn cares little for the diffuse part and the tails.
//
// The models and their parameters (isotropic, like the tables):
//   ggx        diffuse kd (RGB), f0 (RGB), alpha            material/ggx.h
//   ggx2       ggx's, plus a second GGX lobe f0_2 (RGB), alpha_2 (no diffuse term of its own)
//                                                           material/ggx_two_lobes.h
//   abc        kd (RGB), A (RGB), B, C, ior (Löw et al. 2012, the published MERL fits' form)
//                                                           material/abc.h
//   sgd        rho_d (RGB), rho_s (RGB), and one lobe shape for all channels: alpha, p, f0, f1, and
//              the shadowing's lambda and width w (Bagher et al. 2012 with c = w^-k, k = 25,
//              theta0 = 0, kap = 1: src/fit/fit_models.h says why)    material/sgd.h
//   ward       diffuse kd (RGB), specular ks (RGB), alpha   material/ward.h
//   lafortune  diffuse kd (RGB), per lobe rho (RGB), c = (cxy, cxy, cz), exponent n
//              (1 to 3 lobes; shared lobe shapes with RGB weights, or each channel its own)
// Bounds: albedos in [0, 1]; alpha in [1e-3, 2]; ABC's A in [1e-6, 1e6], B in [1e-3, 1e8], C in
// [0.01, 100], ior in [1.01, 10] (the published fits' ranges, widened); SGD's rho_s in [1e-8, 1e5],
// alpha in [1e-5, 2], p in [0, 2], f0 in [0, 10], f1 in [-1, 10], lambda in [0, 100], w in [0.5, 3]
// radians (the published fits' ranges); n in [1, 1e5]; c on the unit circle of (cxy, cz) (only its
// direction matters in this normalization of the model).
//
// The energy term (tables only). Neither objective sees the material's energy: the log objective
// compresses the highlight, so a fit may trade a dim, wide lobe for a bright, narrow one of far
// more energy than the data's, and the linear one may put all the energy in a diffuse term.
// So each fit also minimizes, at the view angles kEnergyAnglesDeg, the relative difference of the
// model's directional albedo from the data's, per channel,
//   e_ac = s (A_model,c(theta_a) - A_data,c(theta_a)) / max(A_data,c(theta_a), 0.01),
// both albedos by the same half-vector quadrature (48 x 24 pairs per angle, dense near the mirror
// direction) of the data's interpolated lookup and of the model, so that the discretization cancels.
// A penalty rather than a constraint: a model that cannot match both the shape and the energy
// settles between them, and the report says how far each is off. s = energy_weight times
// sqrt(samples x channels / energy residuals) times the residuals' typical size (1 in log space;
// the RMS data value for the linear objective): a relative albedo error e at every angle then costs
// what every sample off by e (in those units) does, whatever the number of samples. Scattered data (a BTF texel) has no
// albedo quadrature and takes no energy term.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "btf/core/rgb.h"
#include "btf/io/merl.h"
#include "btf/material/lafortune.h"
#include "btf/material/material.h"
#include "btf/material/model_family.h"
#include "btf/material/sgd.h"

namespace btf {

// The families the fitter knows (btf/material/model_family.h names them).
inline constexpr std::array<ModelFamily, 6> kFittableFamilies = {ModelFamily::Lafortune, ModelFamily::Ggx, ModelFamily::Ward,
                                                                 ModelFamily::Ggx2, ModelFamily::Abc, ModelFamily::Sgd};
// The residuals minimized (see above): log-compressed and robust, or linear (the measure itself).
enum class FitObjective { Log, Linear };

// "log", "linear", and the inverse (throws btf::Error naming the choices).
const char* fitObjectiveName(FitObjective objective);
FitObjective parseFitObjective(std::string_view text);

// The most Lafortune lobes a fit has: kMaxFitLobes shared shapes, or as many per channel. A fit
// file holds at most kMaxFitLobes x 3 lobes, as the fitter writes them.
inline constexpr int kMaxFitLobes = 3;

// The defaults are the default fit of `btf fit`: ABC under the linear objective with the energy
// term. On tables of measured materials the measure is dominated by the tall highlight and its
// grazing Fresnel rise, which ABC's long-tailed shape and ior follow and the log objective treats
// as outliers (docs/fit.md shows the comparison).
struct AnalyticFitOptions {
  ModelFamily family = ModelFamily::Abc;
  int lobes = 1;             // Lafortune: 1 to 3
  bool per_channel = false;  // Lafortune: each channel its own lobe shapes (3 x lobes lobes in all)
  int starts = 6;            // initial guesses, spread over the shape parameters (>= 1)
  int max_iterations = 100;  // per start
  FitObjective objective = FitObjective::Linear;
  double energy_weight = 1.0;  // the energy term's weight (above); 0 leaves it out
  // Tables, ABC fits (the default family; other families ignore it): where the fit is degenerate
  // (isDegenerateFit: a parameter at a bound, or rel_rmse above kFitRelRmseLimit, as ABC's on
  // mirror-like tables, whose lobe it gives up to keep the energy), this family is fitted too and the fit with the lower rel_rmse kept
  // (AnalyticFitReport::fallback says so). SGD: its lobe follows near-mirror peaks that ABC's
  // cannot, at about 3x ABC's time, paid only where ABC degenerates. nullopt: ABC alone, as
  // `btf fit --model abc` asks.
  std::optional<ModelFamily> fallback = ModelFamily::Sgd;
};

// The view angles of the energy term, and those the report checks the albedo at.
inline constexpr std::array<float, 6> kEnergyAnglesDeg = {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f};
inline constexpr std::array<float, 3> kAlbedoCheckAnglesDeg = {0.0f, 30.0f, 60.0f};
// A fit is reported with a warning when its albedo (mean of RGB) misses the data's by more than
// this fraction at any of kAlbedoCheckAnglesDeg, when its rel_rmse exceeds kFitRelRmseLimit (it
// explains less than half of the data's f cos), or when a shape parameter ends at a bound of the
// search (a degenerate fit: the solver wanted to go further than the model allows).
inline constexpr double kFitAlbedoTolerance = 0.10;
inline constexpr double kFitRelRmseLimit = 0.5;

// The directional albedo of the fit against the data's at one view angle.
struct AlbedoCheck {
  float theta_o_deg = 0;
  Rgb data, fit;
  double rel_error = 0;  // |mean(fit) - mean(data)| / mean(data), means over RGB
};
AlbedoCheck albedoCheck(float theta_o_deg, const Rgb& data, const Rgb& fit);
// Where a table's fit misses the albedo tolerance, fitAnalytic repeats it with the energy weight
// raised by kEnergyRaiseFactor, at most kEnergyRaises times, and keeps the fit whose albedo is
// closest (the report gives the weight that fit used).
inline constexpr int kEnergyRaises = 2;
inline constexpr double kEnergyRaiseFactor = 4.0;

// The fitted parameters; which are used depends on the family.
struct AnalyticParameters {
  ModelFamily family = ModelFamily::Ggx;
  Rgb diffuse;                        // kd, every family
  Rgb specular;                       // f0 (ggx, ggx2) or ks (ward)
  float alpha = 0;                    // ggx, ggx2, ward
  std::vector<LafortuneLobe> lobes;   // lafortune
  Rgb specular_2 = {};                // ggx2: the second lobe's f0
  float alpha_2 = 0;                  // ggx2: the second lobe's alpha
  double abc_b = 1, abc_c = 1, abc_ior = 1.5;  // abc: B, C and ior (A is `specular`)
  // sgd: the lobe shape of every channel (alpha, p, f0, f1, kap, lambda, c, k, theta0; its rho_d and
  // rho_s are ignored: they are `diffuse` and `specular`).
  SgdChannel sgd_shape = {};
};

// The Material of a parameter set (a Ggx, GgxTwoLobes, Ward or Lafortune). Throws btf::Error for parameters
// the model refuses.
std::unique_ptr<Material> makeAnalyticMaterial(const AnalyticParameters& parameters);

struct AnalyticFitReport {
  bool converged = false;      // the final solve (the chosen start on all samples) ended on Ceres' convergence tolerances
  int starts = 0;              // starts screened
  int screening_converged = 0; // starts whose screening run (15 iterations on every 5th sample) already converged
  int iterations = 0;          // of the final solve
  double cost = 0;             // the objective above at the chosen start's end
  std::size_t samples = 0;     // cells in the objective
  std::size_t excluded = 0;    // cells of the sampling grid left out (unmeasured or below the horizon)
  double rel_rmse = 0;         // tableRelRmse of the fit
  double seconds = 0;          // wall time of the fit
  std::string ceres_report;    // Ceres' BriefReport of the chosen start (per channel: three lines)
  std::vector<AlbedoCheck> albedo;    // tables: at kAlbedoCheckAnglesDeg (scattered data: empty)
  double energy_weight = 0;           // the energy term's weight of the fit kept (tables; 0: none)
  // The fitted parameters that ended at a bound of the search, one line each ("B 1e+08, its upper
  // bound"). Checked: the shape parameters and ABC's and SGD's lobe scales, at the ends that are
  // limits of the search; not the albedos at 0 or 1, nor ABC's A or SGD's rho_s at their lower ends (no lobe in that
  // channel), nor SGD's f0 or lambda at 0 (no Fresnel rise, no shadowing), which
  // are the model's own limits and a material may reach them.
  std::vector<std::string> at_bound;
  std::vector<std::string> warnings;  // fitWarnings of this report
  // Where AnalyticFitOptions::fallback was fitted: why, and which fit was kept, one line ("abc's
  // fit was degenerate (...); sgd fitted too and kept: rel_rmse 0.05 against 0.99"); else empty.
  std::string fallback;
};

// What is wrong with a fit, one line each: a final solve that did not converge, rel_rmse above
// kFitRelRmseLimit, a parameter at a bound (at_bound), an albedo off by more than
// kFitAlbedoTolerance (`btf fit` prints them, and --strict makes them an error).
std::vector<std::string> fitWarnings(const AnalyticFitReport& report);
// The largest rel_error of report.albedo (0 when empty).
double worstAlbedoError(const AnalyticFitReport& report);
// A degenerate fit: a parameter at a bound, or rel_rmse above kFitRelRmseLimit (the fit explains
// little of the data's shape, whatever its albedo).
bool isDegenerateFit(const AnalyticFitReport& report);

struct AnalyticFit {
  AnalyticParameters parameters;
  std::shared_ptr<const Material> material;
  AnalyticFitReport report;
};

// Throws btf::Error for bad options and for a table with no usable cell. Deterministic: the
// starts run in parallel, each from a fixed initial guess, and the lowest cost wins (ties to the
// earlier start). Progress: one "fit" task over the starts.
AnalyticFit fitAnalytic(const MerlTable& table, const AnalyticFitOptions& options);

// `btf fit --model auto`: the candidates fitted one after another, in the order given (the
// caller's order of size: the fewest parameters first), and the first kept whose rel_rmse is within
// (1 + tolerance) of the best candidate's and whose albedo is within kFitAlbedoTolerance of the
// data's at every checked angle: the smallest model that does as well as any of them (the "model
// no more than a scene needs" rule, at the table level). Where no candidate keeps the albedo, the
// smallest within the rel_rmse tolerance is kept and `reason` says so. Throws btf::Error for an
// empty candidate list, and as fitAnalytic does.
struct AutoFit {
  AnalyticFit chosen;
  std::vector<AnalyticFit> tried;  // every candidate's fit, in the order given
  std::size_t chosen_index = 0;
  std::string reason;              // one line: why this candidate
};
AutoFit fitSmallestModel(const MerlTable& table, std::span<const AnalyticFitOptions> candidates, double tolerance);

// One measured value of a BRDF at a direction pair: scattered data such as a BTF texel's entries
// at its 81 x 81 direction pairs.
struct MeasuredReflectance {
  glm::vec3 wi, wo;  // unit, local frame
  Rgb f;             // 1/sr
};

// The same fit on scattered data: every sample is in the objective (no sampling grid) unless a
// channel is negative or not finite (unmeasured) or a direction lies below the horizon. Throws
// btf::Error for fewer than kMinimumFitSamples usable samples. report.rel_rmse is
// measuredRelRmse over the same data.
inline constexpr std::size_t kMinimumFitSamples = 50;
AnalyticFit fitAnalytic(std::span<const MeasuredReflectance> data, const AnalyticFitOptions& options);

// How far a model is from a table: rel_rmse of f cos(theta_i) over every measured cell whose
// directions both lie within 80 degrees of the normal (grazing cells of tabulated measurements
// hold outliers of 1e5 1/sr that would be the whole measure), all channels together:
//   sqrt(sum (cos_i (f_model - f_table))^2) / sqrt(sum (cos_i f_table)^2).
// The measure of `btf fit` and of the comparison with the published fits (docs/fit.md).
double tableRelRmse(const Material& model, const MerlTable& table);
// The same measure between two tables, cell by cell (a compressed table against its original).
// Comparing through a lookup would not do: the cells of theta_d = 0 all stand for one direction
// pair, so a lookup reads one of them for all, and on noisy tables even a lossless copy would
// show an error.
double tableRelRmse(const MerlTable& stored, const MerlTable& table);
// The same measure over scattered data (its usable samples within 80 degrees of the normal).
double measuredRelRmse(const Material& model, std::span<const MeasuredReflectance> data);

}  // namespace btf
