#include "material_input.h"

#include <algorithm>

#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"

namespace btf::cli {

bool isBtf(const IdentifiedMaterial& material) { return isBtfType(*material.type); }

BtfInput openBtfInput(const std::string& path_or_spec, const std::string& database_material) {
  OpenOptions options;
  options.database_material = database_material;
  return openBtfInput(identifyMaterial(path_or_spec, options));
}

BtfInput openBtfInput(IdentifiedMaterial material) {
  BtfInput input{std::move(material), nullptr, "", false};
  input.source = materialBtf(input.material);
  input.description = input.material.description;
  // A .btfz is compressed (VQ or factor form); a Bonn .btf is factorised too, but it is the measured data as
  // distributed, what users compress.
  if (isBtf(input.material))
    input.compressed = std::dynamic_pointer_cast<const VqBtf>(input.source) != nullptr ||
                       std::dynamic_pointer_cast<const FactorBtf>(input.source) != nullptr;
  else input.description += " as a one-texel BTF at 81 x 81 directions";
  return input;
}

BrdfInput openBrdfInput(const std::string& path_or_spec, std::optional<TableLookup> lookup) {
  OpenOptions options;
  options.lookup = lookup;
  return openBrdfInput(identifyMaterial(path_or_spec, options), path_or_spec, lookup);
}

BrdfInput openBrdfInput(IdentifiedMaterial material, const std::string& path_or_spec, std::optional<TableLookup> lookup) {
  BrdfInput input{std::move(material), nullptr, ""};
  const MaterialType& type = *input.material.type;
  const bool table = std::find(type.keys.begin(), type.keys.end(), "lookup") != type.keys.end();
  if (type.name == "rgl") {
    if (lookup)
      throw Error("--lookup does not apply to " + path_or_spec +
                  ": an RGL .bsdf file is evaluated through its own parameterization (convert it to a MERL table "
                  "with `btf convert` to choose a table lookup)");
    input.evaluation = "rgl parameterization";
  } else if (isBtf(input.material)) {
    if (lookup) throw Error("--lookup does not apply to " + path_or_spec + ": a BTF is looked up by its own texels");
    input.evaluation = "btf texels";
  } else if (!table) {
    if (lookup) throw Error("--lookup does not apply to " + path_or_spec + ": a fitted model is evaluated by its formula");
    input.evaluation = "analytic";
  } else {
    input.evaluation = tableLookupName(lookup.value_or(TableLookup::Interpolated));
  }
  input.brdf = createMaterial(input.material.params);
  return input;
}

void addLookupOption(CLI::App& cmd, std::optional<TableLookup>& lookup, const std::string& help) {
  cmd.add_option_function<std::string>(
         "--lookup", [&lookup](const std::string& name) { lookup = parseTableLookup(name); },
         help + ": interpolated (default), nearest, or truncated (MERL's own reader)")
      ->check(CLI::IsMember({"interpolated", "nearest", "truncated"}));
}

}  // namespace btf::cli
