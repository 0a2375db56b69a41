#include "btf/io/atomic_file.h"

#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <mutex>
#include <set>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "btf/core/error.h"
#include "btf/core/progress.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

// The temporaries being written, in fixed storage that a signal handler can read without locks or
// allocation: a slot is claimed by compare-and-swap, filled, then published.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled or emptied, 2 a file, 3 a folder
  char path[kPathBytes];
};
std::array<Slot, kSlots> slots;

// Removes a folder and what is in it with system calls only (the handler's context; a temporary
// folder holds files, no subfolders).
void removeFolder(const char* path) {
  if (DIR* dir = ::opendir(path)) {
    char child[kPathBytes];
    while (const dirent* entry = ::readdir(dir)) {
      if (std::strcmp(entry->d_name, ".") == 0 || std::strcmp(entry->d_name, "..") == 0) continue;
      const std::size_t a = std::strlen(path), b = std::strlen(entry->d_name);
      if (a + 1 + b + 1 > sizeof child) continue;
      std::memcpy(child, path, a);
      child[a] = '/';
      std::memcpy(child + a + 1, entry->d_name, b + 1);
      ::unlink(child);
    }
    ::closedir(dir);
  }
  ::rmdir(path);
}

void onSignal(int signal) {
  for (Slot& slot : slots) {
    const int state = slot.state.load();
    if (state == 2) ::unlink(slot.path);
    if (state == 3) removeFolder(slot.path);
  }
  ::signal(signal, SIG_DFL);  // and end as the signal would have
  ::raise(signal);
}

// The pid in a name this library gives its temporaries, ".<stem>.tmp<pid>-<n><ext>" (a file) or
// ".<name>.tmp<pid>-<n>" (a folder), or 0 for any other name.
long temporaryOwner(const std::string& name) {
  const std::size_t tmp = name.rfind(".tmp");
  if (name.empty() || name[0] != '.' || tmp == 0 || tmp == std::string::npos) return 0;
  std::size_t at = tmp + 4;
  const std::size_t pid_end = name.find_first_not_of("0123456789", at);
  if (pid_end == at || pid_end == std::string::npos || name[pid_end] != '-') return 0;
  const std::size_t n_end = name.find_first_not_of("0123456789", pid_end + 1);
  if (n_end == pid_end + 1 || (n_end != std::string::npos && name[n_end] != '.')) return 0;
  return std::stol(name.substr(at, pid_end - at));
}

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

TemporaryGuard::TemporaryGuard(const fs::path& path, bool folder) : slot_(-1) {
  const std::string text = fs::absolute(path).string();
  if (text.size() >= kPathBytes) return;  // too long to remember: left to removeStaleTemporaries
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!slots[std::size_t(i)].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slots[std::size_t(i)].path, text.c_str(), text.size() + 1);
    slots[std::size_t(i)].state.store(folder ? 3 : 2);
    slot_ = i;
    return;
  }
}

TemporaryGuard::~TemporaryGuard() {
  if (slot_ >= 0) slots[std::size_t(slot_)].state.store(0);
}

void removeTemporariesOnSignals() {
  for (const int signal : {SIGINT, SIGTERM}) {
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal, &action, nullptr);
  }
}

std::size_t removeStaleTemporaries(const fs::path& path) {
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  // Once per folder and process: what an earlier run left is there before this process writes, and
  // a writer of many files into one folder (an image-folder BTF) must not list it for each of them.
  {
    static std::mutex mutex;
    static std::set<fs::path> scanned;
    const std::lock_guard lock(mutex);
    if (!scanned.insert(fs::absolute(folder).lexically_normal()).second) return 0;
  }
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const long owner = temporaryOwner(entry.path().filename().string());
    if (owner <= 0 || owner == long(::getpid())) continue;
    if (::kill(pid_t(owner), 0) == 0 || errno != ESRCH) continue;  // its writer still runs
    std::error_code ignored;
    if (fs::remove_all(entry.path(), ignored) > 0) {
      ++removed;
      log(LogLevel::Warning, entry.path().string() + ": removed, a temporary that an interrupted run left");
    }
  }
  return removed;
}

void writeViaTemporaryPath(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  requireWritableDestination(path);
  removeStaleTemporaries(path);
  const fs::path tmp = temporaryPathFor(path);
  const TemporaryGuard guard(tmp, false);
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
