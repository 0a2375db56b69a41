// `btf-datagen`: synthetic MERL tables from analytic models (presets, or the published fits of
// the 100 MERL materials), with the artifacts of real measurements, deterministic from a seed.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <exception>
#include <iostream>
#include <optional>

#include "acquisition_response.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/terminal.h"
#include "btf/io/atomic_file.h"
#include "btf/io/merl.h"
#include "btf/material/albedo.h"
#include "btf/material/registry.h"
#include "btf/material/tabulated_brdf.h"
#include "btf_command.h"
#include "merl_fit_report.h"
#include "presets.h"
#include "scene_command.h"
#include "table_artifacts.h"

namespace btf::datagen {
using namespace btf::datagen;
namespace {

// The incidence angles `btf info` reports, so its output can be compared line by line.
constexpr float kAlbedoAnglesDeg[] = {0.0f, 30.0f, 60.0f, 75.0f};

struct Options {
  std::string preset;
  std::string merl_fit;  // a MERL name (or SGD alternative name) instead of a preset
  std::string model = "sgd";
  std::string fits_dir;
  std::string compare_fits;
  bool list_merl_fits = false;
  std::string output;
  std::uint64_t seed = 1;
  TableArtifacts artifacts{0.03f, 0.005f, 2.0f};
  float falloff = 0.2f;
  std::vector<float> tint{1.0f, 1.0f, 1.0f};
  bool clean = false;
  bool list = false;
  bool json = false;
  std::vector<float> eval_angles_deg;
};

nlohmann::json rgbJson(const Rgb& c) { return {c.r, c.g, c.b}; }

float radians(float degrees) { return degrees * kPi / 180.0f; }

void listPresets(bool json) {
  nlohmann::json out = nlohmann::json::array();
  for (const Preset& p : presets()) {
    const Rgb albedo = integrateAlbedoHalfVector(*p.make(), 0.0f);
    if (json) {
      out.push_back({{"name", p.name}, {"description", p.description}, {"albedo_normal", rgbJson(albedo)}});
    } else {
      std::printf("%-20s albedo(0 deg) %.3f %.3f %.3f  %s\n", p.name.c_str(), albedo.r, albedo.g, albedo.b,
                  p.description.c_str());
    }
  }
  if (json) std::cout << out.dump(2) << "\n";
}

// The material a table is made of: a preset, or a published fit (loaded once per run).
struct Source {
  std::string label;  // "chrome" or "chrome (abc)"
  std::shared_ptr<const Material> material;
  std::optional<MerlFitComparison> comparison;  // for a MERL fit: how all fits of it compare
};

// --merl-fit NAME --model MODEL [--fits-dir DIR] as the registry's parameter set.
MaterialParams merlFitParams(const Options& o) {
  MaterialParams params("merl-fit");
  params.set("name", o.merl_fit).set("model", o.model);
  if (!o.fits_dir.empty()) params.set("fits_dir", o.fits_dir);
  return params;
}

Source resolveSource(const Options& o, bool compare) {
  if (!o.preset.empty()) return {o.preset, findPreset(o.preset).make(), std::nullopt};
  const MerlFits fits = loadMerlFits(o.fits_dir);
  const ModelFamily model = parseModelFamily(o.model, kPublishedFitFamilies);
  std::shared_ptr<const Material> material = createMaterial(merlFitParams(o));
  const std::string name = fits.resolve(o.merl_fit);
  std::optional<MerlFitComparison> comparison;
  if (compare) comparison = compareMerlFits(fits, name, kFitDisagreementThreshold);
  return {name + " (" + modelFamilyName(model) + ")", std::move(material), std::move(comparison)};
}

// The analytic material with the acquisition response that the generated table is sampled from.
std::shared_ptr<const Material> measuredLook(const Options& o, const Source& source) {
  const Rgb tint(o.tint[0], o.tint[1], o.tint[2]);
  return std::make_shared<AcquisitionResponse>(source.material, tint, o.falloff, source.label);
}

nlohmann::json sourceJson(const Options& o) {
  if (!o.preset.empty()) return {{"preset", o.preset}};
  return {{"merl_fit", o.merl_fit}, {"model", o.model}};
}

void printAnalyticValue(const Options& o) {
  const auto& a = o.eval_angles_deg;
  const glm::vec3 wi = sphericalDirection(radians(a[0]), radians(a[1]));
  const glm::vec3 wo = sphericalDirection(radians(a[2]), radians(a[3]));
  const Source source = resolveSource(o, false);
  const Rgb f = measuredLook(o, source)->eval(wi, wo);
  if (o.json) {
    nlohmann::json out = sourceJson(o);
    out["f"] = rgbJson(f);
    std::cout << out.dump(2) << "\n";
  } else {
    std::printf("%s f = %.6g %.6g %.6g (1/sr)\n", source.label.c_str(), f.r, f.g, f.b);
  }
}

void generate(const Options& o) {
  const std::filesystem::path output = o.output;
  if (output.extension() != ".binary")
    throw FileError(output, "unknown output extension '" + output.extension().string() +
                                "' (btf-datagen writes MERL tables: use .binary)");
  // Fail before the work, not after it, when the table could not be written anyway.
  const std::filesystem::path folder = output.has_parent_path() ? output.parent_path() : ".";
  if (!std::filesystem::is_directory(folder)) throw FileError(output, "folder " + folder.string() + " does not exist");
  if (std::filesystem::is_directory(output)) throw FileError(output, "is a directory, expected a file name to write");
  const Source source = resolveSource(o, true);
  const std::shared_ptr<const Material> material = measuredLook(o, source);
  MerlTable table = tabulate(*material);
  applyArtifacts(table, o.artifacts, o.seed);
  writeMerl(output, table);

  std::size_t unmeasured = 0;
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) unmeasured += !table.isMeasured(i);
  const double percent = 100.0 * double(unmeasured) / double(MerlTable::kEntriesPerChannel);

