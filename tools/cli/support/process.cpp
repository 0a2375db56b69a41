#include "process.h"

#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>

#include "btf/core/error.h"

namespace btf::tools {

std::string shellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::filesystem::path programBeside(const std::string& name) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path program = self.parent_path() / name;
  if (ec || !std::filesystem::is_regular_file(program, ec))
    throw Error("cannot find " + name + " beside " + (self.empty() ? std::string("this program") : self.string()) +
                " (build or install both)");
  return program;
}

std::uint64_t peakMemoryBytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return std::uint64_t(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

namespace {

// `argv` run by the shell with stdout to `stdout_path`; throws naming the command when it fails.
void runTo(const std::vector<std::string>& argv, const std::string& stdout_path) {
  std::string command, shown;
  for (const std::string& a : argv) {
    command += (command.empty() ? "" : " ") + shellQuote(a);
    shown += (shown.empty() ? "" : " ") + a;
  }
  const int status = std::system((command + " >" + shellQuote(stdout_path)).c_str());
  if (status != 0) throw Error("`" + shown + "` failed (exit status " + std::to_string(status) + "; its message is above)");
}

}  // namespace

void runCommand(const std::vector<std::string>& argv) { runTo(argv, "/dev/null"); }

nlohmann::json runJsonCommand(const std::vector<std::string>& argv) {
  static std::atomic<int> runs{0};
  const std::filesystem::path out = std::filesystem::temp_directory_path() /
                                    ("btf-run-" + std::to_string(::getpid()) + "-" + std::to_string(runs++) + ".json");
  struct Remove {
    std::filesystem::path path;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
  } remove{out};
  runTo(argv, out.string());
  std::string text;
  {
    std::ifstream in(out);
    std::getline(in, text, '\0');
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw Error("`" + argv.front() + " " + (argv.size() > 1 ? argv[1] : "") + "` printed no JSON report");
  }
}

}  // namespace btf::tools
