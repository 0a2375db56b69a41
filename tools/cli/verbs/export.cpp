// `btf export --runtime IN.btfz OUT [--material NAME]`: the file the engine runtime reads
// (runtime/, libbtf::runtime; compress/vq_runtime_export.h): the .btfz's decoded codebooks as
// flat little-endian arrays, so that the runtime needs no zstd (docs/renderers.md#embedding-the-runtime).
#include <filesystem>
#include <memory>
#include <string>

#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_runtime_export.h"
#include "btf/core/error.h"
#include "commands.h"

namespace btf::cli {

void registerExportCommand(CLI::App& app) {
  auto in = std::make_shared<std::string>(), out = std::make_shared<std::string>(), material = std::make_shared<std::string>();
  auto runtime = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("export", "Write a .btfz in the flat form an engine embeds: --runtime, the file libbtf::runtime reads");
  cmd->add_flag("--runtime", *runtime, "The runtime file (docs/formats.md#runtime-file-btfrt-from-btf-export---runtime): decoded codebooks, no zstd")->required();
  cmd->add_option("IN", *in, "Input .btfz (VQ codebooks, 81-direction set)")->required();
  cmd->add_option("OUT", *out, "Output runtime file (.btfrt), written atomically")->required();
  cmd->add_option("--material", *material, "The material to export from a database (btf info lists them)");
  cmd->callback([in, out, material] {
    if (std::filesystem::path(*in).extension() != ".btfz") throw FileError(*in, "is not a .btfz file");
    writeVqRuntimeFile(VqBtf::read(*in, *material), *out);
  });
}

}  // namespace btf::cli
