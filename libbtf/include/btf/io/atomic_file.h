// Writes that never leave a half-written output: data goes to a temporary file in the same folder,
// which is renamed over the destination only once it is complete.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>

namespace btf {

// Calls write(stream) on a temporary file beside `path`, then renames it to `path`. On any
// exception (or a stream failure) the temporary file is removed and FileError is thrown.
void writeFileAtomically(const std::filesystem::path& path, const std::function<void(std::ofstream&)>& write);

// For writers that need a file name (OpenImageIO): calls write(temporary_path), then renames.
void writeViaTemporaryPath(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write);

// Throws FileError unless `path` names an existing regular file that can be opened for reading.
void requireReadableFile(const std::filesystem::path& path);

}  // namespace btf
