// Fit files (`btf fit -o params.json`): readFitFile, as `btf info/eval/sample` and scenes'
// {"type": "fitted"} materials read them; a model that loads is evaluated and sampled.
#include "btf/fit/fit_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.json");
  btf::fuzz::acceptingFileErrors([&] { btf::fuzz::exerciseMaterial(*btf::makeAnalyticMaterial(btf::readFitFile(path))); });
  return 0;
}
