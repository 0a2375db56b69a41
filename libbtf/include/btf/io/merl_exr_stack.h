// The EXR view of a MERL table written by `btf convert`: a multi-part EXR with one part per
// theta_h index (90 parts, named theta_h_00 .. theta_h_89), each a 180 x 90 RGB float image with
// x = phi_d index (1 deg steps over [0, 180)) and y = theta_d index (1 deg steps over [0, 90)),
// holding f in 1/sr (MERL's channel scales applied). Unmeasured samples stay negative, exactly as
// in the MERL file (its -1 becomes -1 * channel scale), so EXR -> MERL restores them; NaN and
// infinity are rejected on reading. Values are 32-bit floats: a MERL -> EXR -> MERL round trip
// reproduces every value to a relative 2^-24 (MERL stores doubles).
#pragma once

#include <filesystem>
#include <vector>

#include "btf/io/image.h"
#include "btf/io/merl.h"

namespace btf {

std::vector<StackLayer> merlToExrStack(const MerlTable& table);

// Throws FileError (naming `path`) unless the stack has the layout above and only finite values.
MerlTable exrStackToMerl(const std::filesystem::path& path, const std::vector<StackLayer>& layers);

}  // namespace btf
