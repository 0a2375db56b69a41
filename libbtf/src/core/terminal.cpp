#include "btf/core/terminal.h"

#include <unistd.h>

#include <cstdio>
#include <string>

#include "btf/core/progress.h"

namespace btf {

void installTerminalHooks() {
  setLogHook([](LogLevel level, std::string_view message) {
    std::fprintf(stderr, "%s%.*s\n", level == LogLevel::Warning ? "warning: " : "",
                 int(message.size()), message.data());
  });
  if (!::isatty(STDERR_FILENO)) return;  // quiet when output is not a terminal
  setProgressHook([](std::string_view task, std::uint64_t done, std::uint64_t total) {
    const double fraction = total ? double(done) / double(total) : 1.0;
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth + 0.5);
    std::fprintf(stderr, "\r%.*s [%s%s] %3d%%", int(task.size()), task.data(), std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), int(fraction * 100 + 0.5));
    if (done >= total) std::fputc('\n', stderr);
    std::fflush(stderr);
  });
}

}  // namespace btf
