// Opening a measured material file by its extension, for every `btf` subcommand that reads one.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "btf/io/merl.h"
#include "btf/material/tabulated_brdf.h"

namespace btf::cli {

enum class MeasuredFormat { MerlBinary, ExrStack, RglTensor, FittedModel, Octree };

// .binary -> MERL, .exr -> the EXR stack `btf convert` writes, .bsdf -> an RGL measured material
// (tensor_file), .json -> an analytic model fitted by `btf fit` (fit/fit_file.h), .octree -> an
// octree table (compress/octree_table.h); FileError for anything else.
MeasuredFormat measuredFormatOf(const std::filesystem::path& path);
std::string describe(MeasuredFormat format);

// The file as a MERL-layout table; an RGL material or a fit is tabulated into it (tabulate()), an
// octree expanded.
MerlTable loadMeasuredTable(const std::filesystem::path& path);
// The file as a Material: a TabulatedBrdf with `lookup` for tables, an RglBrdf (evaluated through
// its own parameterization; `lookup` does not apply) for .bsdf, the analytic model for a fit, an
// OctreeBrdf with `lookup` for an octree.
std::unique_ptr<Material> loadMeasuredMaterial(const std::filesystem::path& path, TableLookup lookup);

// The --lookup option of several subcommands (tableLookupName gives the name back); throws
// btf::Error for a name that is none of the lookups.
TableLookup parseLookup(const std::string& name);

}  // namespace btf::cli
