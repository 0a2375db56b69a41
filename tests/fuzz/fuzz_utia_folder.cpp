// UTIA-layout folders (btf/io/btf_images.h): the input is the database's list of shifted lights
// (number, theta, phi, theta_lS, phi_lS per line) that btf.json names, beside a small valid folder
// (one view of 2 x 2 texels, float XYZ EXR, made by our writer at start-up). The folder is opened
// (the subfolder scan, the list, the view-dependent light set) and its view decoded.
#include <fstream>

#include "btf/io/btf_images.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path f = btf::fuzz::writeSmallUtiaFolder();
    std::ofstream(f / btf::kBtfSidecarName) << R"({"direction_list": "directions.txt"})";
    return f;
  }();
  btf::fuzz::writeFile(folder / "directions.txt", {data, size});
  btf::fuzz::acceptingFileErrors([&] {
    const btf::BtfImageFolder btf = btf::BtfImageFolder::open(folder);
    btf::fuzz::exerciseDecode(btf);
  });
  return 0;
}
