#include "measured_file.h"

#include "btf/core/error.h"
#include "btf/io/image.h"
#include "merl_exr_stack.h"

namespace btf::cli {

MeasuredFormat measuredFormatOf(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".binary") return MeasuredFormat::MerlBinary;
  if (ext == ".exr") return MeasuredFormat::ExrStack;
  const std::string what = ext.empty() ? "has no extension" : "has the unknown extension '" + ext + "'";
  throw FileError(path, what + " (expected .binary for a MERL table or .exr for a btf convert stack)");
}

std::string describe(MeasuredFormat format) {
  return format == MeasuredFormat::MerlBinary ? "MERL binary (isotropic BRDF table)"
                                              : "EXR stack of MERL half/diff slices (btf convert)";
}

MerlTable loadMeasuredTable(const std::filesystem::path& path) {
  switch (measuredFormatOf(path)) {
    case MeasuredFormat::MerlBinary: return readMerl(path);
    case MeasuredFormat::ExrStack: return exrStackToMerl(path, readImageStack(path));
  }
  throw FileError(path, "unsupported format");
}

TableLookup parseLookup(const std::string& name) {
  if (name == "nearest") return TableLookup::Nearest;
  if (name == "interpolated") return TableLookup::Interpolated;
  throw Error("unknown lookup '" + name + "' (expected nearest or interpolated)");
}

}  // namespace btf::cli
