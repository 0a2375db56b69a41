// Helpers shared by the test programs.
#pragma once

#include <cmath>
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

// The measured RGL materials of the shared data (file stems) and the path of one of them.
inline const std::vector<std::string> kRglFiles = {"cc_ibiza_sunset_rgb", "paper_white_rgb", "vch_golden_yellow_rgb"};
inline std::filesystem::path rglPath(const std::string& stem) { return sharedDataDir() / "rgl_bsdf" / (stem + ".bsdf"); }

// The IEC 61966-2-1 sRGB curves in double, written out here rather than taken from the library.
inline double srgbDecode(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }
inline double srgbEncode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055; }

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
