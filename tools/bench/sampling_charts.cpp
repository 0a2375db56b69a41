#include "sampling_charts.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "bench_summary.h"
#include "gnuplot_charts.h"

namespace btf::cli {
namespace {

// Log axes cannot show 0: an estimate that hit the reference exactly is drawn at this floor.
constexpr double kErrorFloor = 1e-5;

std::string gpQuote(const std::string& text) { return tools::gnuplotQuote(text); }

std::string seriesName(const SamplingRow& r) {
  return r.parameterization.empty() ? r.sampler : r.sampler + " " + r.parameterization;
}

// One inline data block per sampler, in order of first appearance: "x y" lines.
template <typename Point>
std::string dataBlocks(const std::vector<SamplingRow>& rows, const std::string& prefix, Point point,
                       std::vector<std::string>& series) {
  std::map<std::string, std::ostringstream> blocks;
  for (const SamplingRow& r : rows) {
    double x = 0, y = 0;
    if (!point(r, x, y)) continue;
    const std::string name = seriesName(r);
    if (!blocks.count(name)) series.push_back(name);
    blocks[name] << x << ' ' << y << '\n';
  }
  std::ostringstream out;
  for (std::size_t i = 0; i < series.size(); ++i)
    out << '$' << prefix << i << " << EOD\n" << blocks[series[i]].str() << "EOD\n";
  return out.str();
}

std::string plotSeries(const std::string& prefix, const std::vector<std::string>& series) {
  std::ostringstream out;
  out << "plot ";
  for (std::size_t i = 0; i < series.size(); ++i)
    out << (i ? ", " : "") << '$' << prefix << i << " using 1:2 with points pt 7 ps 1.3 title " << gpQuote(series[i]);
  return out.str() + "\n";
}

// The samplers of the bar chart: the warps, the material's own, and the middle of each sweep.
std::vector<std::pair<std::string, std::optional<double>>> barSamplers(const std::vector<SamplingRow>& rows) {
  std::vector<std::pair<std::string, std::optional<double>>> chosen;
  std::map<std::string, std::vector<double>> sweeps;
  for (const SamplingRow& r : rows) {
    if (r.parameter) {
      auto& v = sweeps[seriesName(r)];
      if (std::find(v.begin(), v.end(), *r.parameter) == v.end()) v.push_back(*r.parameter);
    } else if (std::find(chosen.begin(), chosen.end(), std::make_pair(seriesName(r), std::optional<double>())) ==
               chosen.end()) {
      chosen.emplace_back(seriesName(r), std::nullopt);
    }
  }
  for (auto& [sampler, values] : sweeps) {
    std::sort(values.begin(), values.end());
    chosen.emplace_back(sampler, values[values.size() / 2]);
  }
  return chosen;
}

// The bars show the first view of the run (the rows of its theta_o), one bar per sampler setting.
std::string efficiencyBlock(const std::vector<SamplingRow>& all_rows, std::vector<std::string>& titles) {
  std::vector<SamplingRow> rows;
  for (const SamplingRow& r : all_rows)
    if (r.theta_o_deg == all_rows.front().theta_o_deg) rows.push_back(r);
  const auto samplers = barSamplers(rows);
  std::vector<std::string> materials;
  for (const SamplingRow& r : rows)
    if (std::find(materials.begin(), materials.end(), r.material) == materials.end()) materials.push_back(r.material);
  std::ostringstream out;
  out << "$eff << EOD\n";
  for (const std::string& m : materials) {
    out << gpQuote(m);
    for (const auto& [sampler, parameter] : samplers) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const SamplingRow& r) {
        return r.material == m && seriesName(r) == sampler && r.parameter == parameter;
      });
      if (it != rows.end() && it->efficiency > 0 && std::isfinite(it->efficiency)) out << ' ' << it->efficiency;
      else out << " ?";
    }
    out << '\n';
  }
  out << "EOD\n";
  for (const auto& [sampler, parameter] : samplers) {
    std::ostringstream t;
    t << sampler;
    if (parameter) t << (sampler.rfind("dp-cdf", 0) == 0 ? " eps " : " thr ") << *parameter;
    titles.push_back(t.str());
  }
  return out.str();
}

