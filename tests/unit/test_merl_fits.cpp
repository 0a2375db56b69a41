// Reading the published MERL fit tables (../shared/data/real/fits): row counts and values against
// a naive reader, name lookup (alternative names, suggestions, models a table lacks), malformed
// files, and the comparison of fits of one material.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "btf/core/error.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/albedo.h"
#include "unit/merl_fit_reference.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;

// Copies a real table, replacing line `line` (1-based) by `text`.
fs::path editedCopy(const TempDir& dir, const char* file, int line, const std::string& text) {
  std::ifstream in(fitsDir() / file);
  std::ofstream out(dir / file);
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) out << (n == line ? text : s) << "\n";
  return dir / file;
}

std::set<std::string> namesOf(const std::vector<CsvRecord>& rows) {
  std::set<std::string> names;
  for (const CsvRecord& r : rows) names.insert(r.at("material"));
  return names;
}

}  // namespace

TEST(MerlFits, ReadsAllRowsOfTheThreeTablesWithTheirValues) {
  const MerlFits fits = MerlFits::load(fitsDir());
  const auto sgd_rows = readCsvRecords(fitsDir() / kSgdFitsFile);
  const auto abc_rows = readCsvRecords(fitsDir() / kAbcFitsFile);
  const auto laf_rows = readCsvRecords(fitsDir() / kLafortuneFitsFile);
  // SOURCES.md: 100 rows each.
  ASSERT_EQ(fits.sgd().size(), 100u);
  ASSERT_EQ(fits.abc().size(), 100u);
  ASSERT_EQ(fits.lafortune().size(), 100u);
  ASSERT_EQ(sgd_rows.size(), 100u);
  for (std::size_t i = 0; i < sgd_rows.size(); ++i) {
    const SgdFit& f = fits.sgd()[i];
    ASSERT_EQ(f.name, sgd_rows[i].at("material"));
    EXPECT_EQ(f.other_name, sgd_rows[i].at("other_name"));
    for (int c = 0; c < 3; ++c) {
      const SgdChannel& p = f.parameters.channel[c];
      const char* s = channelSuffix(c);
      auto col = [&](const char* name) { return num(sgd_rows[i], name + std::string(s)); };
      EXPECT_EQ(p.rho_d, col("rhoD"));
      EXPECT_EQ(p.rho_s, col("rhoS"));
      EXPECT_EQ(p.alpha, col("alpha"));
      EXPECT_EQ(p.p, col("p"));
      EXPECT_EQ(p.f0, col("f0"));
      EXPECT_EQ(p.f1, col("f1"));
      EXPECT_EQ(p.kap, col("kap"));
      EXPECT_EQ(p.lambda, col("lambda"));
      EXPECT_EQ(p.c, col("c"));
      EXPECT_EQ(p.k, col("k"));
      EXPECT_EQ(p.theta0, col("theta0"));
      EXPECT_FLOAT_EQ(f.error[c], float(col("error")));
    }
  }
  for (std::size_t i = 0; i < abc_rows.size(); ++i) {
    const AbcFit& f = fits.abc()[i];
    ASSERT_EQ(f.name, abc_rows[i].at("material"));
    EXPECT_EQ(f.parameters.b, num(abc_rows[i], "B"));
    EXPECT_EQ(f.parameters.c, num(abc_rows[i], "C"));
    EXPECT_EQ(f.parameters.ior, num(abc_rows[i], "ior"));
    for (int c = 0; c < 3; ++c) {
      EXPECT_FLOAT_EQ(f.parameters.kd[c], float(num(abc_rows[i], std::string("kD") + channelSuffix(c))));
      EXPECT_FLOAT_EQ(f.parameters.a[c], float(num(abc_rows[i], std::string("A") + channelSuffix(c))));
    }
  }
  for (std::size_t i = 0; i < laf_rows.size(); ++i) {
    const LafortuneFit& f = fits.lafortune()[i];
    ASSERT_EQ(f.name, laf_rows[i].at("material"));
    EXPECT_EQ(f.index, int(num(laf_rows[i], "index")));
    EXPECT_FLOAT_EQ(f.n, float(num(laf_rows[i], "n")));
    EXPECT_FLOAT_EQ(f.cxy, float(num(laf_rows[i], "Cxy")));
    EXPECT_FLOAT_EQ(f.cz, float(num(laf_rows[i], "Cz")));
    EXPECT_FLOAT_EQ(f.rho_s.b, float(num(laf_rows[i], "rho_s_b")));
  }
}

