// `btf decompress IN.btfz OUT_DIR [--material NAME]`: the image folder of a .btfz (EXR or PNG).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "commands.h"

namespace btf::cli {
namespace {

void runDecompress(const std::string& in, const std::string& out, const std::string& format_name, const std::string& material) {
  BtfImageWriteOptions options;
  if (format_name == "exr") options.format = BtfImageFormat::Exr;
  else if (format_name == "png8" || format_name == "png") options.format = BtfImageFormat::Png8;
  else if (format_name == "png16") options.format = BtfImageFormat::Png16;
  else throw Error("unknown --format '" + format_name + "' (expected exr, png8 or png16)");
  if (std::filesystem::path(in).extension() != ".btfz") throw FileError(in, "is not a .btfz file");
  const VqBtf compressed = VqBtf::read(in, material);
  writeBtfImageFolder(compressed, out, options);
  std::printf("wrote %s: %d x %d texels, %s, %d %s images\n", out.c_str(), compressed.width(), compressed.height(),
              compressed.views().describe().c_str(), compressed.views().count() * kBtfDirectionCount,
              btfImageFormatName(options.format).c_str());
}

}  // namespace

void registerDecompressCommand(CLI::App& app) {
  auto in = std::make_shared<std::string>(), out = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>("exr");
  auto* dec = app.add_subcommand("decompress", "Write the image folder (one image per view and light) of a .btfz file");
  dec->add_option("IN", *in, "Input .btfz")->required();
  dec->add_option("OUT", *out, "Output folder, written atomically (a temporary folder renamed at the end)")->required();
  dec->add_option("--format", *format, "exr (float), png8 or png16 (scaled; btf.json holds the scale)")->capture_default_str();
  auto material = std::make_shared<std::string>();
  dec->add_option("--material", *material, "The material to decompress from a database (btf info lists them)");
  dec->callback([in, out, format, material] { runDecompress(*in, *out, *format, *material); });
}

}  // namespace btf::cli
