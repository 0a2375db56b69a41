// `btf fit IN --model M -o params.json`: an analytic model fitted to a measured table with Ceres
// (fit/analytic_fit.h). Prints the fit's parameters, whether it converged, its rel_rmse against
// the table, and its directional albedo beside the data's; writes the model as a material file.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/fit_file.h"
#include "btf/material/albedo.h"
#include "btf/material/tabulated_brdf.h"
#include "commands.h"
#include "measured_file.h"

namespace btf::cli {
namespace {

constexpr float kAlbedoAnglesDeg[] = {0.0f, 30.0f, 60.0f, 75.0f};

struct FitCommandOptions {
  std::string in, out, model = "ggx";
  int lobes = 1, starts = 6, iterations = 100;
  bool per_channel = false, json = false;
};

std::string rgbText(const Rgb& c) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.4g, %.4g, %.4g)", c.r, c.g, c.b);
  return text;
}

std::string parameterText(const AnalyticParameters& p) {
  std::string text = "diffuse " + rgbText(p.diffuse);
  if (p.family == AnalyticFamily::Ggx) text += ", f0 " + rgbText(p.specular) + ", alpha " + std::to_string(p.alpha);
  if (p.family == AnalyticFamily::Ward) text += ", specular " + rgbText(p.specular) + ", alpha " + std::to_string(p.alpha);
  for (const LafortuneLobe& l : p.lobes) {
    char lobe[160];
    std::snprintf(lobe, sizeof lobe, "\n    lobe rho %s, c (%.4g, %.4g, %.4g), n %.4g", rgbText(l.rho).c_str(), l.c.x, l.c.y, l.c.z,
                  l.exponent);
    text += lobe;
  }
  return text;
}

void runFit(const FitCommandOptions& o) {
  AnalyticFitOptions options;
  options.family = parseAnalyticFamily(o.model);
  options.lobes = o.lobes;
  options.per_channel = o.per_channel;
  options.starts = o.starts;
  options.max_iterations = o.iterations;
  if (std::filesystem::path(o.out).extension() != ".json") throw FileError(o.out, "the fit is written as JSON: give a .json name");
  if (measuredFormatOf(o.in) == MeasuredFormat::FittedModel) throw FileError(o.in, "is a fitted model already; fit a measured table");
  const auto table = std::make_shared<const MerlTable>(loadMeasuredTable(o.in));
  const AnalyticFit fit = fitAnalytic(*table, options);
  writeFitFile(o.out, fit, o.in);

  const TabulatedBrdf data(table, TableLookup::Interpolated);
  nlohmann::json albedo = nlohmann::json::array();
  for (float deg : kAlbedoAnglesDeg) {
    const float theta = deg * kPi / 180.0f;
    const Rgb a_data = integrateAlbedoHalfVector(data, theta), a_fit = integrateAlbedoHalfVector(*fit.material, theta);
    albedo.push_back({{"theta_o_deg", deg}, {"data", {a_data.r, a_data.g, a_data.b}}, {"fit", {a_fit.r, a_fit.g, a_fit.b}}});
  }
  const AnalyticFitReport& r = fit.report;
  if (o.json) {
    std::cout << nlohmann::json{{"file", o.in},   {"output", o.out},       {"model", o.model},
                                {"rel_rmse", r.rel_rmse}, {"converged", r.converged}, {"starts", r.starts},
                                {"starts_converged", r.starts_converged}, {"iterations", r.iterations},
                                {"samples", r.samples}, {"excluded", r.excluded}, {"seconds", r.seconds},
                                {"albedo", albedo}}
                     .dump(2)
              << '\n';
    return;
  }
  std::printf("%s fitted to %s: %zu cells of the fitting grid (%zu unmeasured or below the horizon, left out)\n",
              fit.material->name().c_str(), o.in.c_str(), r.samples, r.excluded);
  std::printf("  %s\n", parameterText(fit.parameters).c_str());
  std::printf("  %s after %d iterations (%d of %d starts converged), %.1f s\n",
              r.converged ? "converged" : "NOT converged", r.iterations, r.starts_converged, r.starts, r.seconds);
  std::printf("  rel_rmse of f cos(theta_i) over the table: %.4f\n", r.rel_rmse);
  std::printf("  albedo (mean of RGB)  ");
  for (float deg : kAlbedoAnglesDeg) std::printf("  %5.0f deg", double(deg));
  std::printf("\n");
  for (const char* which : {"data", "fit"}) {
    std::printf("    %-19s", which);
    for (const auto& a : albedo) std::printf("  %9.4f", (a[which][0].get<double>() + a[which][1].get<double>() + a[which][2].get<double>()) / 3.0);
    std::printf("\n");
  }
  std::printf("wrote %s\n", o.out.c_str());
  if (!r.converged)
    std::fprintf(stderr, "btf: warning: the fit did not converge within %d iterations; Ceres says:\n%s\n", o.iterations,
                 r.ceres_report.c_str());
}

}  // namespace

void registerFitCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit an analytic model (ggx, ward or lafortune with 1-3 lobes) to a measured table with Ceres; the loss is robust on "
      "ln(1 + f cos theta_i), unmeasured cells left out. Writes the model as JSON, usable as a material by info, eval, plot, "
      "sample and in scenes ({\"type\": \"fitted\", \"file\": ...})");
  auto o = std::make_shared<FitCommandOptions>();
  cmd->add_option("IN", o->in, "Measured table (.binary, .exr stack or .bsdf)")->required();
  cmd->add_option("-o,--output", o->out, "The fitted model (.json), written atomically")->required();
  cmd->add_option("--model", o->model, "ggx, ward or lafortune")->check(CLI::IsMember({"ggx", "ward", "lafortune"}))->capture_default_str();
  cmd->add_option("--lobes", o->lobes, "Lafortune lobes (1-3)")->check(CLI::Range(1, 3))->capture_default_str();
  cmd->add_flag("--per-channel", o->per_channel, "Lafortune: each channel its own lobes (else shared lobes, RGB weights)");
  cmd->add_option("--starts", o->starts, "Initial guesses spread over the shape parameters")->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--iterations", o->iterations, "Levenberg-Marquardt iterations per start")->check(CLI::Range(1, 10000))->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the report as JSON");
  cmd->callback([o] { runFit(*o); });
}

}  // namespace btf::cli
