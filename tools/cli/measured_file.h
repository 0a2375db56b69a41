// Opening a measured material file by its extension, for every `btf` subcommand that reads one.
#pragma once

#include <filesystem>
#include <string>

#include "btf/io/merl.h"
#include "btf/material/tabulated_brdf.h"

namespace btf::cli {

enum class MeasuredFormat { MerlBinary, ExrStack };

// .binary -> MERL, .exr -> the EXR stack `btf convert` writes; FileError for anything else.
MeasuredFormat measuredFormatOf(const std::filesystem::path& path);
std::string describe(MeasuredFormat format);

MerlTable loadMeasuredTable(const std::filesystem::path& path);

// "nearest" or "interpolated" (the --lookup option of several subcommands).
TableLookup parseLookup(const std::string& name);

}  // namespace btf::cli
