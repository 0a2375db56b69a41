#include "merl_fit_report.h"

#include "btf/core/error.h"
#include "btf/core/progress.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "btf/core/error.h"

namespace btf::datagen {
namespace fs = std::filesystem;

namespace {

std::string modelList(const MerlFits& fits, const std::string& name) {
  std::string s;
  for (ModelFamily m : fits.modelsFor(name)) {
    if (!s.empty()) s += ',';
    s += modelFamilyName(m);
  }
  return s;
}

}  // namespace

std::optional<MerlFitComparison> compareFitsOfFile(const std::filesystem::path& file, const std::string& name) {
  const std::string wanted = name.empty() ? file.stem().string() : name;
  std::optional<MerlFits> fits;
  try {
    fits = loadMerlFits();
  } catch (const Error& e) {
    log(LogLevel::Info, std::string("no comparison with published fits: ") + e.what());
    return std::nullopt;
  }
  std::string canonical;
  try {
    canonical = fits->resolve(wanted);
  } catch (const Error&) {
    if (name.empty()) return std::nullopt;  // a file not named after a MERL material
    throw;                                  // an explicit name that is no MERL material
  }
  return compareMerlFits(*fits, canonical, kFitDisagreementThreshold);
}

void listMerlFits(const MerlFits& fits, bool json) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : fits.names()) {
    nlohmann::json models = nlohmann::json::array();
    for (ModelFamily m : fits.modelsFor(name)) models.push_back(modelFamilyName(m));
    const SgdFit* sgd = fits.findSgd(name);
    const std::string other = sgd && sgd->other_name != name ? sgd->other_name : "";
    if (json) {
      out.push_back({{"name", name}, {"merl", fits.isMerl(name)}, {"models", models}, {"other_name", other}});
    } else {
      std::printf("%-26s %-18s%s%s\n", name.c_str(), modelList(fits, name).c_str(),
                  fits.isMerl(name) ? "" : "  (not in the MERL 100: Ngan et al.'s larger set)",
                  other.empty() ? "" : ("  also '" + other + "'").c_str());
    }
  }
  if (json) std::cout << out.dump(2) << "\n";
}

nlohmann::json comparisonJson(const MerlFitComparison& c) {
  nlohmann::json fits = nlohmann::json::array();
  for (const FitAlbedos& f : c.fits) {
    nlohmann::json albedo = nlohmann::json::array();
    for (const Rgb& a : f.albedo) albedo.push_back({a.r, a.g, a.b});
    fits.push_back({{"model", modelFamilyName(f.model)}, {"albedo", albedo}});
  }
  return {{"name", c.name},
          {"theta_o_deg", c.theta_o_deg},
          {"fits", fits},
          {"spread", c.spread},
          {"spread_theta_o_deg", c.spread_theta_o_deg},
          {"threshold", c.threshold},
          {"disagree", c.disagree}};
}

void printFitComparison(const MerlFitComparison& c) {
  std::printf("  albedo of the published fits of %s (mean RGB; r g b):\n", c.name.c_str());
  for (const FitAlbedos& f : c.fits) {
    std::printf("    %-9s", modelFamilyName(f.model));
    for (std::size_t a = 0; a < f.albedo.size(); ++a)
      std::printf("  %2.0f deg %.3f (%.3f %.3f %.3f)", c.theta_o_deg[a], f.albedo[a].average(), f.albedo[a].r,
                  f.albedo[a].g, f.albedo[a].b);
    std::printf("\n");
  }
  if (c.fits.size() < 2) {
    std::printf("  only one fit of %s: nothing to compare\n", c.name.c_str());
  } else if (c.disagree) {
    std::printf("warning: the fits of %s disagree: albedos differ by %.0f%% at %.0f deg (threshold %.0f%%)\n",
                c.name.c_str(), 100.0 * c.spread, c.spread_theta_o_deg, 100.0 * c.threshold);
  } else {
    std::printf("  the fits agree within %.0f%% (largest difference %.1f%% at %.0f deg)\n", 100.0 * c.threshold,
                100.0 * c.spread, c.spread_theta_o_deg);
  }
}

}  // namespace btf::datagen
