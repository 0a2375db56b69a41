// The rows of `btf bench sampling` and their CSV file (sampling.csv): one row per material, sampler
// setting and view theta_o, columns
//   material, sampler, parameter, bytes, samples_per_s, chi2_statistic, chi2_p, variance, seconds,
//   efficiency, rel_error_vs_reference, per_sample_variance, full_cdf_bytes, acceptance_rate,
//   stream_samples_per_s (the tabulated samplers' stream call, sampleDirections; dj-warp's draws one
//   by one in the same blocks; empty for others),
//   theta_o_deg, parameterization (incident or half for the tabulated samplers, empty for others),
//   fcos_rel_variance (fcosRelativeVariance: the sampler's quality without the environment),
//   efficiency_vs_own (efficiency / the material's own sampler's at the same theta_o),
//   stream_efficiency_vs_own (the same with the time per draw of the stream call followed by the
//   material's eval of every drawn direction: the stream returns the direction and its pdf, and a
//   renderer still needs f for the weight, which the own sampler's sample() includes),
//   stream_with_eval_per_s (that rate: the draws, then eval per draw; empty for others),
//   ceiling_vs_own, stream_ceiling_vs_own, proportional_variance_vs_own, eval_env_ns and
//   draw_budget_ns_2x (the own sampler's rows only, see SamplingRow), ns_per_draw
// rel_error_vs_reference compares the estimate with the quadrature reference (referenceRadiance);
// full_cdf_bytes (the float CDFs of the full grid, for memory ratios) is empty for warps and a
// material's own sampler; acceptance_rate is the quadtree's mean per-proposal acceptance over its
// bins, and its acceptance in the measured wo's bin is printed by the bench.
// parameter is epsilon for dp-cdf, the threshold for quadtree, empty otherwise; bytes is empty when
// the sampler does not report its memory (a material's own sampler); see sampling_measures.h.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace btf::cli {

struct SamplingRow {
  std::string material, sampler;
  std::optional<double> parameter;
  std::optional<double> bytes;
  double samples_per_s = 0;
  std::optional<double> stream_samples_per_s, stream_with_eval_per_s;
  double chi2_statistic = 0, chi2_p = 0;
  double variance = 0, seconds = 0, efficiency = 0;
  double rel_error_vs_reference = 0;
  double per_sample_variance = 0;
  std::optional<double> full_cdf_bytes;
  std::optional<double> acceptance_rate;
  double theta_o_deg = 0;
  std::string parameterization;
  double fcos_rel_variance = 0;
  std::optional<double> efficiency_vs_own, stream_efficiency_vs_own;
  // The own sampler's row only: what an exactly proportional sampler at no cost beyond the eval
  // would reach relative to it (EfficiencyCeiling).
  std::optional<double> ceiling_vs_own, stream_ceiling_vs_own;
  // The own sampler's row only: the per-sample variance of a sampler exactly proportional to
  // lum(f) cos over the own sampler's (EfficiencyCeiling::variance_ratio inverted). Below 1, a
  // perfect f cos sampler has less variance than the own one; above 1, the own sampler's departures
  // from f cos favour the environment, and no sampler proportional to f cos reaches its variance.
  std::optional<double> proportional_variance_vs_own;
  // Nanoseconds per draw of the fixed estimate (seconds over its draws: the draw with its weight's
  // eval and the environment).
  double ns_per_draw = 0;
  // The own sampler's row only: nanoseconds per draw of eval, weight and environment at its draws,
  // which every table sampler pays on top of its draw (ns_per_draw - eval_env_ns is what a table
  // row's draw costs), and the draw time at which an exactly proportional sampler would reach 2x
  // the own sampler's single-query efficiency (EfficiencyCeiling::drawBudget; negative: none can).
  std::optional<double> eval_env_ns, draw_budget_ns_2x;
  // material, theta_o and parameterization: the rows the summaries compare with each other.
  std::string group() const;
};

// The single-query target of the table samplers against a material's own sampler (twice its
// efficiency): the bench reports the draw time it asks for (draw_budget_ns_2x).
inline constexpr double kSingleQueryTarget = 2.0;

// The own sampler's row of r's material and view, or null.
const SamplingRow* ownRowOf(const std::vector<SamplingRow>& rows, const SamplingRow& r);

// The own sampler's variances over r's (> 1: r samples better), 0 where r's is 0: under the
// environment (per_sample_variance) and of f cos alone (fcos_rel_variance).
struct VarianceVsOwn {
  double env = 0, fcos = 0;
};
VarianceVsOwn varianceVsOwn(const SamplingRow& own, const SamplingRow& r);

// The column names, in order.
const std::vector<std::string>& samplingCsvColumns();

// Writes the CSV atomically (FileError on failure).
void writeSamplingCsv(const std::filesystem::path& path, const std::vector<SamplingRow>& rows);

}  // namespace btf::cli
