// `btf fit IN --model M -o params.json`: an analytic model fitted to a measured table with Ceres
// (fit/analytic_fit.h), or to a BTF texel (`--texel X,Y`; without it, the mean over the texels).
// Prints the fit's parameters, whether it converged, its rel_rmse against the data, and its
// directional albedo beside the data's; writes the model as a material file.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/core/btf_view_set.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/btf_texel.h"
#include "btf/fit/fit_file.h"
#include "btf/material/albedo.h"
#include "btf/material/btf_material.h"
#include "btf/material/tabulated_brdf.h"
#include "comma_list.h"
#include "fit_scene_candidates.h"
#include "material_input.h"
#include "commands.h"

namespace btf::cli {
namespace {

constexpr float kAlbedoAnglesDeg[] = {0.0f, 30.0f, 60.0f, 75.0f};
constexpr std::uint32_t kBtfAlbedoSamples = 1u << 18;

struct FitCommandOptions {
  std::string in, out;
  // The library's default fit (AnalyticFitOptions): one place decides it.
  std::string model = modelFamilyName(AnalyticFitOptions{}.family), objective = fitObjectiveName(AnalyticFitOptions{}.objective);
  std::vector<int> texel;  // empty, or x and y
  int lobes = 1, starts = 6, iterations = 100;
  bool per_channel = false, json = false, strict = false, no_energy = false;
  double energy_weight = 1.0;
  std::string candidates = "ggx,abc,ggx2,sgd";  // --model auto, smallest first
  double auto_tolerance = 0.1;
  bool model_given = false;  // --model named: that family alone, without the default's fallback
};

std::string rgbText(const Rgb& c) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.4g, %.4g, %.4g)", c.r, c.g, c.b);
  return text;
}

std::string parameterText(const AnalyticParameters& p) {
  std::string text = "diffuse " + rgbText(p.diffuse);
  if (p.family == ModelFamily::Ggx || p.family == ModelFamily::Ggx2)
    text += ", f0 " + rgbText(p.specular) + ", alpha " + std::to_string(p.alpha);
  if (p.family == ModelFamily::Ggx2)
    text += ", second lobe f0 " + rgbText(p.specular_2) + ", alpha " + std::to_string(p.alpha_2);
  if (p.family == ModelFamily::Ward) text += ", specular " + rgbText(p.specular) + ", alpha " + std::to_string(p.alpha);
  if (p.family == ModelFamily::Sgd) {
    const SgdChannel& g = p.sgd_shape;
    char shape[200];
    std::snprintf(shape, sizeof shape, ", rho_s %s, alpha %.4g, p %.4g, f0 %.4g, f1 %.4g, lambda %.4g, c %.4g, k %.4g",
                  rgbText(p.specular).c_str(), g.alpha, g.p, g.f0, g.f1, g.lambda, g.c, g.k);
    text += shape;
  }
  if (p.family == ModelFamily::Abc)
    text += ", A " + rgbText(p.specular) + ", B " + std::to_string(p.abc_b) + ", C " + std::to_string(p.abc_c) + ", ior " +
            std::to_string(p.abc_ior);
  for (const LafortuneLobe& l : p.lobes) {
    char lobe[160];
    std::snprintf(lobe, sizeof lobe, "\n    lobe rho %s, c (%.4g, %.4g, %.4g), n %.4g", rgbText(l.rho).c_str(), l.c.x, l.c.y, l.c.z,
                  l.exponent);
    text += lobe;
  }
  return text;
}

// The data a fit is made to: a measured table, or a BTF texel (a one-texel BTF and its
// measurements). `data` is the data as a material, for its albedo: a table's interpolated lookup,
// or a BTF's interpolation between its 81 directions, 15 degrees apart, which spreads any lobe
// narrower than that (its albedo is then only what the BTF shows as a material).
struct FitData {
  std::shared_ptr<const MerlTable> table;
  std::vector<MeasuredReflectance> measurements;
  std::shared_ptr<const Material> data;
  std::optional<BtfViewSet> views;  // a BTF's views: its albedo only where the view was measured
  std::string description;          // what the report names as fitted
};

