#include "sampling_table.h"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>

#include "btf/io/atomic_file.h"

namespace btf::cli {

const std::vector<std::string>& samplingCsvColumns() {
  static const std::vector<std::string> columns = {"material", "sampler", "parameter", "bytes",
                                                   "samples_per_s", "chi2_statistic", "chi2_p", "variance",
                                                   "seconds", "efficiency", "rel_error_vs_reference",
                                                   "per_sample_variance", "full_cdf_bytes", "acceptance_rate",
                                                   "stream_samples_per_s", "theta_o_deg", "parameterization",
                                                   "fcos_rel_variance", "efficiency_vs_own",
                                                   "stream_efficiency_vs_own", "stream_with_eval_per_s",
                                                   "ceiling_vs_own", "stream_ceiling_vs_own",
                                                   "proportional_variance_vs_own", "eval_env_ns",
                                                   "draw_budget_ns_2x", "ns_per_draw"};
  return columns;
}

const SamplingRow* ownRowOf(const std::vector<SamplingRow>& rows, const SamplingRow& r) {
  for (const SamplingRow& o : rows)
    if (o.material == r.material && o.theta_o_deg == r.theta_o_deg && o.sampler == "material") return &o;
  return nullptr;
}

VarianceVsOwn varianceVsOwn(const SamplingRow& own, const SamplingRow& r) {
  return {r.per_sample_variance > 0 ? own.per_sample_variance / r.per_sample_variance : 0.0,
          r.fcos_rel_variance > 0 ? own.fcos_rel_variance / r.fcos_rel_variance : 0.0};
}

std::string SamplingRow::group() const {
  char theta[32];
  std::snprintf(theta, sizeof theta, " %g deg", theta_o_deg);
  return material + theta + (parameterization.empty() ? "" : " " + parameterization);
}

void writeSamplingCsv(const std::filesystem::path& path, const std::vector<SamplingRow>& rows) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    const auto& columns = samplingCsvColumns();
    for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
    out << '\n' << std::setprecision(6);
    auto optional = [&](const std::optional<double>& v) {
      if (v) out << *v;
    };
    // Names hold no commas or quotes (presets, MERL names, file stems), so no quoting is needed.
    for (const SamplingRow& r : rows) {
      out << r.material << ',' << r.sampler << ',';
      optional(r.parameter);
      out << ',';
      optional(r.bytes);
      out << ',' << r.samples_per_s << ',' << r.chi2_statistic << ',' << r.chi2_p << ',' << r.variance << ','
          << r.seconds << ',' << r.efficiency << ',' << r.rel_error_vs_reference << ',' << r.per_sample_variance << ',';
      optional(r.full_cdf_bytes);
      out << ',';
      optional(r.acceptance_rate);
      out << ',';
      optional(r.stream_samples_per_s);
      out << ',' << r.theta_o_deg << ',' << r.parameterization << ',' << r.fcos_rel_variance << ',';
      optional(r.efficiency_vs_own);
      out << ',';
      optional(r.stream_efficiency_vs_own);
      out << ',';
      optional(r.stream_with_eval_per_s);
      out << ',';
      optional(r.ceiling_vs_own);
      out << ',';
      optional(r.stream_ceiling_vs_own);
      out << ',';
      optional(r.proportional_variance_vs_own);
      out << ',';
      optional(r.eval_env_ns);
      out << ',';
      optional(r.draw_budget_ns_2x);
      out << ',' << r.ns_per_draw << '\n';
    }
  });
}

}  // namespace btf::cli
