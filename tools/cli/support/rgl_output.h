// `btf convert X out.bsdf`: any isotropic material, or one texel (or the mean) of a BTF, written as
// an RGL measured material by virtual acquisition (btf/material/rgl_acquisition.h), for pbrt-v4's
// and Mitsuba 3's `measured` materials (with spectra) or Mitsuba 3's RGB variants (--rgb-only), and
// any reader of the RGL database's files.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "btf/material/registry.h"

namespace btf::cli {

struct RglOutputOptions {
  // Unset: an RGL input's own resolutions, else the RGL database's (rgl_acquisition.h).
  std::optional<int> theta_i_count, resolution, vndf_resolution, ndf_resolution;
  std::string description;  // empty: names the source
  std::string texel;        // a BTF input: "X,Y" or "mean"
  bool rgb_only = false;    // no wavelengths/spectra: the file Mitsuba 3's RGB variants load
  bool given() const {
    return theta_i_count || resolution || vndf_resolution || ndf_resolution || !description.empty() || rgb_only;
  }
};

// --theta-i, --resolution, --vndf-resolution, --ndf-resolution, --description, --texel, --rgb-only.
void addRglOutputOptions(CLI::App& cmd, RglOutputOptions& options);

// Writes `out` atomically and prints what it holds and what the conversion lost: rel_rmse of
// f cos and the directional albedo against the source (material_difference.h). Throws FileError
// naming `in` for an anisotropic material, a BTF without --texel, or a material with NaN or
// negative values.
void writeRglOutput(const IdentifiedMaterial& from, const std::string& in, const std::string& out,
                    const RglOutputOptions& options);

}  // namespace btf::cli
