#include "image_backend.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>

#include "btf/core/error.h"
#include "btf/io/image.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

// Whether the backend is loaded and whether OpenEXR is to decode in the calling threads, under one
// mutex so that a call of decodeExrInCallingThreads during the load is not lost.
std::mutex g_mutex;
image_backend::Backend* g_loaded = nullptr;
bool g_exr_in_calling_threads = false;

// The module sits beside the libbtf that loads it, in the build tree and where it is installed
// alike, so it is found by this library's own path (not the program's, not LD_LIBRARY_PATH).
fs::path modulePath() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&imageBackend), &info) != 0 && info.dli_fname != nullptr)
    return fs::path(info.dli_fname).parent_path() / image_backend::kModuleFileName;
  return image_backend::kModuleFileName;
}

image_backend::Backend* load() {
  const fs::path path = modulePath();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw Error("cannot load libbtf's image backend " + path.string() + ", which reads and writes every image file: " +
                (why ? why : "unknown error"));
  }
  auto entry = reinterpret_cast<image_backend::EntryPoint>(dlsym(handle, image_backend::kEntryPointName));
  image_backend::Backend* backend = entry ? entry(image_backend::kAbiVersion) : nullptr;
  if (!backend)
    throw Error("libbtf's image backend " + path.string() + " was built for another version of libbtf");
  std::lock_guard lock(g_mutex);
  if (g_exr_in_calling_threads) backend->decodeExrInCallingThreads();
  g_loaded = backend;
  return backend;
}

}  // namespace

image_backend::Backend& imageBackend() {
  // The first call loads the module (a throw leaves it unloaded, and the next call tries again);
  // the handle is never closed, as the backend's objects may live until the program ends.
  static image_backend::Backend* const backend = load();
  return *backend;
}

void decodeExrInCallingThreads() {
  const char* options = std::getenv("OPENIMAGEIO_OPTIONS");
  if (options && std::string_view(options).find("exr_threads") != std::string_view::npos) return;
  // Applied when the backend loads, or now if it has; loading it here would make every program
  // that calls this at start pay for the image libraries whether it reads images or not.
  std::lock_guard lock(g_mutex);
  g_exr_in_calling_threads = true;
  if (g_loaded) g_loaded->decodeExrInCallingThreads();
}

}  // namespace btf