FitData loadFitData(const FitCommandOptions& o) {
  FitData d;
  const IdentifiedMaterial material = identifyMaterial(o.in);
  if (isBtf(material)) {
    const BtfInput input = openBtfInput(material);
    std::optional<glm::ivec2> texel;
    if (!o.texel.empty()) {
      texel = glm::ivec2(o.texel[0], o.texel[1]);
      if (const auto problem = texelOutside(*input.source, *texel)) throw FileError(o.in, *problem);
    }
    auto one = std::make_shared<BtfData>(btfTexel(*input.source, texel));
    d.measurements = texelMeasurements(*one);
    d.views = one->views();
    d.description = o.in + (texel ? " texel (" + std::to_string(texel->x) + ", " + std::to_string(texel->y) + ")"
                                  : " (mean over its " + std::to_string(input.source->texelCount()) + " texels)");
    try {
      d.data = std::make_shared<BtfMaterial>(one);
    } catch (const Error&) {
      // A partial BTF whose views are not whole rings: its albedo is left out.
    }
    return d;
  }
  if (!o.texel.empty()) throw FileError(o.in, "--texel is for BTFs (an image folder or a .btfz); this is a table");
  if (material.type->name == "fitted") throw FileError(o.in, "is a fitted model already; fit a measured table");
  d.table = std::make_shared<const MerlTable>(materialTable(material));
  d.data = std::make_shared<TabulatedBrdf>(d.table, TableLookup::Interpolated);
  d.description = o.in;
  return d;
}

// --model auto: the candidates, each a fit spec (family[:lobes][:linear|log]), with the command's
// starts, iterations and energy weight.
std::vector<AnalyticFitOptions> autoCandidates(const FitCommandOptions& o) {
  std::vector<AnalyticFitOptions> list;
  for (const std::string& spec : splitCommaList(o.candidates)) {
    AnalyticFitOptions c = parseFitSpec(spec);
    c.starts = o.starts;
    c.max_iterations = o.iterations;
    c.energy_weight = o.no_energy ? 0.0 : o.energy_weight;
    c.fallback.reset();  // auto compares the candidates themselves
    list.push_back(c);
  }
  if (list.empty()) throw Error("--model auto: --candidates lists no model");
  return list;
}

std::string specLabel(const AnalyticFitOptions& c) {
  std::string label = modelFamilyName(c.family);
  if (c.family == ModelFamily::Lafortune) label += ":" + std::to_string(c.lobes);
  if (c.objective == FitObjective::Linear) label += ":linear";
  return label;
}

nlohmann::json candidatesJson(const std::optional<AutoFit>& automatic) {
  if (!automatic) return nullptr;
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < automatic->tried.size(); ++k) {
    const AnalyticFit& f = automatic->tried[k];
    nlohmann::json errors = nlohmann::json::array();
    for (const AlbedoCheck& a : f.report.albedo) errors.push_back({{"theta_o_deg", a.theta_o_deg}, {"rel_error", a.rel_error}});
    list.push_back({{"model", modelFamilyName(f.parameters.family)}, {"rel_rmse", f.report.rel_rmse},
                    {"albedo_errors", errors}, {"kept", k == automatic->chosen_index}});
  }
  return list;
}