TEST(MerlFits, NameSetsMatchSourcesMd) {
  const MerlFits fits = MerlFits::load(fitsDir());
  const auto sgd = namesOf(readCsvRecords(fitsDir() / kSgdFitsFile));
  const auto abc = namesOf(readCsvRecords(fitsDir() / kAbcFitsFile));
  const auto laf = namesOf(readCsvRecords(fitsDir() / kLafortuneFitsFile));
  EXPECT_EQ(sgd, abc) << "SOURCES.md: the SGD and ABC tables cover the same 100 names";
  // SOURCES.md lists the 14 MERL materials Ngan's table lacks.
  const std::set<std::string> missing = {"color-changing-paint1", "color-changing-paint2", "color-changing-paint3",
                                         "dark-specular-fabric",  "grease-covered-steel",  "light-brown-fabric",
                                         "pink-fabric",           "red-fabric2",           "silver-metallic-paint2",
                                         "two-layer-gold",        "two-layer-silver",      "white-fabric",
                                         "white-fabric2",         "white-marble"};
  int merl_in_lafortune = 0;
  for (const std::string& name : sgd) {
    const bool has_lafortune = laf.count(name) > 0;
    merl_in_lafortune += has_lafortune;
    EXPECT_EQ(has_lafortune, missing.count(name) == 0) << name;
    const auto models = fits.modelsFor(name);
    EXPECT_EQ(models.size(), has_lafortune ? 3u : 2u) << name;
    EXPECT_TRUE(fits.isMerl(name));
  }
  EXPECT_EQ(merl_in_lafortune, 86);
  EXPECT_EQ(fits.names().size(), 114u) << "100 MERL names + 14 Lafortune-only materials";
  EXPECT_FALSE(fits.isMerl("copper"));
  EXPECT_EQ(fits.modelsFor("copper"), std::vector<ModelFamily>{ModelFamily::Lafortune});
}

