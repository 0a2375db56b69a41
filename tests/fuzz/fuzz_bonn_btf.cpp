// Bonn .btf files (DFMF, FMF, PVF; btf/io/bonn_btf.h): the header reader that `btf info` uses,
// then every view decoded, so that what opens is finite, non-negative and within the value limits.
#include "btf/io/bonn_btf.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.btf");
  btf::fuzz::acceptingFileErrors([&] {
    (void)btf::readBonnBtfHeader(path);
    btf::fuzz::exerciseDecode(btf::BonnBtf::open(path));
  });
  return 0;
}
