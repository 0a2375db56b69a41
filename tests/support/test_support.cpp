#include "support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <stdexcept>

namespace btf::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("btf-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

namespace {
std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
}  // namespace

CommandResult runCommand(const std::string& program, const std::vector<std::string>& args) {
  std::string command = shellQuote(program);
  for (const auto& a : args) {
    command += ' ';  // appended separately: GCC 12 warns falsely (-Wrestrict) on " " + std::string&&
    command += shellQuote(a);
  }
  command += " 2>&1 </dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + program);
  CommandResult result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  if (WIFEXITED(status)) {
    result.exit_code = WEXITSTATUS(status);
    // The shell reports a child killed by signal N as exit status 128 + N.
  } else if (WIFSIGNALED(status)) {
    result.exit_code = 128 + WTERMSIG(status);
  }
  return result;
}

fs::path rewriteContainer(const fs::path& from, const fs::path& to,
                          const std::function<void(std::vector<ContainerSection>&)>& change) {
  auto sections = readContainer(from);
  for (auto& s : sections) s.compress = true;
  change(sections);
  writeContainer(to, sections);
  return to;
}

fs::path sharedDataDir() { return BTF_SHARED_DATA_DIR; }

}  // namespace btf::test
