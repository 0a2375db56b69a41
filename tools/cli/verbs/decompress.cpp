// `btf decompress IN.btfz OUT [--material NAME]`: a .btfz decoded to an image folder (EXR or PNG)
// or to a Bonn .btf file (OUT ending in .btf; support/btf_output.h).
#include <filesystem>
#include <memory>
#include <string>

#include "btf/compress/compressed_btf.h"
#include "btf/core/error.h"
#include "btf_output.h"
#include "commands.h"

namespace btf::cli {

void registerDecompressCommand(CLI::App& app) {
  auto in = std::make_shared<std::string>(), out = std::make_shared<std::string>();
  auto options = std::make_shared<BtfOutputOptions>();
  auto* dec = app.add_subcommand(
      "decompress",
      "Decode a .btfz file to an image folder (one image per view and light) or to a Bonn .btf file (OUT ending in .btf)");
  dec->add_option("IN", *in, "Input .btfz")->required();
  dec->add_option("OUT", *out, "Output folder or .btf file, written atomically")->required();
  addBtfOutputOptions(*dec, *options);
  auto material = std::make_shared<std::string>();
  dec->add_option("--material", *material, "The material to decompress from a database (btf info lists them)");
  dec->callback([in, out, options, material] {
    if (std::filesystem::path(*in).extension() != ".btfz") throw FileError(*in, "is not a .btfz file");
    writeBtfOutput(*readCompressedBtf(*in, *material), *out, *options);
  });
}

}  // namespace btf::cli
