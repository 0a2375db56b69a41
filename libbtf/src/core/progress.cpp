#include "btf/core/progress.h"

#include <atomic>
#include <chrono>
#include <mutex>

namespace btf {
namespace {

std::mutex g_hook_mutex;
LogHook g_log_hook;
ProgressHook g_progress_hook;

}  // namespace

void setLogHook(LogHook hook) {
  std::lock_guard lock(g_hook_mutex);
  g_log_hook = std::move(hook);
}

void setProgressHook(ProgressHook hook) {
  std::lock_guard lock(g_hook_mutex);
  g_progress_hook = std::move(hook);
}

void log(LogLevel level, std::string_view message) {
  std::lock_guard lock(g_hook_mutex);
  if (g_log_hook) g_log_hook(level, message);
}

struct Progress::State {
  std::atomic<std::uint64_t> done{0};
  std::atomic<std::int64_t> last_report_ns{0};
};

Progress::Progress(std::string task, std::uint64_t total)
    : task_(std::move(task)), total_(total), state_(new State) {}

Progress::~Progress() {
  {
    std::lock_guard lock(g_hook_mutex);
    if (g_progress_hook) g_progress_hook(task_, total_, total_);
  }
  delete state_;
}

void Progress::advance(std::uint64_t amount) {
  const std::uint64_t done = state_->done.fetch_add(amount) + amount;
  using namespace std::chrono;
  const std::int64_t now = duration_cast<nanoseconds>(steady_clock::now().time_since_epoch()).count();
  std::int64_t last = state_->last_report_ns.load();
  constexpr std::int64_t kInterval = 100'000'000;  // 10 reports per second at most
  if (now - last < kInterval || !state_->last_report_ns.compare_exchange_strong(last, now)) return;
  std::lock_guard lock(g_hook_mutex);
  if (g_progress_hook) g_progress_hook(task_, std::min(done, total_), total_);
}

}  // namespace btf
