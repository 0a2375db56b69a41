// Published analytic fits of the MERL materials (../shared/data/real/fits/,
// docs/design-notes.md#measured-data), read from their CSV tables and turned into Materials:
//   sgd_bagher2012_merl.csv        Shifted Gamma Distribution (Bagher et al. 2012), 100 MERL names
//   abc_low2012_merl.csv           ABC model (Löw et al. 2012), the same 100 names
//   lafortune1_ngan2005_merl.csv   one-lobe Lafortune (Ngan et al. 2005): 86 of the MERL names and
//                                  14 materials of Ngan's larger set that MERL never released
// A name resolves if it is in any table or is an SGD `other_name` (e.g. "metallic-gold").
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "btf/core/rgb.h"
#include "btf/material/abc.h"
#include "btf/material/material.h"
#include "btf/material/model_family.h"
#include "btf/material/sgd.h"

namespace btf {

// The families with published fits (btf/material/model_family.h names them).
inline constexpr std::array<ModelFamily, 3> kPublishedFitFamilies = {ModelFamily::Sgd, ModelFamily::Abc,
                                                                     ModelFamily::Lafortune};

inline constexpr const char* kSgdFitsFile = "sgd_bagher2012_merl.csv";
inline constexpr const char* kAbcFitsFile = "abc_low2012_merl.csv";
inline constexpr const char* kLafortuneFitsFile = "lafortune1_ngan2005_merl.csv";

struct SgdFit {
  std::string name, other_name;  // other_name: the authors' alternative name, may be empty
  SgdParameters parameters;
  Rgb error;  // the fit error the authors report per channel
};
struct AbcFit {
  std::string name;
  AbcParameters parameters;
};
struct LafortuneFit {
  int index = 0;  // the source's running number
  std::string name;
  Rgb rho_d, rho_s;
  float cxy = 0, cz = 0, n = 0;  // lobe (cxy, cxy, cz), exponent n
};

// Readers of one table each. Throw FileError "<file>: <problem>" for a missing or unreadable file,
// a header other than the expected columns, and "<file>: line N: <problem>" for a row with the
// wrong number of fields, an empty or duplicate name, a field that is not a number, or a number
// that is not finite.
std::vector<SgdFit> readSgdFits(const std::filesystem::path& csv);
std::vector<AbcFit> readAbcFits(const std::filesystem::path& csv);
std::vector<LafortuneFit> readLafortuneFits(const std::filesystem::path& csv);

class MerlFits {
 public:
  // Reads the three tables from one folder (kSgdFitsFile etc.).
  static MerlFits load(const std::filesystem::path& folder);
  MerlFits(std::vector<SgdFit> sgd, std::vector<AbcFit> abc, std::vector<LafortuneFit> lafortune);

  const std::vector<SgdFit>& sgd() const { return sgd_; }
  const std::vector<AbcFit>& abc() const { return abc_; }
  const std::vector<LafortuneFit>& lafortune() const { return lafortune_; }

  // Every name of any table, sorted (the MERL-100 names plus Lafortune-only ones).
  std::vector<std::string> names() const;
  // True for the 100 MERL names (those of the SGD or ABC table).
  bool isMerl(std::string_view canonical_name) const;
  // The table name for a name or SGD other_name. Throws btf::Error for an unknown name, with up to
  // three close names ("did you mean ...?").
  std::string resolve(std::string_view name) const;
  // Models with a fit of the material (any resolvable name), in kPublishedFitFamilies order.
  std::vector<ModelFamily> modelsFor(std::string_view name) const;

  // nullptr when the table lacks the (canonical) name.
  const SgdFit* findSgd(std::string_view canonical_name) const;
  const AbcFit* findAbc(std::string_view canonical_name) const;
  const LafortuneFit* findLafortune(std::string_view canonical_name) const;

 private:
  std::vector<SgdFit> sgd_;
  std::vector<AbcFit> abc_;
  std::vector<LafortuneFit> lafortune_;
};

// The material of one fit: Sgd, Abc, or Lafortune(rho_d, {rho_s, (cxy, cxy, cz), n}). Throws
// btf::Error for an unknown name (with suggestions) and for a model whose table lacks the material
// (naming the models that have it).
std::unique_ptr<Material> makeMerlFitMaterial(const MerlFits& fits, std::string_view name, ModelFamily model);

// The first candidate folder holding all three tables. Throws btf::Error listing every candidate
// and what each lacks. Empty paths are skipped.
std::filesystem::path findMerlFitsFolder(const std::vector<std::filesystem::path>& candidates);
// Where libbtf looks for the tables when no folder is named: $BTF_FITS_DIR when set, the shared data
// folder of the build, then the copy installed with the library (share/libbtf/fits beside its lib
// folder, found from libbtf.so's own location, so that a moved install still works).
std::vector<std::filesystem::path> defaultMerlFitsFolders();
// MerlFits::load(findMerlFitsFolder(...)) of `folder` when not empty, else of the default folders.
MerlFits loadMerlFits(const std::filesystem::path& folder = {});

// The material type "merl-fit" ({"type": "merl-fit", "name": "alum-bronze", "model": "sgd",
// "fits_dir": optional folder}; spec merl-fit:MODEL:NAME) is registered by this reader.

// --- Where fits of one material disagree -----------------------------------------------------
struct FitAlbedos {
  ModelFamily model;
  std::vector<Rgb> albedo;  // directional albedo at each comparison angle
};
struct MerlFitComparison {
  std::string name;                // canonical
  std::vector<float> theta_o_deg;  // the comparison angles
  std::vector<FitAlbedos> fits;    // every model with a fit, in kPublishedFitFamilies order
  // max over angles of (max - min) / max across models of the mean-RGB albedo; 0 with one model.
  double spread = 0;
  float spread_theta_o_deg = 0;  // the angle where the spread is largest
  double threshold = 0;
  bool disagree = false;  // spread > threshold
};
// Albedo by deterministic half-vector quadrature (integrateAlbedoHalfVector) of each available fit:
// one quadrature per model, the cost of this call.
MerlFitComparison compareMerlFits(const MerlFits& fits, std::string_view name, double threshold = 0.10,
                                  const std::vector<float>& theta_o_deg = {0.0f, 30.0f, 60.0f});

}  // namespace btf
