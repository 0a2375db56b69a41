// Files of a render: the linear EXR a user measures with, a tone-mapped PNG preview beside it, and
// the AOVs. Every file is written atomically (temporary file, then rename), so a failed render
// never leaves a half-written image.
#pragma once

#include <filesystem>
#include <vector>

#include "btf/render/integrator.h"

namespace btf::render {

// Writes result.color to `exr` (which must end in .exr), its preview to the same stem with .png
// (sRGB, exposure in stops), and each AOV present to <stem>.<albedo|normal|depth|samples>.exr.
// Returns the paths written. Throws FileError naming the file that could not be written.
std::vector<std::filesystem::path> writeRenderOutputs(const RenderResult& result, const std::filesystem::path& exr,
                                                      float exposure_stops = 0.0f);

}  // namespace btf::render
