#include "btf/fit/merl_fits.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <fstream>
#include <set>

#include "btf/core/error.h"
#include "btf/material/lafortune.h"
#include "btf/material/registry.h"

namespace btf {
namespace fs = std::filesystem;

namespace {

// One data row of a CSV table with the line it came from, for messages.
struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
};

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return std::string(s.substr(first, last - first + 1));
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(std::string_view(line).substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

// Reads a table whose header must be exactly `columns`; blank lines are skipped.
std::vector<CsvRow> readCsv(const fs::path& path, const std::vector<std::string>& columns) {
  if (!fs::exists(path)) throw FileError(path, "no such file");
  if (fs::is_directory(path)) throw FileError(path, "is a directory, expected a CSV file");
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot open for reading");
  std::string line;
  int number = 0;
  bool have_header = false;
  std::vector<CsvRow> rows;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    std::vector<std::string> fields = splitFields(line);
    if (!have_header) {
      if (fields != columns) {
        std::string expected;
        for (const std::string& c : columns) expected += (expected.empty() ? "" : ",") + c;
        throw FileError(path, "line " + std::to_string(number) + ": unexpected header; expected the columns " + expected);
      }
      have_header = true;
      continue;
    }
    if (fields.size() != columns.size())
      throw FileError(path, "line " + std::to_string(number) + ": " + std::to_string(fields.size()) +
                                " fields, expected " + std::to_string(columns.size()));
    rows.push_back({number, std::move(fields)});
  }
  if (in.bad()) throw FileError(path, "read error");
  if (!have_header) throw FileError(path, "empty file, expected a header line");
  if (rows.empty()) throw FileError(path, "no data rows after the header");
  return rows;
}

// Field access with the file, line and column in every message.
class RowReader {
 public:
  RowReader(const fs::path& path, const std::vector<std::string>& columns, const CsvRow& row)
      : path_(path), columns_(columns), row_(row) {}

  std::string name(const char* column) const {
    std::string value = field(column);
    if (value.empty()) fail(column, "empty name");
    return value;
  }
  std::string text(const char* column) const { return field(column); }
  double number(const char* column) const {
    const std::string value = field(column);
    double x = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
    if (value.empty() || ec != std::errc() || end != value.data() + value.size())
      fail(column, "'" + value + "' is not a number");
    if (!std::isfinite(x)) fail(column, "'" + value + "' is not a finite number");
    return x;
  }
  Rgb rgb(const std::string& prefix) const {
    return {float(number((prefix + "_r").c_str())), float(number((prefix + "_g").c_str())),
            float(number((prefix + "_b").c_str()))};
  }
  [[noreturn]] void fail(const char* column, const std::string& problem) const {
    throw FileError(path_, "line " + std::to_string(row_.line) + ": column " + column + ": " + problem);
  }
  int line() const { return row_.line; }

 private:
  const std::string& field(const char* column) const {
    const auto it = std::find(columns_.begin(), columns_.end(), column);
    return row_.fields[std::size_t(it - columns_.begin())];
  }
  const fs::path& path_;
  const std::vector<std::string>& columns_;
  const CsvRow& row_;
};

std::vector<std::string> rgbColumns(std::vector<std::string> head, const std::vector<std::string>& prefixes,
                                    const std::vector<std::string>& tail = {}) {
  for (const std::string& p : prefixes)
    for (const char* c : {"_r", "_g", "_b"}) head.push_back(p + c);
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

template <typename Fit>
void requireUniqueNames(const fs::path& path, const std::vector<Fit>& fits, const std::vector<int>& lines) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < fits.size(); ++i)
    if (!seen.insert(fits[i].name).second)
      throw FileError(path, "line " + std::to_string(lines[i]) + ": duplicate material '" + fits[i].name + "'");
}

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::vector<SgdFit> readSgdFits(const fs::path& csv) {
  static const std::vector<std::string> prefixes = {"rhoD", "rhoS", "alpha", "p", "f0", "f1", "kap",
                                                    "lambda", "c", "k", "theta0", "error"};
  const std::vector<std::string> columns = rgbColumns({"material", "other_name"}, prefixes);
  std::vector<SgdFit> fits;
  std::vector<int> lines;
  for (const CsvRow& row : readCsv(csv, columns)) {
    const RowReader r(csv, columns, row);
    SgdFit fit{r.name("material"), r.text("other_name"), {}, r.rgb("error")};
    for (int c = 0; c < 3; ++c) {
      const std::string suffix = std::string("_") + "rgb"[c];
      auto value = [&](const char* prefix) { return r.number((prefix + suffix).c_str()); };
      fit.parameters.channel[c] = {value("rhoD"), value("rhoS"), value("alpha"), value("p"), value("f0"), value("f1"),
                                   value("kap"),  value("lambda"), value("c"),   value("k"), value("theta0")};
      if (!(fit.parameters.channel[c].alpha > 0)) r.fail(("alpha" + suffix).c_str(), "must be > 0");
    }
    fits.push_back(std::move(fit));
    lines.push_back(row.line);
  }
  requireUniqueNames(csv, fits, lines);
  return fits;
}

