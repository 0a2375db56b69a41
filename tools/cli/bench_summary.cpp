#include "bench_summary.h"

#include <algorithm>
#include <string>

namespace btf::cli {
namespace {

// Materials in order of first appearance.
std::vector<std::string> materialsOf(const std::vector<SamplingRow>& rows) {
  std::vector<std::string> names;
  for (const SamplingRow& r : rows)
    if (std::find(names.begin(), names.end(), r.material) == names.end()) names.push_back(r.material);
  return names;
}

// The row of the sampler on the material with the largest efficiency, or null.
const SamplingRow* best(const std::vector<SamplingRow>& rows, const std::string& material, const std::string& sampler) {
  const SamplingRow* found = nullptr;
  for (const SamplingRow& r : rows)
    if (r.material == material && r.sampler == sampler && (!found || r.efficiency > found->efficiency)) found = &r;
  return found;
}

}  // namespace

void printQuadtreeSummary(std::FILE* out, const std::vector<SamplingRow>& rows) {
  std::fprintf(out, "\nQuadtree sampler (acceptance = mean over its bins of the per-proposal acceptance):\n");
  std::fprintf(out, "  %-26s %9s %11s %12s %12s %12s\n", "material", "threshold", "acceptance", "samples/s",
               "efficiency", "best dp-cdf");
  std::string wins, losses;
  for (const std::string& m : materialsOf(rows)) {
    const SamplingRow* dp = best(rows, m, "dp-cdf");
    for (const SamplingRow& r : rows) {
      if (r.material != m || r.sampler != "quadtree") continue;
      std::fprintf(out, "  %-26s %9.3g %11.3f %12.4g %12.4g %12.4g\n", m.c_str(), r.parameter.value_or(0),
                   r.acceptance_rate.value_or(0), r.samples_per_s, r.efficiency, dp ? dp->efficiency : 0.0);
    }
    const SamplingRow* qt = best(rows, m, "quadtree");
    if (!qt || !dp) continue;
    char item[160];
    std::snprintf(item, sizeof item, "%s%s (x%.2f)", (qt->efficiency > dp->efficiency ? wins : losses).empty() ? "" : ", ",
                  m.c_str(), qt->efficiency / dp->efficiency);
    (qt->efficiency > dp->efficiency ? wins : losses) += item;
  }
  std::fprintf(out, "Quadtree beats DP-CDF (best efficiency of each) on: %s\n", wins.empty() ? "none" : wins.c_str());
  std::fprintf(out, "Quadtree loses to DP-CDF on: %s\n", losses.empty() ? "none" : losses.c_str());
}

void printMemoryTargetSummary(std::FILE* out, const std::vector<SamplingRow>& rows) {
  std::fprintf(out,
               "\nDP-CDF memory target: bytes <= 1/10 of the full tabulated CDF at efficiency >= 0.95 of the "
               "tabulated sampler's (* = both met; efficiency ratios carry the noise of a timing, variance ratios "
               "none):\n");
  std::fprintf(out, "  %-26s %9s %14s %16s %16s %s\n", "material", "epsilon", "bytes/full_cdf", "eff/tabulated",
               "var_tab/var_dp", "");
  std::string met, missed;
  for (const std::string& m : materialsOf(rows)) {
    const SamplingRow* tab = best(rows, m, "tabulated");
    bool any = false;
    for (const SamplingRow& r : rows) {
      if (r.material != m || r.sampler != "dp-cdf" || !r.bytes || !r.full_cdf_bytes || *r.full_cdf_bytes <= 0) continue;
      const double memory = *r.bytes / *r.full_cdf_bytes;
      const double efficiency = tab && tab->efficiency > 0 ? r.efficiency / tab->efficiency : 0.0;
      const bool ok = memory <= 0.1 && efficiency >= 0.95;
      // The variance ratio is the efficiency ratio without the timing (same draws every run).
      const double variance_ratio = tab && r.variance > 0 ? tab->variance / r.variance : 0.0;
      std::fprintf(out, "  %-26s %9.3g %14.4f %16.3f %16.3f %s\n", m.c_str(), r.parameter.value_or(0), memory, efficiency,
                   variance_ratio, ok ? "*" : "");
      if (ok && !any) {
        char item[160];
        std::snprintf(item, sizeof item, "%s%s (eps %.3g)", met.empty() ? "" : ", ", m.c_str(), r.parameter.value_or(0));
        met += item;
        any = true;
      }
    }
    if (!any && tab) missed += (missed.empty() ? "" : ", ") + m;
  }
  std::fprintf(out, "Memory target met (first epsilon) on: %s\n", met.empty() ? "none" : met.c_str());
  std::fprintf(out, "Memory target missed on: %s\n", missed.empty() ? "none" : missed.c_str());
}

}  // namespace btf::cli
