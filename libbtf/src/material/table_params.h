// The "lookup" key of the table types (merl, octree): interpolated unless the set names another.
#pragma once

#include "btf/material/material_params.h"
#include "btf/material/tabulated_brdf.h"

namespace btf {

inline TableLookup tableLookupParam(const MaterialParams& params) {
  if (!params.has("lookup")) return TableLookup::Interpolated;
  const std::optional<TableLookup> named = parseTableLookup(params.string("lookup"));
  if (!named) params.fail("lookup", std::string("expected ") + kTableLookupNames);
  return *named;
}

}  // namespace btf
