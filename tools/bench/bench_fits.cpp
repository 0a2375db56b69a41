// `btf bench fits [-o DIR]`: our Ceres fits (fit/analytic_fit.h) side by side with the published
// fits of the MERL materials (io/merl_fits.h: SGD, ABC, one-lobe Lafortune), on tables made from
// those fits. For every material and every published model that fits it (the reference), the
// reference is tabulated into the MERL layout (as `btf-datagen --merl-fit NAME:MODEL --clean`),
// our models are fitted to that table, and every model, the published ones and ours, is measured
// on it by tableRelRmse (the measure of `btf fit`). The reference's own row is 0 by construction
// (the table holds its values at the cells' directions, where tableRelRmse evaluates): a check
// that the table is the reference. Each published fit was made to the real measurement, not to
// another model's table, so this shows how far the models are from each other's shapes, and where
// ours stand among them; it does not rank the published fits on MERL's own data.
//   DIR/fits.csv                    one row per (material, reference, model): rel_rmse, and for our
//                                   fits converged and seconds
//   DIR/fits_<reference>.png/.svg   per reference, every model's rel_rmse per material, materials
//                                   sorted by the best other model's error; fits_charts.gp
//   stdout                          per reference and model: median and 90th percentile of rel_rmse,
//                                   and in how many materials it beats each of our fits
// With --tables, the data are measured-style tables instead (a folder of MERL .binary files, e.g.
// the MERL-like tables of ../shared/tools/nbrdf-to-merl, and any RGL .bsdf files, each tabulated
// into the MERL layout): the reference is "data", the published fits of a table named after a
// MERL material are measured beside ours, and each row also holds the largest error of the
// model's directional albedo (mean of RGB) against the data's at theta_o 0, 30 and 60 deg:
//   DIR/fits_vs_albedo.png/.svg     per model, rel_rmse against that albedo error per table
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <optional>
#include <vector>

#include <tbb/global_control.h>

#include "bench_fits.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/fit/analytic_fit.h"
#include "btf/io/atomic_file.h"
#include "btf/fit/merl_fits.h"
#include "btf/core/math.h"
#include "btf/material/albedo.h"
#include "btf/material/registry.h"
#include "btf/material/tabulated_brdf.h"
#include "comma_list.h"
#include "gnuplot_charts.h"
#include "merl_fit_report.h"

