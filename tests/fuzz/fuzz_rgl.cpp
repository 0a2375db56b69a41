// RGL measured materials (.bsdf, Mitsuba's tensor_file): the RglBrdf constructor, which reads the
// tensor file and checks every field it uses, then the material evaluated and sampled through its
// own warp.
#include "btf/material/rgl_brdf.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.bsdf");
  btf::fuzz::acceptingFileErrors([&] { btf::fuzz::exerciseMaterial(btf::RglBrdf(path)); });
  return 0;
}
