// MERL .binary tables: readMerl (every `btf` verb that opens a .binary), then the table evaluated
// and sampled as a TabulatedBrdf. A valid table is 33 MB, beyond what a fuzzer mutates, so this
// target explores the header, size and value checks; the tables themselves are tested on real files.
#include <memory>

#include "btf/io/merl.h"
#include "btf/material/tabulated_brdf.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.binary");
  btf::fuzz::acceptingFileErrors([&] {
    auto table = std::make_shared<const btf::MerlTable>(btf::readMerl(path));
    btf::fuzz::exerciseMaterial(btf::TabulatedBrdf(table));
  });
  return 0;
}