std::vector<AbcFit> readAbcFits(const fs::path& csv) {
  const std::vector<std::string> columns = rgbColumns({"material"}, {"kD", "A"}, {"B", "C", "ior"});
  std::vector<AbcFit> fits;
  std::vector<int> lines;
  for (const CsvRow& row : readCsv(csv, columns)) {
    const RowReader r(csv, columns, row);
    fits.push_back({r.name("material"), {r.rgb("kD"), r.rgb("A"), r.number("B"), r.number("C"), r.number("ior")}});
    lines.push_back(row.line);
  }
  requireUniqueNames(csv, fits, lines);
  return fits;
}

std::vector<LafortuneFit> readLafortuneFits(const fs::path& csv) {
  const std::vector<std::string> columns = rgbColumns({"index", "material"}, {"rho_d", "rho_s"}, {"Cxy", "Cz", "n"});
  std::vector<LafortuneFit> fits;
  std::vector<int> lines;
  for (const CsvRow& row : readCsv(csv, columns)) {
    const RowReader r(csv, columns, row);
    const double index = r.number("index");
    if (index != std::floor(index)) r.fail("index", "must be a whole number");
    fits.push_back({int(index), r.name("material"), r.rgb("rho_d"), r.rgb("rho_s"), float(r.number("Cxy")),
                    float(r.number("Cz")), float(r.number("n"))});
    lines.push_back(row.line);
  }
  requireUniqueNames(csv, fits, lines);
  return fits;
}

MerlFits MerlFits::load(const fs::path& folder) {
  return MerlFits(readSgdFits(folder / kSgdFitsFile), readAbcFits(folder / kAbcFitsFile),
                  readLafortuneFits(folder / kLafortuneFitsFile));
}

MerlFits::MerlFits(std::vector<SgdFit> sgd, std::vector<AbcFit> abc, std::vector<LafortuneFit> lafortune)
    : sgd_(std::move(sgd)), abc_(std::move(abc)), lafortune_(std::move(lafortune)) {}

std::vector<std::string> MerlFits::names() const {
  std::set<std::string> all;
  for (const SgdFit& f : sgd_) all.insert(f.name);
  for (const AbcFit& f : abc_) all.insert(f.name);
  for (const LafortuneFit& f : lafortune_) all.insert(f.name);
  return {all.begin(), all.end()};
}

bool MerlFits::isMerl(std::string_view name) const { return findSgd(name) || findAbc(name); }

const SgdFit* MerlFits::findSgd(std::string_view name) const {
  const auto it = std::find_if(sgd_.begin(), sgd_.end(), [&](const SgdFit& f) { return f.name == name; });
  return it == sgd_.end() ? nullptr : &*it;
}
const AbcFit* MerlFits::findAbc(std::string_view name) const {
  const auto it = std::find_if(abc_.begin(), abc_.end(), [&](const AbcFit& f) { return f.name == name; });
  return it == abc_.end() ? nullptr : &*it;
}
const LafortuneFit* MerlFits::findLafortune(std::string_view name) const {
  const auto it = std::find_if(lafortune_.begin(), lafortune_.end(), [&](const LafortuneFit& f) { return f.name == name; });
  return it == lafortune_.end() ? nullptr : &*it;
}

std::string MerlFits::resolve(std::string_view name) const {
  if (findSgd(name) || findAbc(name) || findLafortune(name)) return std::string(name);
  for (const SgdFit& f : sgd_)
    if (!f.other_name.empty() && f.other_name == name) return f.name;
  // Suggest the closest names (and alternative names): a typo is a few edits away; a part of a
  // name ("gold") is contained in it.
  std::vector<std::pair<std::size_t, std::string>> ranked;
  auto consider = [&](const std::string& candidate, const std::string& shown) {
    std::size_t d = editDistance(name, candidate);
    if (!name.empty() && candidate.find(name) != std::string::npos) d = std::min<std::size_t>(d, 1);
    if (d <= std::max<std::size_t>(3, name.size() / 3)) ranked.emplace_back(d, shown);
  };
  for (const std::string& n : names()) consider(n, n);
  for (const SgdFit& f : sgd_)
    if (!f.other_name.empty() && f.other_name != f.name) consider(f.other_name, f.other_name + " (= " + f.name + ")");
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string message = "unknown MERL material '" + std::string(name) + "'";
  if (ranked.empty()) throw Error(message + " (btf-datagen --list-merl-fits lists the names)");
  message += "; did you mean ";
  for (std::size_t i = 0; i < std::min<std::size_t>(3, ranked.size()); ++i)
    message += (i ? ", " : "") + ranked[i].second;
  throw Error(message + "?");
}

