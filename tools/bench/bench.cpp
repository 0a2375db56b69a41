// `btf bench sampling [--materials LIST] [--quick] -o DIR`: every sampler on every material, with
// the measures of sampling_measures.h, written to DIR/sampling.csv and charted by gnuplot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_bonn.h"
#include "bench_compressibility.h"
#include "bench_compression.h"
#include "bench_decode.h"
#include "bench_fits.h"
#include "bench_materials.h"
#include "bench_render.h"
#include "bench_rgl_writer.h"
#include "bench_summary.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/quadtree_sampler.h"
#include "btf/sampling/rgl_warp_sampler.h"
#include "comma_list.h"
#include "bench_command.h"
#include "btf/sampling/sampler_choice.h"
#include "sampling_charts.h"
#include "sampling_measures.h"
#include "sampling_table.h"

namespace btf::cli {
namespace {

struct BenchOptions {
  std::string materials;  // comma-separated; empty: the default list
  std::string output;
  bool quick = false;
  std::vector<float> theta_o = {0.0f, 30.0f, 60.0f, 80.0f};
  std::vector<std::string> parameterizations = {"incident", "half"};
  std::uint64_t seed = 1;
  std::vector<float> epsilons, thresholds;  // empty: the sizes' defaults
  std::vector<std::string> samplers = {"tabulated", "dp-cdf", "quadtree", "dj-warp"};  // the table samplers run
  bool as_tables = false;  // every material tabulated into the MERL layout first
  int theta_o_bins = 0, half_vector_bins = 0;  // 0: the sizes' (the library's defaults)
};

// Work per row. --quick is for tests.
struct BenchSizes {
  SamplerOptions tables;
  std::vector<float> epsilons, thresholds;
  std::uint64_t speed_draws, estimate_draws, chi2_draws;
  int reference_theta_steps;  // of the quadrature reference (referenceRadiance)
};

BenchSizes sizesFor(bool quick) {
  BenchSizes s;
  if (quick) {
    s.tables.theta_o_bins = 4;
    s.tables.cos_theta_bins = 16;
    s.tables.phi_bins = 32;
    s.tables.half_vector_bins = 16;
    s.tables.supersampling = 1;
    s.tables.max_depth = 6;
    s.epsilons = {1e-3f, 1e-2f};
    s.thresholds = {4.0f};
    s.speed_draws = 20'000, s.estimate_draws = 5'000, s.chi2_draws = 20'000;
    s.reference_theta_steps = 64;
  } else {
    // The library's default tables (what users get): every view is measured on the tables a
    // renderer would build. Three tolerances across the memory target's range.
    s.epsilons = {1e-3f, 3e-3f, 1e-2f};
    s.thresholds = {2.0f, 8.0f};
    s.speed_draws = 100'000, s.estimate_draws = 50'000, s.chi2_draws = 100'000;
    // 768 x 1536 midpoints in (theta, phi), 0.1 deg apart: resolves the chrome preset's lobe.
    s.reference_theta_steps = 384;
  }
  return s;
}

constexpr int kTimingRepeats = 3;

struct Setting {
  SamplerChoice choice;
  std::optional<double> parameter;
  std::optional<Parameterization> parameterization;  // the tabulated samplers only
};

// The baselines always run: every efficiency is relative to the material's own sampler.
std::vector<Setting> settingsFor(const BenchSizes& sizes, const std::vector<Parameterization>& parameterizations,
                                 const std::vector<SamplerChoice>& samplers) {
  std::vector<Setting> settings = {{SamplerChoice::Uniform, {}, {}}, {SamplerChoice::Cosine, {}, {}},
                                   {SamplerChoice::Own, {}, {}}};
  auto runs = [&](SamplerChoice c) { return std::find(samplers.begin(), samplers.end(), c) != samplers.end(); };
  for (const Parameterization p : parameterizations) {
    if (runs(SamplerChoice::Tabulated)) settings.push_back({SamplerChoice::Tabulated, {}, p});
    if (runs(SamplerChoice::DpCdf))
      for (float e : sizes.epsilons) settings.push_back({SamplerChoice::DpCdf, e, p});
    if (runs(SamplerChoice::Quadtree))
      for (float t : sizes.thresholds) settings.push_back({SamplerChoice::Quadtree, t, p});
  }
  if (runs(SamplerChoice::DjWarp)) settings.push_back({SamplerChoice::DjWarp, {}, {}});
  return settings;
}

std::shared_ptr<const Material> build(const BenchMaterial& m, const Setting& setting, const BenchSizes& sizes) {
  SamplerOptions options = sizes.tables;
  if (setting.choice == SamplerChoice::DpCdf) options.epsilon = float(*setting.parameter);
  if (setting.choice == SamplerChoice::Quadtree) options.threshold = float(*setting.parameter);
  if (setting.parameterization) options.parameterization = *setting.parameterization;
  return withSampler(setting.choice, m.material, options);
}

// Timings are the best of kTimingRepeats identical runs: other processes on a shared machine only
// ever add time, and the best run is the one they disturbed least (the draws, and so the
// variance, are the same each time). `rate` returns draws per second.
template <class Rate>
double bestRate(Rate rate) {
  double best = 0.0;
  for (int k = 0; k < kTimingRepeats; ++k) best = std::max(best, rate());
  return best;
}

SamplingRow measure(const BenchMaterial& m, const Setting& setting, const Material& sampled, const BenchSizes& sizes,
                    float theta_o_deg, double reference, std::uint64_t seed) {
  const glm::vec3 wo = sphericalDirection(theta_o_deg * kPi / 180.0f, 0.0f);
  SamplingRow row;
  row.material = m.name;
  row.sampler = std::string(toString(setting.choice));
  row.parameter = setting.parameter;
  row.theta_o_deg = theta_o_deg;
  if (const auto* binned = dynamic_cast<const BinnedSampler*>(&sampled)) {
    const SamplerStats stats = binned->stats();
    row.parameterization = stats.parameterization;
    row.bytes = double(stats.bytes);
    row.full_cdf_bytes = double(stats.full_cdf_bytes);
    if (std::isfinite(stats.acceptance_rate)) row.acceptance_rate = stats.acceptance_rate;
    row.stream_samples_per_s = bestRate([&] { return streamSamplesPerSecond(*binned, wo, sizes.speed_draws, seed); });
    row.stream_with_eval_per_s =
        bestRate([&] { return streamSamplesPerSecond(*binned, wo, sizes.speed_draws, seed, true); });
  } else if (const auto* warp = dynamic_cast<const RglWarpSampler*>(&sampled)) {
    row.bytes = double(warp->bytes());
    // The warp has no stream call: its draws one by one, their weights' evals per block.
    row.stream_samples_per_s = bestRate([&] { return streamSamplesPerSecond(sampled, wo, sizes.speed_draws, seed); });
    row.stream_with_eval_per_s =
        bestRate([&] { return streamSamplesPerSecond(sampled, wo, sizes.speed_draws, seed, true); });
  } else if (setting.choice != SamplerChoice::Own) {
    row.bytes = 0.0;  // a hemisphere warp has no tables
  }
  row.samples_per_s = bestRate([&] { return samplesPerSecond(sampled, wo, sizes.speed_draws, seed); });
  // The harness's default 20 x 40 cells: it integrates the sharp piecewise-constant tables
  // exactly (to ~1e-6 of a count), so finer cells are not needed, and the integration of the
  // 40 x 80 cells of `btf sample` made the chi-square most of the run time.
  Chi2Options chi2;
  chi2.sample_count = sizes.chi2_draws;
  chi2.seed = seed;
  const Chi2Result test = chi2TestMaterial(sampled, wo, {}, chi2);
  row.chi2_statistic = test.statistic;
  row.chi2_p = test.p_value;
  Estimate e = estimateReflectedRadiance(sampled, wo, sizes.estimate_draws, seed);
  for (int k = 1; k < kTimingRepeats; ++k)
    e.seconds = std::min(e.seconds, estimateReflectedRadiance(sampled, wo, sizes.estimate_draws, seed).seconds);
  row.variance = e.variance;
  row.per_sample_variance = e.per_sample_variance;
  row.seconds = e.seconds;
  row.efficiency = e.efficiency();
  row.ns_per_draw = e.seconds / double(sizes.estimate_draws) * 1e9;
  row.fcos_rel_variance = fcosRelativeVariance(sampled, wo, sizes.estimate_draws, seed);
  row.rel_error_vs_reference = reference > 0 ? std::abs(e.mean - reference) / reference : std::abs(e.mean);
  if (setting.choice == SamplerChoice::Own) {
    const EfficiencyCeiling ceiling = efficiencyCeiling(sampled, wo, sizes.estimate_draws, seed, kTimingRepeats);
    row.eval_env_ns = ceiling.evalEnvPerDraw() * 1e9;
    // Without a variance ratio (a variance that vanishes) there is no ceiling to report.
    if (ceiling.variance_ratio > 0) {
      row.ceiling_vs_own = ceiling.single();
      row.stream_ceiling_vs_own = ceiling.stream();
      row.proportional_variance_vs_own = 1.0 / ceiling.variance_ratio;
      row.draw_budget_ns_2x = ceiling.drawBudget(kSingleQueryTarget) * 1e9;
    }
  }
  return row;
}

// Efficiencies relative to the own sampler's row of the same material and view.
void relateToOwn(std::vector<SamplingRow>& rows) {
  for (SamplingRow& r : rows) {
    const SamplingRow* own = ownRowOf(rows, r);
    if (!own || !(own->efficiency > 0)) continue;
    r.efficiency_vs_own = r.efficiency / own->efficiency;
    // efficiency = 1 / (variance of the mean * seconds of the draws) = 1 / (variance per sample *
    // seconds per draw), so the stream's is its draws per second over its variance per sample. The
    // draws are counted with the eval that forms their weight, which the own sampler's time holds.
    if (r.stream_with_eval_per_s && r.per_sample_variance > 0)
      r.stream_efficiency_vs_own = *r.stream_with_eval_per_s / r.per_sample_variance / own->efficiency;
  }
}

void runBenchSampling(const BenchOptions& o) {
  const std::vector<std::string> names = o.materials.empty() ? defaultBenchMaterialNames(o.quick) : splitCommaList(o.materials);
  if (names.empty()) throw Error("--materials lists no material");
  if (o.theta_o.empty()) throw Error("--theta-o lists no view");
  for (float t : o.theta_o)
    if (!(t >= 0.0f && t < 90.0f)) throw Error("--theta-o must be in [0, 90) degrees");
  std::vector<Parameterization> parameterizations;
  for (const std::string& name : o.parameterizations) {
    const auto p = parseParameterization(name);
    if (!p) throw Error("--parameterizations: unknown parameterization '" + name + "' (known: auto, incident, half)");
    parameterizations.push_back(*p);
  }
  const std::filesystem::path folder = o.output;
  std::filesystem::create_directories(folder);

  BenchSizes sizes = sizesFor(o.quick);
  if (!o.epsilons.empty()) sizes.epsilons = o.epsilons;
  if (!o.thresholds.empty()) sizes.thresholds = o.thresholds;
  for (float e : sizes.epsilons)
    if (!(e >= 0.0f)) throw Error("--epsilons must be >= 0");
  for (float t : sizes.thresholds)
    if (!(t >= 1.0f) || !std::isfinite(t)) throw Error("--thresholds must be finite and >= 1");
  // 0 keeps the default; past 4096 half-vector bins a table would not fit in memory.
  if (o.theta_o_bins < 0 || o.theta_o_bins > 4096) throw Error("--theta-o-bins must be in [1, 4096]");
  if (o.half_vector_bins < 0 || o.half_vector_bins == 1 || o.half_vector_bins > 4096)
    throw Error("--half-vector-bins must be in [2, 4096]");
  if (o.theta_o_bins > 0) sizes.tables.theta_o_bins = o.theta_o_bins;
  if (o.half_vector_bins > 0) sizes.tables.half_vector_bins = o.half_vector_bins;
  std::vector<SamplerChoice> samplers;
  for (const std::string& name : o.samplers) {
    const auto c = parseSamplerChoice(name);
    if (!c || (*c != SamplerChoice::Tabulated && *c != SamplerChoice::DpCdf && *c != SamplerChoice::Quadtree &&
               *c != SamplerChoice::DjWarp))
      throw Error("--samplers: '" + name + "' is not a table sampler (known: tabulated, dp-cdf, quadtree, dj-warp)");
    samplers.push_back(*c);
  }
  const std::vector<Setting> settings = settingsFor(sizes, parameterizations, samplers);
  std::vector<SamplingRow> rows;
  Progress progress("bench sampling", names.size() * (settings.size() + 1));
  for (const std::string& name : names) {
    const BenchMaterial m = o.as_tables ? asTable(loadBenchMaterial(name)) : loadBenchMaterial(name);
    // The reference: deterministic quadrature of the material itself, so that an estimate's error
    // is measured against the exact value rather than against another noisy estimate.
    std::vector<double> reference;
    for (float t : o.theta_o) {
      const Quadrature q = referenceRadiance(*m.material, sphericalDirection(t * kPi / 180.0f, 0.0f), sizes.reference_theta_steps);
      reference.push_back(q.value);
      std::printf("%s, theta_o %g: reference radiance %.6g (quadrature, %d x %d midpoints, extrapolated; finer rule's "
                  "error %.2g relative, %.2f s)\n",
                  name.c_str(), t, q.value, 2 * sizes.reference_theta_steps, 4 * sizes.reference_theta_steps,
                  q.error / std::max(std::abs(q.value), 1e-30), q.seconds);
    }
    progress.advance();
    for (const Setting& setting : settings) {
      if (setting.choice == SamplerChoice::DjWarp && m.material->isAnisotropic()) {
        std::printf("  dj-warp    skipped: %s is anisotropic, and an RGL file written here is isotropic\n", m.name.c_str());
        progress.advance();
        continue;
      }
      const std::shared_ptr<const Material> sampled = build(m, setting, sizes);
      for (std::size_t v = 0; v < o.theta_o.size(); ++v) {
        rows.push_back(measure(m, setting, *sampled, sizes, o.theta_o[v], reference[v], o.seed));
        const SamplingRow& r = rows.back();
        char acceptance[48] = "";
        if (r.acceptance_rate) std::snprintf(acceptance, sizeof acceptance, "  acceptance %.3f", *r.acceptance_rate);
        std::printf("  %-10s %-8s %-8s %4.0f deg %10.3g samples/s  efficiency %10.4g  rel. error %9.2e  var/sample %9.3g  "
                    "f cos relvar %9.3g  chi2 p %.3g%s\n",
                    r.sampler.c_str(), r.parameterization.c_str(),
                    r.parameter ? std::to_string(*r.parameter).substr(0, 6).c_str() : "", r.theta_o_deg, r.samples_per_s,
                    r.efficiency, r.rel_error_vs_reference, r.per_sample_variance, r.fcos_rel_variance, r.chi2_p,
                    acceptance);
        std::fflush(stdout);
      }
      progress.advance();
    }
  }
  relateToOwn(rows);
  printQuadtreeSummary(stdout, rows);
  printMemoryTargetSummary(stdout, rows);
  printOwnSamplerSummary(stdout, rows);
  printWarpSummary(stdout, rows);
  const std::filesystem::path csv = folder / "sampling.csv";
  writeSamplingCsv(csv, rows);
  std::printf("wrote %s (%zu rows)\n", csv.string().c_str(), rows.size());
  if (const std::vector<WarpComparison> warp = compareWithWarp(rows); !warp.empty()) {
    writeWarpComparisonCsv(folder / "warp_comparison.csv", warp);
    std::printf("wrote %s (%zu rows)\n", (folder / "warp_comparison.csv").string().c_str(), warp.size());
  }
  const ChartOutcome charts = drawSamplingCharts(folder, rows);
  if (!charts.message.empty()) std::fprintf(stderr, "btf: warning: %s\n", charts.message.c_str());
  for (const auto& file : charts.files) std::printf("wrote %s\n", file.string().c_str());
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks");
  bench->require_subcommand(1);
  auto* cmd = bench->add_subcommand(
      "sampling", "Every sampler on every material: samples/s, bytes, chi-square, and efficiency = "
                  "1/(variance*seconds) of an environment-lit radiance estimate; CSV and gnuplot charts");
  auto o = std::make_shared<BenchOptions>();
  cmd->add_option("--materials", o->materials,
                  "Comma-separated: btf-datagen presets by name, or any material file or spec the other verbs open "
                  "(an RGL .bsdf, a MERL .binary, a fit .json, merl-fit:MODEL:NAME, ...)");
  cmd->add_flag("--quick", o->quick, "Tiny tables and few draws (seconds; for tests)");
  cmd->add_flag("--as-tables", o->as_tables,
                "Tabulate every material into the MERL layout first (an RGL file or a fit as a measured table: no "
                "sampler then starts from the material's own parameterization)");
  cmd->add_option("--theta-o", o->theta_o, "Outgoing zenith angles of the measurements (deg, comma-separated)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--parameterizations", o->parameterizations,
                  "Parameterizations of the tabulated samplers (comma-separated: incident, half, auto)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random seed")->capture_default_str();
  cmd->add_option("--epsilons", o->epsilons, "DP-CDF tolerances (default 1e-3,3e-3,1e-2)")->delimiter(',');
  cmd->add_option("--thresholds", o->thresholds, "Quadtree max/mean thresholds (default 2,8)")->delimiter(',');
  cmd->add_option("--samplers", o->samplers,
                  "Table samplers to measure (comma-separated: tabulated, dp-cdf, quadtree, dj-warp: the Dupuy-Jakob warp "
                  "of the material written as an RGL file); the uniform, cosine and material's own samplers always run")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--theta-o-bins", o->theta_o_bins, "theta_o bins of the tables (default: the library's, 32)");
  cmd->add_option("--half-vector-bins", o->half_vector_bins,
                  "Rows and columns of the half-vector tables (default: the library's, 128)");
  cmd->add_option("-o,--output", o->output, "Output folder (sampling.csv and the charts)")->required();
  cmd->callback([o] { runBenchSampling(*o); });
  addBenchBonnCommand(*bench);
  addBenchCompressionCommand(*bench);
  addBenchCompressibilityCommand(*bench);
  addBenchDecodeCommand(*bench);
  addBenchFitsCommand(*bench);
  addBenchRenderCommand(*bench);
  addBenchRglWriterCommand(*bench);
}

}  // namespace btf::cli