TEST(MerlFits, ResolvesAlternativeNamesAndSuggestsCloseOnes) {
  const MerlFits fits = MerlFits::load(fitsDir());
  int alternatives = 0;
  for (const CsvRecord& r : readCsvRecords(fitsDir() / kSgdFitsFile)) {
    if (r.at("other_name").empty()) continue;
    EXPECT_EQ(fits.resolve(r.at("other_name")), r.at("material"));
    ++alternatives;
  }
  EXPECT_GT(alternatives, 50);
  EXPECT_EQ(fits.resolve("chrome"), "chrome");
  const std::string typo = errorOf([&] { fits.resolve("gold-metalic-paint"); });
  EXPECT_NE(typo.find("unknown MERL material 'gold-metalic-paint'"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean gold-metallic-paint"), std::string::npos) << typo;
  const std::string part = errorOf([&] { fits.resolve("phenolic"); });
  EXPECT_NE(part.find("specular-"), std::string::npos) << part;
  const std::string none = errorOf([&] { fits.resolve("zzzzzzzzzzzzzzzzzzzz"); });
  EXPECT_NE(none.find("--list-merl-fits"), std::string::npos) << none;
}

TEST(MerlFits, MakesEachModelAndNamesWhatATableLacks) {
  const MerlFits fits = MerlFits::load(fitsDir());
  EXPECT_EQ(makeMerlFitMaterial(fits, "metallic-gold", ModelFamily::Sgd)->name(), "sgd(gold-metallic-paint)");
  EXPECT_EQ(makeMerlFitMaterial(fits, "chrome", ModelFamily::Abc)->name(), "abc(chrome)");
  EXPECT_NE(makeMerlFitMaterial(fits, "chrome", ModelFamily::Lafortune)->name().find("lafortune"), std::string::npos);
  const std::string lacks = errorOf([&] { makeMerlFitMaterial(fits, "white-marble", ModelFamily::Lafortune); });
  EXPECT_NE(lacks.find("no lafortune fit of 'white-marble'"), std::string::npos) << lacks;
  EXPECT_NE(lacks.find("sgd, abc"), std::string::npos) << lacks;
  EXPECT_NE(errorOf([&] { makeMerlFitMaterial(fits, "copper", ModelFamily::Abc); }).find("lafortune"), std::string::npos);
  EXPECT_EQ(parseModelFamily("abc", kPublishedFitFamilies), ModelFamily::Abc);
  EXPECT_NE(errorOf([] { parseModelFamily("cook-torrance", kPublishedFitFamilies); }).find("unknown model 'cook-torrance' (expected sgd, abc or lafortune)"), std::string::npos);
}

TEST(MerlFits, MalformedTablesNameFileAndLine) {
  TempDir dir;
  const std::string missing = errorOf([&] { readAbcFits(dir / "absent.csv"); });
  EXPECT_NE(missing.find("absent.csv: no such file"), std::string::npos) << missing;

  struct Case {
    const char* file;
    int line;
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {kAbcFitsFile, 3, "alumina-oxide,0.3,0.2,0.2,2191,1851,2064,97381,1.39", "line 3: 9 fields, expected 10"},
      {kAbcFitsFile, 2, "alum-bronze,0.02,0.02,0.01,51,37,27,nan,0.8,2.2", "line 2: column B: 'nan' is not a finite number"},
      {kAbcFitsFile, 4, "aluminium,0.0,0.002,x,1137,1090,1113,218716,1.09,6.28", "line 4: column kD_b: 'x' is not a number"},
      {kAbcFitsFile, 1, "material,kD_r,kD_g,kD_b,A_r,A_g,A_b,B,C", "line 1: unexpected header"},
      {kAbcFitsFile, 3, "alum-bronze,0.02,0.02,0.01,51,37,27,10482,0.8,2.2", "line 3: duplicate material 'alum-bronze'"},
      {kLafortuneFitsFile, 5, "4,,0.1,0.1,0.1,0.1,0.1,0.1,-0.5,0.5,10", "line 5: column material: empty name"},
      {kLafortuneFitsFile, 2, "1,alum-bronze,0.09,0.06,0.03,0.3,0.19,0.1,-0.579,0.574,inf", "line 2: column n: 'inf' is not a finite number"},
  };
  for (const Case& c : cases) {
    const fs::path path = editedCopy(dir, c.file, c.line, c.text);
    const std::string message = errorOf([&] {
      if (std::string(c.file) == kAbcFitsFile) readAbcFits(path);
      else readLafortuneFits(path);
    });
    EXPECT_NE(message.find(path.string() + ": " + c.expected), std::string::npos) << message;
  }
  // An SGD row whose alpha is 0 would divide by zero in D.
  const auto sgd_rows = readCsvRecords(fitsDir() / kSgdFitsFile);
  std::ifstream in(fitsDir() / kSgdFitsFile);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const std::string alpha = sgd_rows[0].at("alpha_r");
  row.replace(row.find("," + alpha + ","), alpha.size() + 2, ",0,");
  const std::string zero = errorOf([&] { readSgdFits(editedCopy(dir, kSgdFitsFile, 2, row)); });
  EXPECT_NE(zero.find("line 2: column alpha_r: must be > 0"), std::string::npos) << zero;
}

TEST(MerlFits, FindsTheFolderHoldingAllThreeTables) {
  TempDir empty;
  EXPECT_EQ(findMerlFitsFolder({"", empty.path(), fitsDir()}), fitsDir());
  const std::string message = errorOf([&] { findMerlFitsFolder({empty.path()}); });
  EXPECT_NE(message.find(empty.path().string() + " (missing sgd_bagher2012_merl.csv"), std::string::npos) << message;
}

TEST(MerlFits, ComparisonReportsEveryFitsAlbedoAndTheSpread) {
  const MerlFits fits = MerlFits::load(fitsDir());
  for (const std::string name : {"chrome", "white-marble"}) {
    const MerlFitComparison c = compareMerlFits(fits, name, 0.1);
    ASSERT_EQ(c.fits.size(), fits.modelsFor(name).size());
    ASSERT_EQ(c.theta_o_deg, (std::vector<float>{0, 30, 60}));
    double spread = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      double lo = 1e9, hi = 0;
      for (const FitAlbedos& f : c.fits) {
        const Rgb expected = integrateAlbedoHalfVector(*makeMerlFitMaterial(fits, name, f.model),
                                                       glm::radians(c.theta_o_deg[a]));
        EXPECT_EQ(f.albedo[a], expected);
        lo = std::min<double>(lo, expected.average());
        hi = std::max<double>(hi, expected.average());
      }
      spread = std::max(spread, (hi - lo) / hi);
    }
    EXPECT_NEAR(c.spread, spread, 1e-12);
    EXPECT_EQ(c.disagree, spread > 0.1);
  }
  // A threshold above any possible spread never flags.
  EXPECT_FALSE(compareMerlFits(fits, "chrome", 1.0).disagree);
}

}  // namespace btf::test
