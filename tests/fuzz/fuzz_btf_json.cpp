// Image-folder BTFs, their sidecar and names: the input is btf.json of a small valid folder (one
// view of 2 x 2 texels, 8-bit PNGs made by our writer at start-up) and, taken as a file name, goes
// through parseBtfImageName. BtfImageFolder::open reads the sidecar; the view is then loaded.
#include <string_view>
#include <vector>

#include "btf/io/btf_images.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path folder = btf::fuzz::writeSmallBtfFolder(false);
  btf::fuzz::acceptingFileErrors(
      [&] { (void)btf::parseBtfImageName(std::string_view(reinterpret_cast<const char*>(data), size)); });
  btf::fuzz::writeFile(folder / btf::kBtfSidecarName, {data, size});
  btf::fuzz::acceptingFileErrors([&] {
    const btf::BtfImageFolder btf = btf::BtfImageFolder::open(folder);
    btf::fuzz::exerciseDecode(btf);
  });
  return 0;
}