namespace btf::cli {
// Named after the file: the unity build compiles the commands together, and their helpers share
// names (Args, Row).
namespace bench_fits {
namespace {

struct Args {
  std::string output = "bench-fits";
  std::string materials;  // comma-separated; empty: the 100 MERL materials
  std::string references = "sgd,abc,lafortune";
  std::string models = "abc,ggx,lafortune";  // ours; lafortune with one lobe, as Ngan's
  std::string objectives = fitObjectiveName(AnalyticFitOptions{}.objective);  // each model with each objective
  std::string fits_dir;
  std::vector<std::string> tables;  // files or folders of measured-style tables; empty: the published fits' tables
  int starts = 6;
  int threads = 0;  // 0: all cores; 1 measures the time goal of one core per fit
};

// One model measured on one table.
struct Row {
  std::string material, reference, model;  // model: a published name, or "ours:ggx" etc.
  double rel_rmse = 0;
  bool ours = false, converged = true;
  double seconds = 0;
  double albedo_error = -1;  // --tables: the largest albedo error at theta_o 0/30/60 (mean of RGB); -1: not measured
};

// One of our models: a family fitted alone, or (nullopt) the library's default fit, `btf fit`'s
// without --model (abc, with its fallback where abc degenerates).
using OurModel = std::optional<ModelFamily>;

// "ours:ggx" for the default objective (the library's), "ours:ggx:log" for the other one;
// "ours:default" for the default fit.
std::string ourName(OurModel family, FitObjective objective) {
  return std::string("ours:") + (family ? modelFamilyName(*family) : "default") +
         (objective == AnalyticFitOptions{}.objective ? "" : std::string(":") + fitObjectiveName(objective));
}

void writeCsv(const std::filesystem::path& path, const std::vector<Row>& rows) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    out << "material,reference,model,ours,rel_rmse,albedo_error,converged,seconds\n";
    for (const Row& r : rows) {
      out << r.material << ',' << r.reference << ',' << r.model << ',' << (r.ours ? 1 : 0) << ',' << r.rel_rmse << ',';
      if (r.albedo_error >= 0) out << r.albedo_error;
      out << ',' << (r.converged ? 1 : 0) << ',' << r.seconds << '\n';
    }
  });
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

// rel_rmse per (reference, model) and material.
using ErrorTable = std::map<std::string, std::map<std::string, std::map<std::string, double>>>;

ErrorTable tabulateRows(const std::vector<Row>& rows) {
  ErrorTable t;
  for (const Row& r : rows) t[r.reference][r.model][r.material] = r.rel_rmse;
  return t;
}

void printSummary(const ErrorTable& table, const std::vector<std::string>& ours) {
  for (const auto& [reference, models] : table) {
    std::printf("\ntables from the %s fits: rel_rmse of f cos(theta_i) (the reference's own is 0 by construction)\n",
                reference.c_str());
    int width = 16;  // the model column, as wide as its longest name
    for (const auto& [model, by_material] : models) width = std::max(width, int(model.size()));
    std::printf("  %-*s %9s %8s %8s", width, "model", "materials", "median", "p90");
    for (const std::string& o : ours) std::printf("  %15s", ("beats " + o).c_str());
    std::printf("\n");
    for (const auto& [model, by_material] : models) {
      std::vector<double> values;
      for (const auto& [m, v] : by_material) values.push_back(v);
      std::printf("  %-*s %9zu %8.4f %8.4f", width, model.c_str(), values.size(), quantile(values, 0.5), quantile(values, 0.9));
      for (const std::string& o : ours) {
        if (o == model) {
          std::printf("  %15s", "-");
          continue;
        }
        const auto it = models.find(o);
        int wins = 0, compared = 0;
        if (it != models.end())
          for (const auto& [m, v] : by_material)
            if (const auto other = it->second.find(m); other != it->second.end()) {
              ++compared;
              wins += v < other->second;
            }
        std::printf("  %9d of %3d", wins, compared);
      }
      std::printf("\n");
    }
  }
}

tools::GnuplotOutcome drawCharts(const std::filesystem::path& folder, const ErrorTable& table) {
  std::ostringstream data;
  std::vector<tools::GnuplotChart> charts;
  int block = 0;
  for (const auto& [reference, models] : table) {
    // Materials ordered by the best model other than the reference (whose own error is 0, off
    // the log scale), so that the lower envelope rises left to right.
    std::map<std::string, double> order_key;
    for (const auto& [model, by_material] : models) {
      if (model == reference) continue;
      for (const auto& [m, v] : by_material) {
        auto [it, inserted] = order_key.emplace(m, v);
        if (!inserted) it->second = std::min(it->second, v);
      }
    }
    std::vector<std::string> materials;
    for (const auto& [m, key] : order_key) materials.push_back(m);
    std::stable_sort(materials.begin(), materials.end(), [&](const std::string& a, const std::string& b) { return order_key[a] < order_key[b]; });
    std::ostringstream body;
    body << "set title " << tools::gnuplotQuote("Fits to MERL-layout tables of the published " + reference +
                                                " fits: rel_rmse of f cos per material") << "\n"
         << "set logscale y\nset xlabel 'material (sorted by the best fit other than the reference)'\n"
         << "set ylabel 'rel_rmse of f cos(theta_i), within 80 degrees (log scale)'\nset key top left\n"
         << "set xrange [-1:" << materials.size() << "]\nplot ";
    int series = 0;
    for (const auto& [model, by_material] : models) {
      data << "$b" << block << " << EOD\n";
      for (std::size_t i = 0; i < materials.size(); ++i)
        if (const auto it = by_material.find(materials[i]); it != by_material.end() && it->second > 0)
          data << i << ' ' << it->second << '\n';
      data << "EOD\n";
      const bool ours = model.rfind("ours:", 0) == 0;
      body << (series++ ? ", " : "") << "$b" << block << " using 1:2 with " << (ours ? "linespoints pt 7 ps 0.6" : "points pt 6 ps 0.7")
           << " title " << tools::gnuplotQuote(model);
      ++block;
    }
    body << '\n';
    charts.push_back({"fits_" + reference, body.str()});
  }
  return tools::drawGnuplotCharts(folder, "fits_charts.gp", data.str(), charts);
}

// One of our fits, with the library's defaults but the family, objective and starts.
AnalyticFit ourFit(const MerlTable& table, OurModel family, FitObjective objective, int starts) {
  AnalyticFitOptions options;
  if (family) {
    options.family = *family;
    options.fallback.reset();  // each model as its label names it, alone
  }
  options.starts = starts;
  options.objective = objective;
  return fitAnalytic(table, options);
}

// The measured-style tables of --tables: every .binary and .bsdf file named, or found in a named
// folder, by name.
std::vector<std::filesystem::path> tableFiles(const std::vector<std::string>& named) {
  std::vector<std::filesystem::path> files;
  for (const std::string& n : named) {
    const std::filesystem::path p(n);
    if (std::filesystem::is_directory(p)) {
      std::vector<std::filesystem::path> found;
      for (const auto& e : std::filesystem::directory_iterator(p))
        if (e.path().extension() == ".binary" || e.path().extension() == ".bsdf") found.push_back(e.path());
      std::sort(found.begin(), found.end());
      if (found.empty()) throw FileError(p, "holds no .binary or .bsdf table");
      files.insert(files.end(), found.begin(), found.end());
    } else {
      requireReadableFile(p);
      files.push_back(p);
    }
  }
  return files;
}

// The largest relative error of the model's albedo (mean of RGB) at kAlbedoCheckAnglesDeg.
double albedoError(const Material& model, const std::vector<Rgb>& data_albedo) {
  double worst = 0;
  for (std::size_t k = 0; k < kAlbedoCheckAnglesDeg.size(); ++k) {
    const Rgb fit = integrateAlbedoHalfVector(model, kAlbedoCheckAnglesDeg[k] * kPi / 180.0f);
    worst = std::max(worst, albedoCheck(kAlbedoCheckAnglesDeg[k], data_albedo[k], fit).rel_error);
  }
  return worst;
}

void printTableSummary(const std::vector<Row>& rows) {
  std::map<std::string, std::vector<const Row*>> by_model;
  for (const Row& r : rows) by_model[r.model].push_back(&r);
  // The best published rel_rmse per table, for "beats the best published".
  std::map<std::string, double> best_published;
  for (const Row& r : rows)
    if (!r.ours) {
      auto [it, inserted] = best_published.emplace(r.material, r.rel_rmse);
      if (!inserted) it->second = std::min(it->second, r.rel_rmse);
    }
  std::printf("\nmeasured-style tables: rel_rmse of f cos(theta_i), and the albedo (mean of RGB) against the data's at "
              "theta_o 0, 30, 60 deg\n");
  std::printf("  %-22s %7s %8s %8s %18s %22s %9s\n", "model", "tables", "median", "p90", "albedo within 10%",
              "<= best published", "rel>1");
  for (const auto& [model, list] : by_model) {
    std::vector<double> errors;
    int albedo_ok = 0, beats = 0, compared = 0, above_one = 0;
    for (const Row* r : list) {
      errors.push_back(r->rel_rmse);
      albedo_ok += r->albedo_error >= 0 && r->albedo_error <= kFitAlbedoTolerance;
      above_one += r->rel_rmse > 1.0;
      if (const auto it = best_published.find(r->material); r->ours && it != best_published.end()) {
        ++compared;
        beats += r->rel_rmse <= it->second;
      }
    }
    char vs[32] = "-";
    if (compared) std::snprintf(vs, sizeof vs, "%d of %d", beats, compared);
    std::printf("  %-22s %7zu %8.4f %8.4f %11d of %3zu %22s %9d\n", model.c_str(), list.size(), quantile(errors, 0.5),
                quantile(errors, 0.9), albedo_ok, list.size(), vs, above_one);
  }
}

tools::GnuplotOutcome drawTableChart(const std::filesystem::path& folder, const std::vector<Row>& rows) {
  std::map<std::string, std::vector<const Row*>> by_model;
  for (const Row& r : rows) by_model[r.model].push_back(&r);
  std::ostringstream data, body;
  body << "set title 'Fits to measured-style tables: shape error against energy error, one point per table'\n"
       << "set logscale xy\nset xlabel 'largest albedo error at theta_o 0/30/60 deg (|fit / data - 1|)'\n"
       << "set ylabel 'rel_rmse of f cos(theta_i)'\nset key outside right\n"
       << "set arrow from 0.1, graph 0 to 0.1, graph 1 nohead dt 2\nplot ";
  int block = 0;
  for (const auto& [model, list] : by_model) {
    data << "$t" << block << " << EOD\n";
    for (const Row* r : list) data << std::max(r->albedo_error, 1e-4) << ' ' << std::max(r->rel_rmse, 1e-4) << '\n';
    data << "EOD\n";
    body << (block ? ", " : "") << "$t" << block << " using 1:2 with points pt 7 ps 0.8 title " << tools::gnuplotQuote(model);
    ++block;
  }
  body << '\n';
  return tools::drawGnuplotCharts(folder, "fits_vs_albedo.gp", data.str(), {{"fits_vs_albedo", body.str()}});
}

// --tables: every table fitted by our models, and measured against the published fits of its
// MERL material where its name is one.
void runBenchFitsOnTables(const Args& args, const MerlFits& fits, const std::vector<OurModel>& ours,
                          const std::vector<FitObjective>& objectives) {
  const std::vector<std::filesystem::path> files = tableFiles(args.tables);
  std::filesystem::create_directories(args.output);
  std::vector<Row> rows;
  Progress progress("fitting", files.size());
  for (const std::filesystem::path& file : files) {
    const std::string name = file.stem().string();
    const MerlTable table = materialTable(identifyMaterial(file.string()));
    const TabulatedBrdf data(std::make_shared<const MerlTable>(table), TableLookup::Interpolated);
    std::vector<Rgb> data_albedo;
    for (const float deg : kAlbedoCheckAnglesDeg) data_albedo.push_back(integrateAlbedoHalfVector(data, deg * kPi / 180.0f));
    std::string merl_name;
    try {
      merl_name = fits.resolve(name);
    } catch (const Error&) {
    }
    if (!merl_name.empty() && fits.isMerl(merl_name))
      for (ModelFamily published : fits.modelsFor(merl_name)) {
        const auto model = makeMerlFitMaterial(fits, merl_name, published);
        rows.push_back({name, "data", modelFamilyName(published), tableRelRmse(*model, table), false, true, 0.0,
                        albedoError(*model, data_albedo)});
      }
    for (OurModel family : ours)
      for (FitObjective objective : objectives) {
        const AnalyticFit fit = ourFit(table, family, objective, args.starts);
        rows.push_back({name, "data", ourName(family, objective), fit.report.rel_rmse, true, fit.report.converged,
                        fit.report.seconds, albedoError(*fit.material, data_albedo)});
        std::printf("%-28s %-22s rel_rmse %8.4f  albedo error %6.1f%%  %5.1f s%s\n", name.c_str(), rows.back().model.c_str(),
                    rows.back().rel_rmse, 100.0 * rows.back().albedo_error, rows.back().seconds,
                    fit.report.converged ? "" : "  (final solve did not converge)");
        std::fflush(stdout);
      }
    progress.advance();
  }
  const std::filesystem::path csv = std::filesystem::path(args.output) / "fits.csv";
  writeCsv(csv, rows);
  printTableSummary(rows);
  const tools::GnuplotOutcome chart = drawTableChart(args.output, rows);
  std::printf("\nwrote %s", csv.string().c_str());
  for (const auto& f : chart.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!chart.message.empty()) std::printf("%s\n", chart.message.c_str());
}

void runBenchFits(const Args& args) {
  std::optional<tbb::global_control> limit;  // the fits' results do not depend on it, their seconds do
  if (args.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(args.threads));
  const MerlFits fits = loadMerlFits(args.fits_dir);
  std::vector<std::string> materials;
  if (args.materials.empty()) {
    for (const std::string& name : fits.names())
      if (fits.isMerl(name)) materials.push_back(name);
  } else {
    for (const std::string& name : splitCommaList(args.materials)) materials.push_back(fits.resolve(name));
  }
  std::vector<ModelFamily> references;
  for (const std::string& r : splitCommaList(args.references)) references.push_back(parseModelFamily(r, kPublishedFitFamilies));
  std::vector<OurModel> ours;
  for (const std::string& m : splitCommaList(args.models))
    ours.push_back(m == "default" ? OurModel() : OurModel(parseModelFamily(m, kFittableFamilies)));
  std::vector<FitObjective> objectives;
  for (const std::string& o : splitCommaList(args.objectives)) objectives.push_back(parseFitObjective(o));
  if (!args.tables.empty()) {
    if (ours.empty() || objectives.empty()) throw Error("bench fits: no models or objectives");
    return runBenchFitsOnTables(args, fits, ours, objectives);
  }
  if (materials.empty() || references.empty() || ours.empty() || objectives.empty())
    throw Error("bench fits: no materials, references, models or objectives");
  std::filesystem::create_directories(args.output);

  std::vector<Row> rows;
  Progress progress("fitting", std::uint64_t(materials.size() * references.size()));
  for (const std::string& material : materials) {
    const std::vector<ModelFamily> available = fits.modelsFor(material);
    for (ModelFamily reference : references) {
      if (std::find(available.begin(), available.end(), reference) == available.end()) {
        progress.advance();
        continue;
      }
      const MerlTable table = tabulate(*makeMerlFitMaterial(fits, material, reference));
      for (ModelFamily published : available)
        rows.push_back({material, modelFamilyName(reference), modelFamilyName(published),
                        tableRelRmse(*makeMerlFitMaterial(fits, material, published), table)});
      for (OurModel family : ours)
        for (FitObjective objective : objectives) {
          const AnalyticFit fit = ourFit(table, family, objective, args.starts);
          rows.push_back({material, modelFamilyName(reference), ourName(family, objective), fit.report.rel_rmse, true,
                          fit.report.converged, fit.report.seconds});
        }
      progress.advance();
    }
  }
  const std::filesystem::path csv = std::filesystem::path(args.output) / "fits.csv";
  writeCsv(csv, rows);
  std::vector<std::string> our_names;
  for (OurModel family : ours)
    for (FitObjective objective : objectives) our_names.push_back(ourName(family, objective));
  const ErrorTable errors = tabulateRows(rows);
  printSummary(errors, our_names);
  const tools::GnuplotOutcome charts = drawCharts(args.output, errors);
  std::printf("\nwrote %s", csv.string().c_str());
  for (const auto& f : charts.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!charts.message.empty()) std::printf("%s\n", charts.message.c_str());
}

}  // namespace
}  // namespace bench_fits

