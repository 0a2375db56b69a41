#include "bench_summary.h"

#include "btf/io/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <utility>

namespace btf::cli {
namespace {

// Groups (material, theta_o, parameterization: SamplingRow::group) in order of first appearance,
// tabulated samplers only (the warps and the own sampler have no parameterization).
std::vector<std::string> groupsOf(const std::vector<SamplingRow>& rows) {
  std::vector<std::string> names;
  for (const SamplingRow& r : rows)
    if (!r.parameterization.empty() && std::find(names.begin(), names.end(), r.group()) == names.end())
      names.push_back(r.group());
  return names;
}

// The row of the sampler in the group with the largest efficiency, or null.
const SamplingRow* best(const std::vector<SamplingRow>& rows, const std::string& group, const std::string& sampler) {
  const SamplingRow* found = nullptr;
  for (const SamplingRow& r : rows)
    if (r.group() == group && r.sampler == sampler && (!found || r.efficiency > found->efficiency)) found = &r;
  return found;
}

}  // namespace

void printQuadtreeSummary(std::FILE* out, const std::vector<SamplingRow>& rows) {
  std::fprintf(out, "\nQuadtree sampler (acceptance = mean over its bins of the per-proposal acceptance):\n");
  std::fprintf(out, "  %-40s %9s %11s %12s %12s %12s\n", "material, theta_o, parameterization", "threshold",
               "acceptance", "samples/s", "efficiency", "best dp-cdf");
  std::string wins, losses;
  for (const std::string& m : groupsOf(rows)) {
    const SamplingRow* dp = best(rows, m, "dp-cdf");
    for (const SamplingRow& r : rows) {
      if (r.group() != m || r.sampler != "quadtree") continue;
      std::fprintf(out, "  %-40s %9.3g %11.3f %12.4g %12.4g %12.4g\n", m.c_str(), r.parameter.value_or(0),
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
  std::fprintf(out, "  %-40s %9s %14s %16s %16s %s\n", "material, theta_o, parameterization", "epsilon",
               "bytes/full_cdf", "eff/tabulated", "var_tab/var_dp", "");
  std::string met, missed;
  for (const std::string& m : groupsOf(rows)) {
    const SamplingRow* tab = best(rows, m, "tabulated");
    bool any = false;
    for (const SamplingRow& r : rows) {
      if (r.group() != m || r.sampler != "dp-cdf" || !r.bytes || !r.full_cdf_bytes || *r.full_cdf_bytes <= 0) continue;
      const double memory = *r.bytes / *r.full_cdf_bytes;
      const double efficiency = tab && tab->efficiency > 0 ? r.efficiency / tab->efficiency : 0.0;
      const bool ok = memory <= 0.1 && efficiency >= 0.95;
      // The variance ratio is the efficiency ratio without the timing (same draws every run).
      const double variance_ratio = tab && r.variance > 0 ? tab->variance / r.variance : 0.0;
      std::fprintf(out, "  %-40s %9.3g %14.4f %16.3f %16.3f %s\n", m.c_str(), r.parameter.value_or(0), memory, efficiency,
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

void printOwnSamplerSummary(std::FILE* out, const std::vector<SamplingRow>& rows) {
  std::fprintf(out,
               "\nAgainst the material's own sampler at the same theta_o (ratios > 1: ours is better; eff = 1 / "
               "(variance * seconds) with sample()'s time, stream = with the stream call's time per draw and the eval of its weight; var = "
               "environment-lit variance per sample; f cos = relative variance of f cos / pdf):\n");
  std::fprintf(out, "  %-26s %7s %-9s %-9s %8s %10s %9s %11s %9s %13s %8s\n", "material", "theta_o", "param", "sampler", "eps",
               "bytes/full", "eff/own", "stream/own", "var own/", "f cos own/", "draw ns");
  for (const SamplingRow& r : rows) {
    if (!r.efficiency_vs_own || r.parameterization.empty()) continue;
    const SamplingRow* own = ownRowOf(rows, r);
    if (!own) continue;
    char eps[16] = "", memory[16] = "", stream[16] = "";
    if (r.parameter) std::snprintf(eps, sizeof eps, "%.3g", *r.parameter);
    if (r.bytes && r.full_cdf_bytes && *r.full_cdf_bytes > 0) std::snprintf(memory, sizeof memory, "%.3f", *r.bytes / *r.full_cdf_bytes);
    if (r.stream_efficiency_vs_own) std::snprintf(stream, sizeof stream, "%.2f", *r.stream_efficiency_vs_own);
    const VarianceVsOwn variance = varianceVsOwn(*own, r);
    // The draw alone, approximately: the estimate's time per draw less the eval, weight and
    // environment timed at the own draws (separate runs, so timing noise can even make it negative).
    char draw[16] = "";
    if (own->eval_env_ns) std::snprintf(draw, sizeof draw, "%.0f", r.ns_per_draw - *own->eval_env_ns);
    std::fprintf(out, "  %-26s %7.0f %-9s %-9s %8s %10s %9.2f %11s %9.3f %13.3f %8s\n", r.material.c_str(), r.theta_o_deg,
                 r.parameterization.c_str(), r.sampler.c_str(), eps, memory, *r.efficiency_vs_own, stream,
                 variance.env, variance.fcos, draw);
  }
  std::fprintf(out,
               "Ceiling (of a sampler with zero cost beyond the eval its weight needs and the variance of one exactly "
               "proportional to f cos; eff/own and stream/own as above):\n");
  for (const SamplingRow& r : rows) {
    if (!r.ceiling_vs_own || !r.stream_ceiling_vs_own) continue;
    char budget[96] = "none reaches it";  // the ceiling itself is below the target
    if (r.draw_budget_ns_2x && *r.draw_budget_ns_2x >= 0)
      std::snprintf(budget, sizeof budget, "its draw may take %.0f ns", *r.draw_budget_ns_2x);
    std::fprintf(out, "  %-26s %7.0f  eff/own <= %.2f, stream/own <= %.2f; variance of an exactly proportional "
                 "sampler / own's %.3f; for eff/own %g %s beyond the %.0f ns of eval, weight and environment\n",
                 r.material.c_str(), r.theta_o_deg, *r.ceiling_vs_own, *r.stream_ceiling_vs_own,
                 r.proportional_variance_vs_own.value_or(0.0), kSingleQueryTarget, budget, r.eval_env_ns.value_or(0.0));
  }
}

namespace {

// Efficiency with the stream call's time per draw and the eval of its weight (as stream_efficiency_vs_own).
std::optional<double> streamEfficiency(const SamplingRow& r) {
  if (!r.stream_with_eval_per_s || !(r.per_sample_variance > 0)) return std::nullopt;
  return *r.stream_with_eval_per_s / r.per_sample_variance;
}

}  // namespace

std::vector<WarpComparison> compareWithWarp(const std::vector<SamplingRow>& rows) {
  std::vector<WarpComparison> out;
  for (const SamplingRow& w : rows) {
    if (w.sampler != "dj-warp" || !w.bytes || !(w.efficiency > 0)) continue;
    WarpComparison c;
    c.material = w.material;
    c.theta_o_deg = w.theta_o_deg;
    c.warp_bytes = *w.bytes;
    const SamplingRow* best_stream = nullptr;
    for (const SamplingRow& r : rows) {
      if (r.material != w.material || r.theta_o_deg != w.theta_o_deg || r.sampler != "dp-cdf" || !r.bytes ||
          *r.bytes > *w.bytes)
        continue;
      if (!c.dp || r.efficiency > c.dp->efficiency) c.dp = &r;
      if (streamEfficiency(r) && (!best_stream || *streamEfficiency(r) > *streamEfficiency(*best_stream))) best_stream = &r;
    }
    if (c.dp) {
      c.efficiency_ratio = c.dp->efficiency / w.efficiency;
      if (c.dp->per_sample_variance > 0) c.variance_ratio = w.per_sample_variance / c.dp->per_sample_variance;
    }
    if (best_stream && streamEfficiency(w)) c.stream_ratio = *streamEfficiency(*best_stream) / *streamEfficiency(w);
    out.push_back(c);
  }
  return out;
}

void writeWarpComparisonCsv(const std::filesystem::path& path, const std::vector<WarpComparison>& comparisons) {
  writeFileAtomically(path, [&](std::ofstream& f) {
    f << "material,theta_o_deg,warp_bytes,dp_cdf_bytes,dp_cdf_parameterization,dp_cdf_epsilon,efficiency_vs_warp,"
         "stream_efficiency_vs_warp,warp_variance_over_dp_cdf\n";
    for (const WarpComparison& c : comparisons) {
      f << '"' << c.material << "\"," << c.theta_o_deg << ',' << c.warp_bytes << ',';
      if (c.dp) f << c.dp->bytes.value_or(0) << ',' << c.dp->parameterization << ',' << c.dp->parameter.value_or(0);
      else f << ",,";
      f << ',' << (c.dp ? std::to_string(c.efficiency_ratio) : "") << ','
        << (c.stream_ratio ? std::to_string(*c.stream_ratio) : "") << ','
        << (c.variance_ratio ? std::to_string(*c.variance_ratio) : "") << '\n';
    }
  });
}

void printWarpSummary(std::FILE* out, const std::vector<SamplingRow>& rows) {
  const std::vector<WarpComparison> comparisons = compareWithWarp(rows);
  if (comparisons.empty()) return;
  std::fprintf(out,
               "\nDP-CDF at no more bytes than the Dupuy-Jakob warp of the same material written as an RGL file (dj-warp), "
               "the best epsilon and parameterization per view (ratios > 1: DP-CDF is better; eff = 1 / (variance * "
               "seconds) per single query, stream = with the stream's time per draw and its weights' eval, var = "
               "environment-lit variance per sample, warp / DP-CDF):\n");
  std::fprintf(out, "  %-40s %7s %10s %10s %-9s %7s %9s %9s %9s\n", "material", "theta_o", "warp bytes", "dp bytes",
               "param", "eps", "eff", "stream", "var");
  struct Tally {
    double log_single = 0, log_stream = 0;
    int views = 0, stream_views = 0;
  };
  std::vector<std::pair<std::string, Tally>> materials;
  for (const WarpComparison& c : comparisons) {
    if (materials.empty() || materials.back().first != c.material) materials.push_back({c.material, {}});
    Tally& t = materials.back().second;
    if (!c.dp) {
      std::fprintf(out, "  %-40s %7.0f %10.0f  no DP-CDF setting within these bytes\n", c.material.c_str(), c.theta_o_deg,
                   c.warp_bytes);
      continue;
    }
    t.log_single += std::log(c.efficiency_ratio);
    ++t.views;
    char stream[16] = "";
    if (c.stream_ratio) {
      std::snprintf(stream, sizeof stream, "%.2f", *c.stream_ratio);
      t.log_stream += std::log(*c.stream_ratio);
      ++t.stream_views;
    }
    std::fprintf(out, "  %-40s %7.0f %10.0f %10.0f %-9s %7.3g %9.2f %9s %9.3f\n", c.material.c_str(), c.theta_o_deg,
                 c.warp_bytes, c.dp->bytes.value_or(0), c.dp->parameterization.c_str(), c.dp->parameter.value_or(0),
                 c.efficiency_ratio, stream, c.variance_ratio.value_or(0));
  }
  int single_wins = 0, stream_wins = 0, counted = 0;
  std::string losses;
  for (const auto& [name, t] : materials) {
    if (t.views == 0) continue;
    ++counted;
    const double single = std::exp(t.log_single / t.views);
    const double stream = t.stream_views ? std::exp(t.log_stream / t.stream_views) : 0.0;
    single_wins += single >= 1.0;
    stream_wins += stream >= 1.0;
    if (single < 1.0) losses += (losses.empty() ? "" : ", ") + name;
    std::fprintf(out, "  %-40s geometric mean over its views: eff %.2f, stream %.2f\n", name.c_str(), single, stream);
  }
  std::fprintf(out,
               "DP-CDF within the warp's bytes reaches the warp's efficiency (geometric mean over the views) on %d of %d "
               "materials per single query, %d of %d in streams; below it per single query: %s\n",
               single_wins, counted, stream_wins, counted, losses.empty() ? "none" : losses.c_str());
}

}  // namespace btf::cli
