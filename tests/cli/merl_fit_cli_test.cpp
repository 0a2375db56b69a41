// btf-datagen with the published MERL fits: tables that hold the fitted formula, listing,
// comparison of fits, and errors for unknown names, missing fits and a wrong fits folder.
#include <gtest/gtest.h>

#include <algorithm>

#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/io/merl.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/tabulated_brdf.h"
#include "cli_test_support.h"
#include "unit/merl_fit_reference.h"

namespace btf::test {
namespace {

CsvRecord rowOf(const char* file, const std::string& name) {
  for (const CsvRecord& r : readCsvRecords(fitsDir() / file))
    if (r.at("material") == name) return r;
  throw std::runtime_error(name + " not in " + file);
}

}  // namespace

TEST(MerlFitCli, CleanTableHoldsTheFormulaAtItsSamplesAndInterpolatesBetween) {
  // gold-metallic-paint with ABC: B = 54, C = 1.5, a lobe broad enough for the table's resolution.
  TempDir dir;
  const auto out = dir / "gold.binary";
  const CommandResult r = runDatagen({"--merl-fit", "gold-metallic-paint", "--model", "abc", "--clean", "-o",
                                      out.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = parseJsonOutput(r);
  EXPECT_EQ(summary["model"], "abc");
  EXPECT_EQ(summary["fit_comparison"]["fits"].size(), 3u);
  const auto table = std::make_shared<const MerlTable>(readMerl(out));
  const CsvRecord row = rowOf(kAbcFitsFile, "gold-metallic-paint");

  // At the table's own sample angles (phi_h = 0) the stored value is the formula, up to float.
  Rng rng(5);
  int checked = 0;
  while (checked < 400) {
    const glm::vec2 u = rng.uniform2D(), v = rng.uniform2D();
    const int ih = int(u.x * 90), id = int(u.y * 90), ip = int(v.x * 180);
    HalfDiff hd;
    hd.theta_h = float(MerlTable::thetaHalfOf(ih));
    hd.theta_d = float(MerlTable::thetaDiffOf(id));
    hd.phi_d = float(MerlTable::phiDiffOf(ip));
    const DirectionPair p = fromHalfDiff(hd);
    const std::size_t i = MerlTable::index(ih, id, ip);
    if (p.wi.z <= 0 || p.wo.z <= 0 || !table->isMeasured(i)) continue;
    ++checked;
    const Rgb stored = table->reflectance(i);
    for (int c = 0; c < 3; ++c) {
      const double expected = referenceAbc(row, c, glm::dvec3(p.wi), glm::dvec3(p.wo));
      ASSERT_NEAR(stored[c], expected, 1e-4 * expected) << "cell " << ih << "," << id << "," << ip;
    }
  }

  // Between samples, TabulatedBrdf interpolates: random directions up to 70 degrees stay within
  // the table's interpolation error (the bounds below leave a wide margin over the error this
  // table shows).
  const TabulatedBrdf tabulated(table);
  std::vector<double> errors;
  for (int n = 0; n < 2000; ++n) {
    const glm::vec3 wi = sphericalDirection(glm::radians(70.0f) * rng.uniform2D().x, kTwoPi * rng.uniform2D().y);
    const glm::vec3 wo = sphericalDirection(glm::radians(70.0f) * rng.uniform2D().x, kTwoPi * rng.uniform2D().y);
    const double expected = referenceAbc(row, 1, glm::dvec3(wi), glm::dvec3(wo));
    errors.push_back(std::abs(tabulated.eval(wi, wo).g - expected) / expected);
  }
  std::sort(errors.begin(), errors.end());
  RecordProperty("median_relative_error", std::to_string(errors[errors.size() / 2]));
  RecordProperty("p99_relative_error", std::to_string(errors[errors.size() * 99 / 100]));
  EXPECT_LT(errors[errors.size() / 2], 0.005) << "median relative interpolation error";
  EXPECT_LT(errors[errors.size() * 99 / 100], 0.03) << "99th percentile relative interpolation error";
}

TEST(MerlFitCli, ListsEveryNameWithItsModels) {
  const CommandResult r = runDatagen({"--list-merl-fits", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json list = parseJsonOutput(r);
  int merl = 0, merl_with_lafortune = 0;
  for (const auto& entry : list) {
    const auto models = entry["models"].get<std::vector<std::string>>();
    if (!entry["merl"].get<bool>()) {
      EXPECT_EQ(models, std::vector<std::string>{"lafortune"}) << entry["name"];
      continue;
    }
    ++merl;
    EXPECT_EQ(models[0], "sgd");
    EXPECT_EQ(models[1], "abc");
    merl_with_lafortune += models.size() == 3;
  }
  EXPECT_EQ(merl, 100);
  EXPECT_EQ(merl_with_lafortune, 86);
  EXPECT_EQ(list.size(), 114u);
}

TEST(MerlFitCli, ComparesFitsAndWarnsWhenTheyDisagree) {
  const CommandResult json = runDatagen({"--compare-fits", "metallic-gold", "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const nlohmann::json c = parseJsonOutput(json);
  EXPECT_EQ(c["name"], "gold-metallic-paint");
  ASSERT_EQ(c["fits"].size(), 3u);
  EXPECT_EQ(c["disagree"].get<bool>(), c["spread"].get<double>() > c["threshold"].get<double>());
  const CommandResult text = runDatagen({"--compare-fits", "metallic-gold"});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_EQ(text.output.find("warning: the fits of gold-metallic-paint disagree") != std::string::npos,
            c["disagree"].get<bool>())
      << text.output;
  for (const char* model : {"sgd", "abc", "lafortune"}) EXPECT_NE(text.output.find(model), std::string::npos);
}

TEST(MerlFitCli, UnknownNamesMissingFitsAndFoldersFailClearly) {
  TempDir dir;
  const CommandResult typo = runDatagen({"--merl-fit", "chrom", "-o", (dir / "t.binary").string()});
  EXPECT_NE(typo.exit_code, 0);
  EXPECT_NE(typo.output.find("unknown MERL material 'chrom'; did you mean chrome"), std::string::npos) << typo.output;
  const CommandResult lacks = runDatagen({"--merl-fit", "two-layer-gold", "--model", "lafortune", "-o", (dir / "t.binary").string()});
  EXPECT_NE(lacks.exit_code, 0);
  EXPECT_NE(lacks.output.find("no lafortune fit of 'two-layer-gold'"), std::string::npos) << lacks.output;
  const CommandResult folder = runDatagen({"--list-merl-fits", "--fits-dir", dir.path().string()});
  EXPECT_NE(folder.exit_code, 0);
  EXPECT_NE(folder.output.find(dir.path().string() + " (missing"), std::string::npos) << folder.output;
  EXPECT_TRUE(filesIn(dir.path()).empty()) << "nothing is written on an error";
  const CommandResult both = runDatagen({"--merl-fit", "chrome", "--preset", "chrome", "-o", (dir / "t.binary").string()});
  EXPECT_NE(both.exit_code, 0);
}

TEST(MerlFitCli, MeasurementEffectsApplyToFitsAsToPresets) {
  // The same fit with the default effects (noise, holes, grazing gap) leaves cells unmeasured that
  // the clean table has.
  TempDir dir;
  const auto run = [&](std::vector<std::string> extra, const std::string& file) {
    std::vector<std::string> args = {"--merl-fit", "pink-felt", "--model", "sgd", "-o", (dir / file).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CommandResult r = runDatagen(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return readMerl(dir / file);
  };
  const MerlTable clean = run({"--clean"}, "clean.binary"), measured = run({}, "measured.binary");
  std::size_t clean_holes = 0, measured_holes = 0;
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) {
    clean_holes += !clean.isMeasured(i);
    measured_holes += !measured.isMeasured(i);
  }
  EXPECT_GT(measured_holes, clean_holes);
}

}  // namespace btf::test

namespace btf::test {

TEST(MerlFitCli, InfoComparesAFileNamedAfterAMerlMaterialWithItsPublishedFits) {
  TempDir dir;
  // MERL names its files after the material; info recognises the name and shows the fits.
  const auto named = dir / "chrome.binary";
  ASSERT_EQ(runDatagen({"--merl-fit", "chrome", "--model", "sgd", "--clean", "-o", named.string()}).exit_code, 0);
  const CommandResult text = runBtf({"info", named.string()});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("published fits of chrome"), std::string::npos) << text.output;
  const nlohmann::json json = parseJsonOutput(runBtf({"info", named.string(), "--json"}));
  const nlohmann::json& fits = json["published_fits"];
  ASSERT_TRUE(fits.is_object()) << json.dump(2);
  EXPECT_EQ(fits["fits"].size(), 3u);
  // The flag is the stated rule applied to the stated numbers, and the text says the same.
  EXPECT_EQ(fits["disagree"].get<bool>(), fits["spread"].get<double>() > fits["threshold"].get<double>());
  EXPECT_EQ(text.output.find("warning: the fits of chrome disagree") != std::string::npos, fits["disagree"].get<bool>());

  // Any other name: no comparison, unless asked for by --fits-of; an unknown --fits-of fails.
  const auto other = dir / "sample.binary";
  std::filesystem::copy_file(named, other);
  EXPECT_TRUE(parseJsonOutput(runBtf({"info", other.string(), "--json"}))["published_fits"].is_null());
  EXPECT_NE(runBtf({"info", other.string(), "--fits-of", "chrome"}).output.find("published fits of chrome"),
            std::string::npos);
  const CommandResult unknown = runBtf({"info", other.string(), "--fits-of", "chrom"});
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.output.find("did you mean chrome"), std::string::npos) << unknown.output;
}

}  // namespace btf::test