  nlohmann::json expected = nlohmann::json::array();
  for (float deg : kAlbedoAnglesDeg)
    expected.push_back({{"theta_o_deg", deg}, {"rgb", rgbJson(integrateAlbedoHalfVector(*material, radians(deg)))}});

  if (o.json) {
    nlohmann::json out = sourceJson(o);
    out.update(nlohmann::json{{"output", o.output},
                                {"seed", o.seed},
                                {"clean", o.clean},
                                {"noise", o.artifacts.noise_sigma},
                                {"holes", o.artifacts.hole_fraction},
                                {"grazing_gap_deg", o.artifacts.grazing_gap_degrees},
                                {"falloff", o.falloff},
                                {"tint", o.tint},
                                {"unmeasured", {{"count", unmeasured}, {"percent", percent}}},
                                {"expected_albedo", expected}});
    if (source.comparison) out["fit_comparison"] = comparisonJson(*source.comparison);
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("wrote %s: %s %s, seed %llu\n", o.output.c_str(), o.preset.empty() ? "MERL fit" : "preset",
              source.label.c_str(), (unsigned long long)o.seed);
  if (o.clean) {
    std::printf("  effects: none (--clean)\n");
  } else {
    std::printf("  effects: noise %g, holes %g%%, grazing gap %g deg, falloff %g, tint %g,%g,%g\n",
                o.artifacts.noise_sigma, 100.0 * o.artifacts.hole_fraction, o.artifacts.grazing_gap_degrees,
                o.falloff, o.tint[0], o.tint[1], o.tint[2]);
  }
  std::printf("  unmeasured: %zu of %zu cells (%.2f%%, incl. cells below the horizon)\n", unmeasured,
              MerlTable::kEntriesPerChannel, percent);
  std::printf("  expected albedo (analytic, with tint and falloff):\n");
  for (const auto& e : expected) {
    std::printf("    theta_o %2.0f deg: %.4f %.4f %.4f\n", e["theta_o_deg"].get<float>(), e["rgb"][0].get<float>(),
                e["rgb"][1].get<float>(), e["rgb"][2].get<float>());
  }
  if (source.comparison) printFitComparison(*source.comparison);
}

void run(Options& o) {
  if (o.list) return listPresets(o.json);
  if (o.list_merl_fits) return listMerlFits(loadMerlFits(o.fits_dir), o.json);
  if (!o.compare_fits.empty()) {
    const MerlFitComparison c = compareMerlFits(loadMerlFits(o.fits_dir), o.compare_fits, kFitDisagreementThreshold);
    if (o.json) std::cout << comparisonJson(c).dump(2) << "\n";
    else printFitComparison(c);
    return;
  }
  if (o.preset.empty() && o.merl_fit.empty())
    throw Error("choose a material with --preset NAME (see --list-presets) or --merl-fit NAME (see --list-merl-fits)");
  if (!o.preset.empty()) findPreset(o.preset);  // fail on a typo before any work
  else createMaterial(merlFitParams(o));
  if (o.clean) {
    o.artifacts = TableArtifacts{};
    o.falloff = 0.0f;
    o.tint = {1.0f, 1.0f, 1.0f};
  }
  if (!o.eval_angles_deg.empty()) return printAnalyticValue(o);
  if (o.output.empty()) throw Error("name the output table with -o FILE.binary");
  generate(o);
}

}  // namespace
}  // namespace btf::datagen

