// Writes that never leave a half-written output: data goes to a temporary file in the same folder,
// which is renamed over the destination only once it is complete.
#pragma once

#include <cstddef>
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

// A temporary file or folder that libbtf is writing, registered while it exists so that
// removeTemporariesOnSignals() can remove it when the program is interrupted. Destroying the guard
// unregisters it (it does not remove it: the writer renames or removes it first).
class TemporaryGuard {
 public:
  TemporaryGuard(const std::filesystem::path& path, bool folder);
  ~TemporaryGuard();
  TemporaryGuard(const TemporaryGuard&) = delete;
  TemporaryGuard& operator=(const TemporaryGuard&) = delete;

 private:
  int slot_;
};

// Installs SIGINT and SIGTERM handlers that remove the temporaries being written, then end the
// process as the signal would have. For programs (the command line calls it at start); a library
// user with handlers of their own leaves it out.
void removeTemporariesOnSignals();

// Temporaries in the folder of `path` that an interrupted earlier run left (named as this library
// names them, by a process that is gone) are removed before the first write into that folder in
// this process; returns how many.
std::size_t removeStaleTemporaries(const std::filesystem::path& path);

// Throws FileError unless `path` names an existing regular file that can be opened for reading.
void requireReadableFile(const std::filesystem::path& path);

}  // namespace btf
