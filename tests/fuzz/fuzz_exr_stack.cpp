// EXR files read through libbtf's image layer: readImageStack (the multi-part MERL-layout stack of
// `btf convert`) and readImage (renders compared by `btf compare`, environment maps of scenes).
#include "btf/io/image.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.exr");
  btf::fuzz::acceptingFileErrors([&] { (void)btf::readImageStack(path); });
  btf::fuzz::acceptingFileErrors([&] { (void)btf::readImage(path); });
  return 0;
}
