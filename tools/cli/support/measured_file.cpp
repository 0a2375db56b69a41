#include "measured_file.h"

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/fit/fit_file.h"
#include "btf/io/image.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/rgl_brdf.h"
#include "merl_exr_stack.h"

namespace btf::cli {

MeasuredFormat measuredFormatOf(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".binary") return MeasuredFormat::MerlBinary;
  if (ext == ".exr") return MeasuredFormat::ExrStack;
  if (ext == ".bsdf") return MeasuredFormat::RglTensor;
  if (ext == ".json") return MeasuredFormat::FittedModel;
  if (ext == ".octree") return MeasuredFormat::Octree;
  const std::string what = ext.empty() ? "has no extension" : "has the unknown extension '" + ext + "'";
  throw FileError(path, what + " (expected .binary for a MERL table, .exr for a btf convert stack, .bsdf for an RGL material "
                               "a .json btf fit model or an .octree table)");
}

std::string describe(MeasuredFormat format) {
  switch (format) {
    case MeasuredFormat::MerlBinary: return "MERL binary (isotropic BRDF table)";
    case MeasuredFormat::ExrStack: return "EXR stack of MERL half/diff slices (btf convert)";
    case MeasuredFormat::RglTensor: return "RGL measured material (tensor_file, Dupuy & Jakob 2018)";
    case MeasuredFormat::FittedModel: return "analytic model fitted by btf fit";
    case MeasuredFormat::Octree: return "octree table (MERL layout, btf convert --tolerance)";
  }
  return "unknown";
}

MerlTable loadMeasuredTable(const std::filesystem::path& path) {
  switch (measuredFormatOf(path)) {
    case MeasuredFormat::MerlBinary: return readMerl(path);
    case MeasuredFormat::ExrStack: return exrStackToMerl(path, readImageStack(path));
    case MeasuredFormat::RglTensor: return tabulate(RglBrdf(path));
    case MeasuredFormat::FittedModel: return tabulate(*makeAnalyticMaterial(readFitFile(path)));
    case MeasuredFormat::Octree: return readOctreeFile(path).expand();
  }
  throw FileError(path, "unsupported format");
}

std::unique_ptr<Material> loadMeasuredMaterial(const std::filesystem::path& path, TableLookup lookup) {
  if (measuredFormatOf(path) == MeasuredFormat::RglTensor) return std::make_unique<RglBrdf>(path);
  if (measuredFormatOf(path) == MeasuredFormat::FittedModel) return makeAnalyticMaterial(readFitFile(path));
  if (measuredFormatOf(path) == MeasuredFormat::Octree)
    return std::make_unique<OctreeBrdf>(std::make_shared<const OctreeTable>(readOctreeFile(path)), lookup);
  return std::make_unique<TabulatedBrdf>(std::make_shared<const MerlTable>(loadMeasuredTable(path)), lookup);
}

TableLookup parseLookup(const std::string& name) {
  if (const std::optional<TableLookup> lookup = parseTableLookup(name)) return *lookup;
  throw Error("unknown lookup '" + name + "' (expected " + kTableLookupNames + ")");
}

}  // namespace btf::cli
