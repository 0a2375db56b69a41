// The one place that decides how a compressed BTF (.btfz) is read: by the "format" of its header,
// a VQ file or database (vq_btf.h, vq_database.h) or a factor file (factor_btf.h).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "btf/io/btf_data.h"

namespace btf {

// True for the container formats that hold a BTF: "libbtf-vq", "libbtf-vq-database", "libbtf-factor".
bool isCompressedBtfFormat(std::string_view format);

// The "format" its header names ("libbtf-vq", "libbtf-factor", ...). Throws FileError naming the
// file when it cannot be opened or is not a libbtf container.
std::string compressedBtfFormat(const std::filesystem::path& path);

// The BTF of a .btfz file (`material` names one material of a database; empty for a single
// material or a database of one). The result is also a BtfLookup. Throws FileError naming the file
// for a container that holds no BTF, or a `material` given for a file that is not a database.
std::shared_ptr<const BtfSource> readCompressedBtf(const std::filesystem::path& path, std::string_view material = {});

}  // namespace btf