// Series of (theta_o, ratio) points, kept in order of first appearance; non-positive or
// non-finite ratios are left out (a log axis cannot show them).
class RatioSeries {
 public:
  // A bound is drawn as a dotted line, a measured series with points.
  void add(const std::string& name, double x, double y, bool bound = false) {
    if (!(y > 0) || !std::isfinite(y)) return;
    if (!blocks_.count(name)) names_.push_back(name), bounds_.push_back(bound);
    blocks_[name] << x << ' ' << y << '\n';
  }
  bool empty() const { return names_.empty(); }
  // The data blocks into `script`, and the plot command's series (after what `plot` already has).
  std::string plotInto(std::ostringstream& script, const std::string& prefix) {
    std::ostringstream plot;
    for (std::size_t i = 0; i < names_.size(); ++i) {
      script << '$' << prefix << i << " << EOD\n" << blocks_[names_[i]].str() << "EOD\n";
      plot << ", $" << prefix << i << " using 1:2 with "
           << (bounds_[i] ? "lines dt 3 lw 3 lc 'gray30'" : "linespoints lw 2") << " title " << gpQuote(names_[i]);
    }
    return plot.str();
  }

 private:
  std::vector<std::string> names_;
  std::vector<bool> bounds_;
  std::map<std::string, std::ostringstream> blocks_;
};

std::string chartStem(const std::string& prefix, const std::string& material) {
  std::string stem = prefix + material;
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  return stem;
}

// Per material, two charts against theta_o, relative to its own sampler (the dashed line at 1):
// - efficiency: the tabulated sampler and DP-CDF at the middle epsilon of the run, single queries
//   and stream calls, per parameterization, under the ceilings of an exactly proportional sampler
//   at no cost beyond the eval (EfficiencyCeiling);
// - variance per sample, own / ours, under the environment and of f cos alone, with the bound an
//   exactly proportional sampler sets under the environment (it need not be 1: a sampler whose
//   departures from f cos favour the environment beats it).
std::vector<tools::GnuplotChart> ownCharts(const std::vector<SamplingRow>& rows, std::ostringstream& script) {
  std::vector<double> epsilons;
  for (const SamplingRow& r : rows)
    if (r.sampler == "dp-cdf" && r.parameter && std::find(epsilons.begin(), epsilons.end(), *r.parameter) == epsilons.end())
      epsilons.push_back(*r.parameter);
  std::sort(epsilons.begin(), epsilons.end());
  const double middle = epsilons.empty() ? -1.0 : epsilons[epsilons.size() / 2];
  std::vector<std::string> materials;
  for (const SamplingRow& r : rows)
    if (r.efficiency_vs_own && std::find(materials.begin(), materials.end(), r.material) == materials.end())
      materials.push_back(r.material);
  std::vector<tools::GnuplotChart> charts;
  for (std::size_t mi = 0; mi < materials.size(); ++mi) {
    RatioSeries efficiency, variance;
    for (const SamplingRow& r : rows) {
      if (r.material != materials[mi]) continue;
      // The ceilings and the proportional sampler's variance (EfficiencyCeiling), on the own sampler's rows.
      if (r.ceiling_vs_own && r.stream_ceiling_vs_own) {
        efficiency.add("ceiling, single", r.theta_o_deg, *r.ceiling_vs_own);
        efficiency.add("ceiling, stream", r.theta_o_deg, *r.stream_ceiling_vs_own);
      }
      if (r.proportional_variance_vs_own)
        variance.add("env, a sampler exactly proportional to f cos", r.theta_o_deg,
                     1.0 / *r.proportional_variance_vs_own, true);
      if (!r.efficiency_vs_own || r.parameterization.empty()) continue;
      std::ostringstream name;
      if (r.sampler == "dp-cdf" && r.parameter && *r.parameter == middle)
        name << "dp-cdf " << r.parameterization << " eps " << middle;
      else if (r.sampler == "tabulated")
        name << "tabulated " << r.parameterization;
      else
        continue;
      efficiency.add(name.str(), r.theta_o_deg, *r.efficiency_vs_own);
      if (r.sampler == "dp-cdf" && r.stream_efficiency_vs_own)
        efficiency.add(name.str() + " stream", r.theta_o_deg, *r.stream_efficiency_vs_own);
      if (const SamplingRow* own = ownRowOf(rows, r)) {
        const VarianceVsOwn v = varianceVsOwn(*own, r);
        variance.add("env, " + name.str(), r.theta_o_deg, v.env);
        variance.add("f cos, " + name.str(), r.theta_o_deg, v.fcos);
      }
    }
    auto chart = [&](RatioSeries& series, const std::string& prefix, const std::string& title,
                     const std::string& ylabel) {
      if (series.empty()) return;
      const std::string data = prefix + std::to_string(mi) + "_";
      std::ostringstream body;
      body << "set title " << gpQuote(title + materials[mi]) << "\n"
           << "set logscale y\nset xlabel 'theta_o (deg)'\nset ylabel " << gpQuote(ylabel) << "\nset grid\n"
           << "set key outside right\nset xrange [-5:90]\n"
           << "plot 1 with lines dt 2 lc 'black' title 'own sampler'" << series.plotInto(script, data) << "\n";
      charts.push_back({chartStem("sampling_" + prefix + "_", materials[mi]), body.str()});
    };
    chart(efficiency, "vs_own", "Efficiency relative to the material's own sampler: ", "efficiency / own sampler");
    chart(variance, "variance_vs_own", "Variance per sample, own sampler's / ours (above 1 favours ours): ",
          "variance of own / variance of ours");
  }
  return charts;
}

