// The direction set and the views held of a compressed BTF in its .btfz JSON header, shared by the
// VQ files (vq_directions.cpp, which adds their ring layout) and the factor files (factor_io.cpp).
//
// Files on the 81-direction UBO2003 set carry no "directions": the set is implied (every file
// written before other sets were read). Any other set is stored whole, as angles in degrees (a
// float printed as the double it is reads back bit for bit), under "directions": {"name", "views":
// [[theta, phi]...], "lights": one list shared by all views or one per view, "nominal": "ubo2003"
// for a set indexed as UBO2003}. "views" lists the views held, only when some are missing.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "btf/core/btf_view_set.h"

namespace btf {

void addDirectionSetHeader(const BtfViewSet& views, nlohmann::json& header);
// `what` names the header in messages ("VQ header"). Throws FileError naming `path` for a malformed
// entry, or btf::Error for a set the direction-set checks refuse.
BtfViewSet readDirectionSetHeader(const nlohmann::json& header, const std::filesystem::path& path, const char* what);

}  // namespace btf
