#include "btf/core/terminal.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include "btf/core/progress.h"

namespace btf {
namespace {

// "1:05" or "1:02:05".
std::string clockText(double seconds) {
  const long s = long(seconds + 0.5);
  char text[32];
  if (s >= 3600) std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

}  // namespace

void installTerminalHooks() {
  setLogHook([](LogLevel level, std::string_view message) {
    std::fprintf(stderr, "%s%.*s\n", level == LogLevel::Warning ? "warning: " : "",
                 int(message.size()), message.data());
  });
  if (!::isatty(STDERR_FILENO)) return;  // quiet when output is not a terminal
  setProgressHook([](std::string_view task, std::uint64_t done, std::uint64_t total) {
    // The time left is the elapsed time scaled by the work left: a task's start is the first call
    // seen for its name (calls of one task come in order; a new name starts a new clock).
    static std::mutex mutex;
    static std::string current;
    static std::chrono::steady_clock::time_point start;
    const std::lock_guard lock(mutex);
    const auto now = std::chrono::steady_clock::now();
    if (task != current) {
      current = std::string(task);
      start = now;
    }
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double fraction = total ? double(done) / double(total) : 1.0;
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth + 0.5);
    std::string timing = ", " + clockText(elapsed);
    if (done > 0 && done < total) timing += ", " + clockText(elapsed * double(total - done) / double(done)) + " left";
    std::fprintf(stderr, "\r%.*s [%s%s] %3d%% %llu/%llu%s   ", int(task.size()), task.data(),
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(), int(fraction * 100 + 0.5),
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total), timing.c_str());
    if (done >= total) {
      std::fputc('\n', stderr);
      current.clear();
    }
    std::fflush(stderr);
  });
}

}  // namespace btf
