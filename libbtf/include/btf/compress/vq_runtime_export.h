// The runtime file of a VqBtf: its decoded codebooks as the flat little-endian arrays that the
// engine runtime (runtime/, libbtf::runtime) reads without zstd or any other library
// (layout: runtime/include/btf_runtime/file_layout.h, docs/formats.md#runtime-file-btfrt-from-btf-export---runtime). `btf export
// --runtime` writes it.
#pragma once

#include <filesystem>

#include "btf/compress/vq_btf.h"

namespace btf {

// Writes the file atomically (io/atomic_file.h). Throws btf::Error naming the BTF when the
// runtime cannot evaluate it: today the 81-direction set (views of whole rings from the pole) only.
void writeVqRuntimeFile(const VqBtf& vq, const std::filesystem::path& path);

}  // namespace btf
