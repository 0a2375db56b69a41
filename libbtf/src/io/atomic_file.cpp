#include "btf/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <system_error>

#include "btf/core/error.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

fs::path temporaryPathFor(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  // Hidden, unique per process and call, and with the extension last: image writers choose the
  // format from it. (Built with append: GCC 12 warns falsely on `"." + std::string`.)
  std::string name(".");
  name.append(path.stem().string())
      .append(".tmp")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(counter++))
      .append(path.extension().string());
  fs::path tmp = path;
  tmp.replace_filename(name);
  return tmp;
}

void requireWritableDestination(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw FileError(path, "is a directory, expected a file name to write");
  const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (!fs::is_directory(parent, ec)) throw FileError(path, "folder " + parent.string() + " does not exist");
}

}  // namespace

void writeViaTemporaryPath(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  requireWritableDestination(path);
  const fs::path tmp = temporaryPathFor(path);
  try {
    write(tmp);
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw FileError(path, "cannot be written: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void writeFileAtomically(const fs::path& path, const std::function<void(std::ofstream&)>& write) {
  writeViaTemporaryPath(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(path, "cannot be opened for writing");
    write(out);
    out.flush();
    if (!out) throw FileError(path, "write failed (disk full?)");
  });
}

void requireReadableFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw FileError(path, "no such file");
  if (fs::is_directory(status)) throw FileError(path, "is a directory, expected a file");
  if (!fs::is_regular_file(status)) throw FileError(path, "is not a regular file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw FileError(path, "cannot be opened for reading (permissions?)");
}

}  // namespace btf
