// How the verbs take a material argument: any path or spec the registry opens
// (btf/material/registry.h), in the form each verb needs, with the words they print about it.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "btf/io/btf_data.h"
#include "btf/material/registry.h"

namespace btf::cli {

// A material as a BTF, for compress, compare, fit and info: a BTF's own data, or a BRDF as a
// one-texel BTF at the 81 x 81 directions.
struct BtfInput {
  IdentifiedMaterial material;
  std::shared_ptr<const BtfSource> source;
  std::string description;  // e.g. "image-folder BTF", "MERL binary (...) as a one-texel BTF at ..."
  bool compressed = false;  // a .btfz file
};
// `database_material` names the material of a .btfz database (empty: the file must hold one).
BtfInput openBtfInput(const std::string& path_or_spec, const std::string& database_material = {});
BtfInput openBtfInput(IdentifiedMaterial material);

// A material for the BRDF verbs (eval, plot, sample, info). `lookup`, when given, is the table
// lookup of a table type; a type without one (an RGL file, a fitted model) refuses it, saying why.
struct BrdfInput {
  IdentifiedMaterial material;
  std::shared_ptr<const Material> brdf;
  const char* evaluation;  // how it is evaluated: the lookup's name, "rgl parameterization", "analytic"
};
BrdfInput openBrdfInput(const std::string& path_or_spec, std::optional<TableLookup> lookup);
// The same for a material identified with OpenOptions::lookup = `lookup` (`path_or_spec` names it).
BrdfInput openBrdfInput(IdentifiedMaterial material, const std::string& path_or_spec, std::optional<TableLookup> lookup);

// True when the material's data is a BTF (varies over the surface).
bool isBtf(const IdentifiedMaterial& material);

// The --lookup option of the verbs that read tables: unset unless given, so that a material with no
// table lookup can refuse it (openBrdfInput). `help` says what the lookup is for in the verb.
void addLookupOption(CLI::App& cmd, std::optional<TableLookup>& lookup, const std::string& help);

// `btf info` for BTFs (an image folder or a .btfz file).
void runBtfInfo(const std::filesystem::path& path, bool json);

}  // namespace btf::cli