void addBenchFitsCommand(CLI::App& bench) {
  auto args = std::make_shared<bench_fits::Args>();
  auto* cmd = bench.add_subcommand(
      "fits",
      "Our Ceres fits beside the published fits of the MERL materials (SGD, ABC, Lafortune), on MERL-layout tables "
      "made from each published fit: rel_rmse per material and model; CSV, summary and gnuplot charts");
  cmd->add_option("-o,--output", args->output, "Output folder (fits.csv, charts)")->capture_default_str();
  cmd->add_option("--materials", args->materials, "MERL names, comma-separated (default: the 100 MERL materials)");
  cmd->add_option("--references", args->references, "Published fits to tabulate as the tables (sgd, abc, lafortune)")
      ->capture_default_str();
  cmd->add_option("--models", args->models, "Our models to fit (abc, sgd, ggx, ggx2, ward, lafortune with one lobe; each alone), or default (btf fit's "
                  "default fit: abc, and sgd where abc degenerates)")->capture_default_str();
  cmd->add_option("--objectives", args->objectives, "Objectives of our fits, comma-separated (log, linear; see btf fit)")
      ->capture_default_str();
  cmd->add_option("--starts", args->starts, "Initial guesses per fit")->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores); 1 times each fit on one core")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--fits-dir", args->fits_dir, "Folder of the published fit tables (default: ../shared/data/real/fits)");
  cmd->add_option("--tables", args->tables,
                  "Measured-style tables instead: .binary or .bsdf files, or folders of them (a table named after a MERL "
                  "material is also measured against its published fits); adds albedo errors and fits_vs_albedo.png")
      ->delimiter(',');
  cmd->callback([args] { bench_fits::runBenchFits(*args); });
}

}  // namespace btf::cli