void runFit(const FitCommandOptions& o) {
  AnalyticFitOptions options;
  std::vector<AnalyticFitOptions> candidates;
  if (o.model == "auto") {
    candidates = autoCandidates(o);
    options = candidates.front();
  } else {
    options.family = parseModelFamily(o.model, kFittableFamilies);
    if (o.model_given) options.fallback.reset();
  }
  options.lobes = o.lobes;
  options.per_channel = o.per_channel;
  options.starts = o.starts;
  options.max_iterations = o.iterations;
  options.objective = parseFitObjective(o.objective);
  if (std::filesystem::path(o.out).extension() != ".json") throw FileError(o.out, "the fit is written as JSON: give a .json name");
  if (o.no_energy) options.energy_weight = 0;
  else options.energy_weight = o.energy_weight;
  const FitData d = loadFitData(o);
  std::optional<AutoFit> automatic;
  if (!candidates.empty() && !d.table)
    throw FileError(o.in, "--model auto chooses among fits to a table; fit a BTF texel with one --model");
  AnalyticFit fit;
  try {  // the library's refusals of the data name no file: this one does
    if (!candidates.empty()) automatic = fitSmallestModel(*d.table, candidates, o.auto_tolerance);
    fit = automatic ? automatic->chosen : d.table ? fitAnalytic(*d.table, options) : fitAnalytic(d.measurements, options);
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(o.in, e.what());
  }

  nlohmann::json albedo = nlohmann::json::array();
  for (float deg : kAlbedoAnglesDeg) {
    const float theta = deg * kPi / 180.0f;
    const Rgb a_fit = integrateAlbedoHalfVector(*fit.material, theta);
    nlohmann::json data = nullptr;
    const std::optional<int> view = findBtfDirection(deg, 0.0f);
    if (d.data && (!d.views || (view && d.views->contains(*view)))) {
      // A BTF texel is anisotropic in general: its albedo at (theta_o, phi_o = 0) by Monte Carlo with
      // its own (exact) sampler, where a table takes the isotropic quadrature.
      const Rgb a_data = d.views ? estimateAlbedo(*d.data, glm::vec3(std::sin(theta), 0.0f, std::cos(theta)), kBtfAlbedoSamples).value
                                 : integrateAlbedoHalfVector(*d.data, theta);
      data = {a_data.r, a_data.g, a_data.b};
    }
    nlohmann::json error = nullptr;
    if (!data.is_null()) {
      const AlbedoCheck check = albedoCheck(deg, Rgb(data[0].get<float>(), data[1].get<float>(), data[2].get<float>()), a_fit);
      error = check.rel_error;
      // A BTF texel's albedo checks are the command's (the library's report has them for tables).
      if (d.views && std::find(kAlbedoCheckAnglesDeg.begin(), kAlbedoCheckAnglesDeg.end(), deg) != kAlbedoCheckAnglesDeg.end())
        fit.report.albedo.push_back(check);
    }
    albedo.push_back({{"theta_o_deg", deg}, {"data", data}, {"fit", {a_fit.r, a_fit.g, a_fit.b}}, {"rel_error", error}});
  }
  if (d.views) fit.report.warnings = fitWarnings(fit.report);
  const AnalyticFitReport& r = fit.report;
  if (o.strict && !r.warnings.empty()) {
    std::string all;
    for (const std::string& w : r.warnings) all += (all.empty() ? "" : "; ") + w;
    throw FileError(o.in, "the fit is not good enough (--strict): " + all + "; nothing was written");
  }
  writeFitFile(o.out, fit, d.description);
  if (o.json) {
    std::cout << nlohmann::json{{"file", o.in},   {"data", d.description}, {"output", o.out}, {"model", o.model}, {"objective", o.objective},
                                {"rel_rmse", r.rel_rmse}, {"converged", r.converged}, {"starts", r.starts},
                                {"screening_converged", r.screening_converged}, {"iterations", r.iterations},
                                {"samples", r.samples}, {"excluded", r.excluded}, {"seconds", r.seconds},
                                {"energy_weight", r.energy_weight}, {"albedo", albedo}, {"warnings", r.warnings},
                                {"fallback", r.fallback.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.fallback)},
                                {"candidates", candidatesJson(automatic)}}
                     .dump(2)
              << '\n';
    return;
  }
  std::printf("%s fitted to %s, %s objective: %zu %s (%zu unmeasured or below the horizon, left out)\n",
              fit.material->name().c_str(), d.description.c_str(), o.objective.c_str(), r.samples, d.table ? "cells of the fitting grid" : "measurements", r.excluded);
  std::printf("  %s\n", parameterText(fit.parameters).c_str());
  if (!r.fallback.empty()) std::printf("  default fit: %s\n", r.fallback.c_str());
  std::printf("  final solve %s after %d iterations, %.1f s; %d starts screened (15 iterations on a fifth of the %s), "
              "%d of them converged there\n",
              r.converged ? "converged" : "did NOT converge", r.iterations, r.seconds, r.starts,
              d.table ? "cells" : "measurements", r.screening_converged);
  if (r.energy_weight > 0 && d.table) {
    std::string angles;
    for (const float deg : kEnergyAnglesDeg) angles += (angles.empty() ? "" : "/") + std::to_string(int(deg));
    std::printf("  energy term: albedo at theta_o %s deg held to the data's, weight %g%s\n", angles.c_str(), r.energy_weight,
                r.energy_weight > options.energy_weight ? " (raised: the albedo missed at the weight asked for)" : "");
  }
  std::printf("  rel_rmse of f cos(theta_i) over the %s: %.4f\n", d.table ? "table" : "measurements", r.rel_rmse);
  std::printf("  albedo (mean of RGB)  ");
  for (float deg : kAlbedoAnglesDeg) std::printf("  %5.0f deg", double(deg));
  std::printf("\n");
  for (const char* which : {"data", "fit"}) {
    std::printf("    %-19s", std::string(which) == "data" && d.views ? "btf (interpolated)" : which);
    for (const auto& a : albedo) {
      if (a[which].is_null()) std::printf("  %9s", "n/a");
      else std::printf("  %9.4f", (a[which][0].get<double>() + a[which][1].get<double>() + a[which][2].get<double>()) / 3.0);
    }
    std::printf("\n");
  }
  std::printf("    %-19s", "fit / data - 1");
  for (const auto& a : albedo) {
    if (a["rel_error"].is_null()) std::printf("  %9s", "n/a");
    else {
      const double data = a["data"][0].get<double>() + a["data"][1].get<double>() + a["data"][2].get<double>();
      const double fitted = a["fit"][0].get<double>() + a["fit"][1].get<double>() + a["fit"][2].get<double>();
      std::printf("  %+8.1f%%", data > 0 ? 100.0 * (fitted / data - 1.0) : 0.0);
    }
  }
  std::printf("\n");
  if (automatic) {
    std::printf("  --model auto kept %s: %s\n", specLabel(candidates[automatic->chosen_index]).c_str(),
                automatic->reason.c_str());
    for (std::size_t k = 0; k < automatic->tried.size(); ++k) {
      double worst = 0;
      for (const AlbedoCheck& a : automatic->tried[k].report.albedo) worst = std::max(worst, a.rel_error);
      std::printf("    %-16s rel_rmse %.4f, largest albedo error %5.1f%%, %.1f s%s\n", specLabel(candidates[k]).c_str(),
                  automatic->tried[k].report.rel_rmse, 100.0 * worst, automatic->tried[k].report.seconds,
                  k == automatic->chosen_index ? "  <- kept" : "");
    }
  }
  std::printf("wrote %s\n", o.out.c_str());
  for (const std::string& w : r.warnings) std::fprintf(stderr, "btf: warning: %s: %s\n", o.in.c_str(), w.c_str());
  if (!r.converged) std::fprintf(stderr, "btf: the final solve's Ceres report:\n%s\n", r.ceres_report.c_str());
}

}  // namespace

void registerFitCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit an analytic model (abc, sgd, ggx, ggx2, ward or lafortune with 1-3 lobes) to a measured table or a BTF texel with Ceres; by default "
      "least squares of f cos theta_i within 80 degrees (the rel_rmse reported) plus an energy term that holds the albedo, or, --objective log, "
      "a loss robust on ln(1 + f cos theta_i); unmeasured cells left out. Writes the model as JSON, usable as a material by info, eval, plot, "
      "sample and in scenes ({\"type\": \"fitted\", \"file\": ...})");
  auto o = std::make_shared<FitCommandOptions>();
  cmd->add_option("IN", o->in, "Measured table (.binary, .exr stack, .bsdf, .octree) or BTF (image folder, .btfz)")->required();
  cmd->add_option("-o,--output", o->out, "The fitted model (.json), written atomically")->required();
  auto* model = cmd->add_option("--model", o->model,
                  "Default: abc, and where its fit is degenerate (a parameter at a bound, or rel_rmse above 0.5) sgd too, "
                  "the closer kept. abc (Low 2012, as the published MERL fits), sgd (Bagher 2012, one lobe shape for all channels), ggx, ggx2 "
                  "(two GGX lobes over the diffuse term), ward, lafortune, or auto (the smallest of --candidates that fits as "
                  "well as any of them and keeps the albedo); a model named is fitted alone")
      ->check(CLI::IsMember({"abc", "sgd", "ggx", "ggx2", "ward", "lafortune", "auto"}))
      ->capture_default_str();
  cmd->add_option("--candidates", o->candidates,
                  "--model auto: the models to try, smallest first, each family[:lobes][:linear|log]")
      ->capture_default_str();
  cmd->add_option("--auto-tolerance", o->auto_tolerance,
                  "--model auto: keep the first candidate whose rel_rmse is within this fraction of the best one's")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--lobes", o->lobes, "Lafortune lobes (1-3)")->check(CLI::Range(1, 3))->capture_default_str();
  cmd->add_option("--texel", o->texel, "BTF: fit texel X,Y (default: the mean over all texels)")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--objective", o->objective,
                  "linear: least squares of f cos within 80 degrees (the rel_rmse reported), which follows tall narrow highlights; "
                  "log: robust on ln(1 + f cos), every part of the lobe counts")
      ->check(CLI::IsMember({"log", "linear"}))
      ->capture_default_str();
  cmd->add_flag("--per-channel", o->per_channel, "Lafortune: each channel its own lobes (else shared lobes, RGB weights)");
  cmd->add_option("--starts", o->starts, "Initial guesses spread over the shape parameters")->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--iterations", o->iterations, "Levenberg-Marquardt iterations per start")->check(CLI::Range(1, 10000))->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the report as JSON (albedo and its error per angle, warnings)");
  cmd->add_flag("--strict", o->strict,
                "Make the warnings errors: an albedo more than 10% off the data's at theta_o 0, 30 or 60 deg, rel_rmse above 0.5, "
                "a parameter at a bound of the search (a degenerate fit), or a final solve that did not converge; nothing is "
                "written then");
  cmd->add_option("--energy-weight", o->energy_weight,
                  "Weight of the energy term, which holds the fit's albedo at theta_o 0-75 deg to the data's (tables)")
      ->check(CLI::Range(0.0, 1e3))
      ->capture_default_str();
  cmd->add_flag("--no-energy", o->no_energy, "Leave the energy term out (the objective alone)");
  cmd->callback([o, model] {
    o->model_given = model->count() > 0;
    runFit(*o);
  });
}

}  // namespace btf::cli
