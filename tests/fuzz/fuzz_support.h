// What every fuzz target shares. The readers take paths, as the command line does, so each input
// becomes a file and goes through the very function `btf` calls; then whatever loaded is evaluated
// and sampled, because a table that loads but crashes on eval is a reader bug too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "btf/core/error.h"

namespace btf {
class Material;
class BtfLookup;
class BtfSource;
namespace render {
struct SceneDescription;
}
}  // namespace btf

namespace btf::fuzz {

// The input as the file `file_name` in a folder private to this process (under /dev/shm when it
// exists: the fuzzer writes one file per input). The next call overwrites it.
std::filesystem::path writeInput(std::span<const std::uint8_t> bytes, std::string_view file_name);
// The private folder itself, emptied (for targets that build a folder of several files).
std::filesystem::path emptyFolder(std::string_view name);
void writeFile(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);

// A small valid image-folder BTF written by our writer into the private folder: one view (the
// pole) of 2 x 2 texels, as EXR or as 8-bit PNG.
std::filesystem::path writeSmallBtfFolder(bool exr);
// The same view in the UTIA layout (tv000_pv000/tl..._tv000_pv000.exr, float XYZ).
std::filesystem::path writeSmallUtiaFolder();

// Runs load(): a btf::Error (a message for the user, naming the file) is the one accepted way to
// fail. Any other exception escapes to libFuzzer, which reports it as a crash with its input.
template <class Load>
void acceptingFileErrors(Load&& load) {
  try {
    load();
  } catch (const btf::Error&) {
  }
}

// Evaluates, samples and takes the pdf of the material on a fixed set of directions (grazing ones
// included) and aborts on a value that is negative or not finite: what loaded must be usable.
void exerciseMaterial(const Material& material);
// Looks up the BTF's corners and centre for every held view and a spread of lights, one by one
// and as a stream (values()), and aborts when the two differ or a value is not finite.
void exerciseLookup(const BtfLookup& btf);
// Decodes every view of the BTF and aborts on a value that is not finite, negative, or beyond
// kMaxReflectance: what libbtf loads is what it may write (btf/core/value_limits.h).
void exerciseDecode(const BtfSource& btf);
// The same rule for a scene: every material's values at a spread of directions, every light's
// radiance, and a tiny render of it, finite.
void exerciseScene(const render::SceneDescription& scene);

}  // namespace btf::fuzz