int main(int argc, char** argv) {
  using btf::datagen::Options;
  Options o;
  CLI::App app{"btf-datagen: synthetic measured BRDFs in the MERL .binary format.\n"
               "Tabulates an analytic preset with what real measurements have (tint, grazing falloff,\n"
               "multiplicative noise, unmeasured holes), deterministic from --seed.\n"
               "`btf-datagen btf ...` generates a synthetic BTF image folder instead (see btf-datagen btf --help),\n"
               "`btf-datagen scene ...` the built-in validation scenes (see btf-datagen scene --help).",
               "btf-datagen"};
  btf::datagen::BtfCommandOptions btf_options;
  CLI::App* btf_command = btf::datagen::addBtfCommand(app, btf_options);
  btf::datagen::SceneCommandOptions scene_options;
  CLI::App* scene_command = btf::datagen::addSceneCommand(app, scene_options);
  app.add_flag("--list-presets", o.list, "List the presets with their analytic albedo at normal incidence");
  auto* preset = app.add_option("--preset", o.preset, "Material preset (see --list-presets)");
  auto* merl_fit = app.add_option("--merl-fit", o.merl_fit,
                                  "A MERL material from its published fit (see --list-merl-fits), e.g. gold-metallic-paint")
                       ->excludes(preset);
  app.add_option("--model", o.model, "Fit of --merl-fit: sgd (Bagher 2012), abc (Low 2012) or lafortune (Ngan 2005)")
      ->check(CLI::IsMember({"sgd", "abc", "lafortune"}))->needs(merl_fit)->capture_default_str();
  app.add_flag("--list-merl-fits", o.list_merl_fits, "List the MERL materials with the models that fit them");
  app.add_option("--compare-fits", o.compare_fits,
                 "Albedo at 0/30/60 deg of every published fit of a MERL material, with a warning where they disagree");
  app.add_option("--fits-dir", o.fits_dir,
                 "Folder with the fit tables (default: the build's ../shared/data/real/fits, else the installed copy)");
  app.add_option("-o,--output", o.output, "Output MERL table (.binary)");
  app.add_option("--seed", o.seed, "Seed of the noise and holes")->capture_default_str();
  auto* noise = app.add_option("--noise", o.artifacts.noise_sigma, "Sigma of the lognormal multiplicative noise (mean 1)")
                    ->check(CLI::Range(0.0f, 2.0f))->capture_default_str();
  auto* holes = app.add_option("--holes", o.artifacts.hole_fraction, "Fraction of cells dropped at random")
                    ->check(CLI::Range(0.0f, 0.99f))->capture_default_str();
  auto* gap = app.add_option("--grazing-gap", o.artifacts.grazing_gap_degrees,
                             "Degrees above the horizon that light and view cannot reach (unmeasured)")
                  ->check(CLI::Range(0.0f, 89.0f))->capture_default_str();
  auto* falloff = app.add_option("--falloff", o.falloff, "Signal lost at the horizon: f *= 1 - falloff*(theta/90)^8 per direction")
                      ->check(CLI::Range(0.0f, 1.0f))->capture_default_str();
  auto* tint = app.add_option("--tint", o.tint, "Colour response r,g,b multiplying f")
                   ->expected(3)->delimiter(',')->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--clean", o.clean, "No measurement effects: the exact analytic table")
      ->excludes(noise)->excludes(holes)->excludes(gap)->excludes(falloff)->excludes(tint);
  app.add_option("--eval", o.eval_angles_deg,
                 "Print the analytic f (with tint and falloff) at THETA_I PHI_I THETA_O PHI_O degrees; writes nothing")
      ->expected(4);
  app.add_flag("--json", o.json, "Machine-readable output");
  btf::installTerminalHooks();
  btf::removeTemporariesOnSignals();  // an interrupted write leaves no partial file
  try {
    app.parse(argc, argv);
    if (btf_command->parsed()) btf::datagen::runBtfCommand(btf_options);
    else if (scene_command->parsed()) btf::datagen::runSceneCommand(scene_options);
    else btf::datagen::run(o);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "btf-datagen: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
