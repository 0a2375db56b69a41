#include "fit_scene_candidates.h"

#include <cctype>
#include <cstdio>
#include <optional>
#include <sstream>

#include "btf/compress/octree_table.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/btf_texel.h"
#include "btf/fit/fit_file.h"
#include "btf/material/btf_material.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/registry.h"

namespace btf::cli {
namespace fs = std::filesystem;

AnalyticFitOptions parseFitSpec(const std::string& spec) {
  AnalyticFitOptions o;
  std::stringstream in(spec);
  std::string part;
  int index = 0;
  while (std::getline(in, part, ':')) {
    if (index++ == 0) {
      o.family = parseModelFamily(part, kFittableFamilies);
    } else if (part == "linear" || part == "log") {
      o.objective = parseFitObjective(part);
    } else if (!part.empty() && part.find_first_not_of("0123456789") == std::string::npos && part.size() < 3) {
      o.lobes = std::stoi(part);
    } else {
      throw Error("fit '" + spec + "': expected family[:lobes][:linear|log], e.g. lafortune:2 or ggx:linear");
    }
  }
  if (o.lobes != 1 && o.family != ModelFamily::Lafortune) throw Error("fit '" + spec + "': lobes are for lafortune");
  if (o.lobes < 1 || o.lobes > 3) throw Error("fit '" + spec + "': lafortune takes 1 to 3 lobes");
  return o;
}

namespace {

std::string fitLabel(const AnalyticFitOptions& o) {
  std::string label = std::string("fit ") + modelFamilyName(o.family);
  if (o.family == ModelFamily::Lafortune) label += " " + std::to_string(o.lobes) + (o.lobes == 1 ? " lobe" : " lobes");
  return label + (o.objective == FitObjective::Linear ? " (linear)" : " (log)");
}

std::string fileStem(const std::string& name, const std::string& what) {
  std::string s = name + "." + what;
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_')) c = '_';
  return s;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

BtfTexelFilter filterOf(const MaterialParams& entry) {
  return entry.has("filter") && entry.string("filter") == "nearest" ? BtfTexelFilter::Nearest : BtfTexelFilter::Bilinear;
}

}  // namespace

bool reducible(const std::string& scene_type) {
  return scene_type == "merl" || scene_type == "rgl" || scene_type == "octree" || scene_type == "btf";
}

std::uint64_t storedBytes(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    std::uint64_t sum = 0;
    for (const auto& e : fs::recursive_directory_iterator(path, ec))
      if (e.is_regular_file(ec)) sum += e.file_size(ec);
    return sum;
  }
  const auto size = fs::file_size(path, ec);
  return ec ? 0 : std::uint64_t(size);
}

std::vector<MaterialCandidate> makeCandidates(const std::string& name, const MaterialParams& entry, const fs::path& file,
                                              std::shared_ptr<const Material> material, const fs::path& work,
                                              const FitSceneSettings& settings) {
  const std::string type = entry.type();
  const bool is_btf = type == "btf";
  std::vector<MaterialCandidate> out;

  // What the fits and compressions read: a BRDF's MERL-layout table (an RGL file tabulated, an
  // octree expanded), or a BTF's own data.
  std::shared_ptr<const MerlTable> table;
  std::shared_ptr<const BtfSource> btf_source;
  std::vector<MeasuredReflectance> mean_texel;
  MaterialParams data = entry;  // the entry as a material alone, without the scene's own keys
  data.erase("sampler").erase("mapping").erase("uv_scale").erase("axis");
  if (is_btf) {
    btf_source = createBtf(data);
    mean_texel = texelMeasurements(btfTexel(*btf_source, std::nullopt));
  } else {
    table = std::make_shared<const MerlTable>(createTable(data));
  }

  for (const std::string& spec : settings.fits) {
    const AnalyticFitOptions options = parseFitSpec(spec);
    MaterialCandidate c;
    c.label = fitLabel(options) + (is_btf ? " of the mean texel" : "");
    c.kind = "fit";
    try {
      const AnalyticFit fit = is_btf ? fitAnalytic(mean_texel, options) : fitAnalytic(*table, options);
      c.file = work / (fileStem(name, spec) + ".fit.json");
      writeFitFile(c.file, fit, file.string() + (is_btf ? " (mean texel)" : ""));
      c.entry = MaterialParams("fitted").set("file", c.file.string());
      c.note = "rel_rmse " + number(fit.report.rel_rmse) + " to the " + (is_btf ? "texel" : "table") + (fit.report.converged ? "" : ", did not converge");
      if (!fit.report.fallback.empty()) c.note += "; " + fit.report.fallback;
      // A degenerate fit (a parameter at a bound, or rel_rmse above kFitRelRmseLimit) is refused
      // whatever its rendered error: in a scene that hides the lobe it would pass by accident.
      if (isDegenerateFit(fit.report)) {
        std::string why;
        for (const std::string& w : fitWarnings(fit.report)) why += (why.empty() ? "" : "; ") + w;
        c.note = "refused for a warning: " + why;
      } else {
        c.material = fit.material;
      }
    } catch (const Error& e) {
      c.note = e.what();
    }
    c.bytes = c.file.empty() ? 0 : storedBytes(c.file);
    out.push_back(std::move(c));
  }

  if (!is_btf)
    for (const double t : settings.octree_tolerances) {
      MaterialCandidate c;
      c.label = "octree t=" + number(t);
      c.kind = "octree";
      auto octree = std::make_shared<const OctreeTable>(OctreeTable::build(*table, t));
      c.file = work / (fileStem(name, "t" + number(t)) + ".octree");
      writeOctreeFile(c.file, *octree);
      c.material = std::make_shared<OctreeBrdf>(octree, TableLookup::Interpolated);
      c.entry = MaterialParams("octree").set("file", c.file.string()).set("lookup", "interpolated");
      c.note = "rel_rmse " + number(tableRelRmse(octree->expand(), *table)) + " to the table";
      c.bytes = storedBytes(c.file);
      out.push_back(std::move(c));
    }

  for (const double eps : settings.vq_epsilons) {
    MaterialCandidate c;
    c.label = "vq eps=" + number(eps) + (is_btf ? "" : " (81 x 81 directions)");
    c.kind = "vq";
    VqOptions options;
    options.epsilon = float(eps);
    try {
      auto vq = std::make_shared<const VqBtf>(is_btf ? compressVq(*btf_source, options)
                                                     : compressVq(brdfAsBtf(*material, name), options));
      c.file = work / (fileStem(name, "eps" + number(eps)) + ".btfz");
      vq->write(c.file);
      c.material = std::make_shared<BtfMaterial>(vq, filterOf(entry));
      c.entry = is_btf ? entry : MaterialParams("btf");
      c.entry.setOrigin({}, {});  // its file is c.file, named from the current directory
      c.entry.set("file", c.file.string()).erase("sampler").erase("material");  // the new file holds this material alone
      c.bytes = storedBytes(c.file);
    } catch (const Error& e) {
      c.note = e.what();
    }
    out.push_back(std::move(c));
  }

  MaterialCandidate full;
  full.label = "full (" + type + ")";
  full.kind = "full";
  full.bytes = storedBytes(file);
  full.material = std::move(material);
  full.entry = entry;
  out.push_back(std::move(full));
  return out;
}

}  // namespace btf::cli
