// Images written past libbtf's writer, which refuses non-finite values: for tests of the readers
// given files with NaN or infinity in them (OpenImageIO directly, uncompressed float).
#pragma once

#include <filesystem>
#include <vector>

#include "btf/io/image.h"

namespace btf::test {

void writeRawImage(const std::filesystem::path& path, const Image& image);
// A multi-part EXR, one part per layer with its name and attributes, as writeImageStack writes.
void writeRawImageStack(const std::filesystem::path& path, const std::vector<StackLayer>& layers);

}  // namespace btf::test