// Per material with a dj-warp row, efficiency relative to the warp (the dashed line at 1) against
// theta_o: the best DP-CDF within the warp's bytes per single query and in streams (the
// comparison of printWarpSummary), and the full tabulated sampler per parameterization, which
// needs more bytes, for scale.
std::vector<tools::GnuplotChart> warpCharts(const std::vector<SamplingRow>& rows, std::ostringstream& script) {
  const std::vector<WarpComparison> comparisons = compareWithWarp(rows);
  std::vector<std::string> materials;
  for (const WarpComparison& c : comparisons)
    if (std::find(materials.begin(), materials.end(), c.material) == materials.end()) materials.push_back(c.material);
  std::vector<tools::GnuplotChart> charts;
  for (std::size_t mi = 0; mi < materials.size(); ++mi) {
    RatioSeries series;
    double warp_bytes = 0;
    for (const WarpComparison& c : comparisons) {
      if (c.material != materials[mi]) continue;
      warp_bytes = c.warp_bytes;
      if (c.dp) series.add("dp-cdf within the warp's bytes, single", c.theta_o_deg, c.efficiency_ratio);
      if (c.stream_ratio) series.add("dp-cdf within the warp's bytes, stream", c.theta_o_deg, *c.stream_ratio);
      for (const SamplingRow& r : rows)
        if (r.material == c.material && r.theta_o_deg == c.theta_o_deg && r.sampler == "tabulated" && r.bytes) {
          const auto w = std::find_if(rows.begin(), rows.end(), [&](const SamplingRow& x) {
            return x.material == c.material && x.theta_o_deg == c.theta_o_deg && x.sampler == "dj-warp";
          });
          char name[96];
          std::snprintf(name, sizeof name, "tabulated %s (%.0f kB)", r.parameterization.c_str(), *r.bytes / 1024);
          if (w != rows.end() && w->efficiency > 0) series.add(name, r.theta_o_deg, r.efficiency / w->efficiency);
        }
    }
    if (series.empty()) continue;
    const std::string data = "warp" + std::to_string(mi) + "_";
    char title[256];
    std::snprintf(title, sizeof title, "Efficiency relative to the Dupuy-Jakob warp (%.0f kB .bsdf): %s", warp_bytes / 1024,
                  materials[mi].c_str());
    std::ostringstream body;
    body << "set title " << gpQuote(title) << "\n"
         << "set logscale y\nset xlabel 'theta_o (deg)'\nset ylabel 'efficiency / dj-warp'\nset grid\n"
         << "set key outside right\nset xrange [-5:90]\n"
         << "plot 1 with lines dt 2 lc 'black' title 'dj-warp'" << series.plotInto(script, data) << "\n";
    charts.push_back({chartStem("sampling_vs_warp_", materials[mi]), body.str()});
  }
  return charts;
}

}  // namespace