std::vector<ModelFamily> MerlFits::modelsFor(std::string_view name) const {
  const std::string canonical = resolve(name);
  std::vector<ModelFamily> models;
  if (findSgd(canonical)) models.push_back(ModelFamily::Sgd);
  if (findAbc(canonical)) models.push_back(ModelFamily::Abc);
  if (findLafortune(canonical)) models.push_back(ModelFamily::Lafortune);
  return models;
}

std::unique_ptr<Material> makeMerlFitMaterial(const MerlFits& fits, std::string_view name, ModelFamily model) {
  const std::string canonical = fits.resolve(name);
  switch (model) {
    case ModelFamily::Sgd:
      if (const SgdFit* f = fits.findSgd(canonical)) return std::make_unique<Sgd>(f->parameters, canonical);
      break;
    case ModelFamily::Abc:
      if (const AbcFit* f = fits.findAbc(canonical)) return std::make_unique<Abc>(f->parameters, canonical);
      break;
    case ModelFamily::Lafortune:
      if (const LafortuneFit* f = fits.findLafortune(canonical))
        return std::make_unique<Lafortune>(f->rho_d, std::vector<LafortuneLobe>{{f->rho_s, {f->cxy, f->cxy, f->cz}, f->n}});
      break;
    default: (void)parseModelFamily(modelFamilyName(model), kPublishedFitFamilies);  // names the published ones
  }
  std::string available;
  for (ModelFamily m : fits.modelsFor(canonical)) available += (available.empty() ? "" : ", ") + std::string(modelFamilyName(m));
  throw Error("no " + std::string(modelFamilyName(model)) + " fit of '" + canonical + "' (" +
              (model == ModelFamily::Lafortune ? "Ngan et al.'s table lacks 14 MERL materials; " : "") +
              "fits of it: " + available + ")");
}

fs::path findMerlFitsFolder(const std::vector<fs::path>& candidates) {
  std::string tried;
  for (const fs::path& folder : candidates) {
    if (folder.empty()) continue;
    std::string missing;
    for (const char* file : {kSgdFitsFile, kAbcFitsFile, kLafortuneFitsFile})
      if (!fs::is_regular_file(folder / file)) missing += (missing.empty() ? "" : ", ") + std::string(file);
    if (missing.empty()) return folder;
    tried += "\n  " + folder.string() + " (missing " + missing + ")";
  }
  throw Error("no folder with the MERL fit tables (" + std::string(kSgdFitsFile) + ", " + kAbcFitsFile + ", " +
              kLafortuneFitsFile + "); tried:" + (tried.empty() ? std::string(" nothing") : tried));
}

std::vector<fs::path> defaultMerlFitsFolders() {
  std::vector<fs::path> folders;
  if (const char* env = std::getenv("BTF_FITS_DIR"); env && *env) folders.emplace_back(env);
  folders.emplace_back(BTF_FITS_BUILD_DIR);
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&defaultMerlFitsFolders), &info) != 0 && info.dli_fname != nullptr)
    folders.push_back((fs::path(info.dli_fname).parent_path() / BTF_FITS_INSTALL_RELATIVE).lexically_normal());
  return folders;
}

MerlFits loadMerlFits(const fs::path& folder) {
  // A named folder that lacks the tables is a mistake to report, not to paper over.
  if (!folder.empty()) return MerlFits::load(findMerlFitsFolder({folder}));
  return MerlFits::load(findMerlFitsFolder(defaultMerlFitsFolders()));
}

BTF_REGISTER_MATERIAL(merl_fit, {.name = "merl-fit",
                                 .summary = "a published analytic fit of a MERL material",
                                 .keys = {"name", "model", "fits_dir"},
                                 .spec_keys = {"model", "name"},
                                 .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                   const MerlFits fits = loadMerlFits(p.has("fits_dir") ? p.existingPath("fits_dir") : fs::path());
                                   const ModelFamily model = p.has("model")
                                                                 ? parseModelFamily(p.string("model"), kPublishedFitFamilies)
                                                                 : ModelFamily::Sgd;
                                   return makeMerlFitMaterial(fits, p.string("name"), model);
                                 },
                                 .label = [](const MaterialParams& p) {
                                   return p.string("name") + "-" + (p.has("model") ? p.string("model") : "sgd");
                                 }});

}  // namespace btf
