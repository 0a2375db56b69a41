// The images of image-folder BTFs: the input replaces the image of light 0 in a small valid folder
// (one view of 2 x 2 texels made by our writer at start-up), an EXR folder when the input starts
// with the EXR magic number and an 8-bit PNG folder otherwise. The folder is opened and its view
// loaded, as `btf info`, `btf compress` and scenes do.
#include <cstring>
#include <vector>

#include "btf/io/btf_images.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path exr = btf::fuzz::writeSmallBtfFolder(true);
  static const std::filesystem::path png = btf::fuzz::writeSmallBtfFolder(false);
  const unsigned char exr_magic[] = {0x76, 0x2f, 0x31, 0x01};
  const bool is_exr = size >= 4 && std::memcmp(data, exr_magic, 4) == 0;
  const auto format = is_exr ? btf::BtfImageFormat::Exr : btf::BtfImageFormat::Png8;
  const auto& folder = is_exr ? exr : png;
  btf::fuzz::writeFile(folder / btf::btfImageName(0, 0, format), {data, size});
  btf::fuzz::acceptingFileErrors([&] {
    const btf::BtfImageFolder btf = btf::BtfImageFolder::open(folder);
    btf::fuzz::exerciseDecode(btf);
  });
  return 0;
}
