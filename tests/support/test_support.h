// Helpers shared by the test programs.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/container.h"

namespace btf::test {

// A fresh empty folder for one test, removed when the object goes out of scope.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int exit_code = -1;  // the process's exit status; 128 + signal number when killed by a signal
  std::string output;  // stdout and stderr together
};
// Runs a program with arguments (through /bin/sh, every argument quoted), capturing its output.
CommandResult runCommand(const std::string& program, const std::vector<std::string>& args);

// A copy of the .btfz container `from` written to `to` with its sections edited by `change` (every
// section stored zstd-compressed, checksums recomputed): for tests of readers given files whose
// container is valid but whose content is not. Returns `to`.
std::filesystem::path rewriteContainer(const std::filesystem::path& from, const std::filesystem::path& to,
                                       const std::function<void(std::vector<ContainerSection>&)>& change);

// ../shared/data/real, as configured at build time.
std::filesystem::path sharedDataDir();

// The message of the btf::Error that `call` throws, or "(no error)": for tests of what an error
// names (another exception type propagates and fails the test).
inline std::string errorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace btf::test
