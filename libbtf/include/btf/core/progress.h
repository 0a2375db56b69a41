// The only way libbtf talks to a terminal: the command line installs hooks, the library calls them.
// With no hook installed, progress and log messages are dropped.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace btf {

enum class LogLevel { Info, Warning };

using LogHook = std::function<void(LogLevel, std::string_view message)>;
// done and total count units of work of one named task; called with done == total at the end.
using ProgressHook = std::function<void(std::string_view task, std::uint64_t done, std::uint64_t total)>;

void setLogHook(LogHook hook);
void setProgressHook(ProgressHook hook);

void log(LogLevel level, std::string_view message);

// Reports progress of one task, throttled to a few calls per second, and 100% on destruction.
class Progress {
 public:
  Progress(std::string task, std::uint64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Thread-safe; `amount` more units are done.
  void advance(std::uint64_t amount = 1);

 private:
  std::string task_;
  std::uint64_t total_;
  struct State;
  State* state_;
};

}  // namespace btf