ChartOutcome drawSamplingCharts(const std::filesystem::path& folder, const std::vector<SamplingRow>& rows) {
  std::ostringstream script;
  std::vector<std::string> mem_series, speed_series, bar_titles;
  script << dataBlocks(rows, "mem", [](const SamplingRow& r, double& x, double& y) {
    if (!r.bytes || *r.bytes <= 0) return false;
    x = *r.bytes, y = std::max(r.rel_error_vs_reference, kErrorFloor);
    return true;
  }, mem_series);
  script << dataBlocks(rows, "speed", [](const SamplingRow& r, double& x, double& y) {
    x = std::max(r.rel_error_vs_reference, kErrorFloor), y = r.samples_per_s;
    return y > 0;
  }, speed_series);
  script << efficiencyBlock(rows, bar_titles);

  std::vector<tools::GnuplotChart> charts = {
      {"sampling_memory_vs_error",
       "set title 'Memory of the sampling tables vs error of the fixed estimate (all materials)'\n"
       "set logscale xy\nset xlabel 'bytes'\nset ylabel 'rel. error vs reference (|estimate - ref| / ref)'\n" +
           plotSeries("mem", mem_series)},
      {"sampling_speed_vs_error",
       "set title 'Sampling speed vs error of the fixed estimate (all materials)'\n"
       "set logscale xy\nset xlabel 'rel. error vs reference'\nset ylabel 'samples/s (one core, direction + pdf)'\n" +
           plotSeries("speed", speed_series)},
      {"sampling_efficiency", [&] {
         std::ostringstream b;
         b << "set title " << gpQuote("efficiency = 1 / (variance * seconds) of the environment-lit radiance estimate, theta_o " +
                                      std::to_string(int(rows.empty() ? 0 : rows.front().theta_o_deg)) + " deg") << "\n"
           << "set logscale y\nset ylabel 'efficiency (1 / (variance * s))'\nset style data histogram\n"
           << "set style histogram clustered gap 1\nset style fill solid 0.85 border -1\nset boxwidth 0.9\n"
           << "set xtics rotate by -30 noenhanced\nset yrange [*:*]\n";
         b << "plot ";
         for (std::size_t i = 0; i < bar_titles.size(); ++i)
           b << (i ? ", " : "") << "$eff using " << i + 2 << (i ? "" : ":xtic(1)") << " title " << gpQuote(bar_titles[i]);
         b << "\n";
         return b.str();
       }()},
  };
  for (tools::GnuplotChart& c : ownCharts(rows, script)) charts.push_back(std::move(c));
  for (tools::GnuplotChart& c : warpCharts(rows, script)) charts.push_back(std::move(c));
  const tools::GnuplotOutcome drawn = tools::drawGnuplotCharts(folder, "sampling_charts.gp", script.str(), charts);
  return ChartOutcome{drawn.files, drawn.message};
}

}  // namespace btf::cli
