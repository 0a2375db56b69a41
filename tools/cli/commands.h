// The subcommands of `btf`, one source file each. Every register function adds its subcommand to
// the app; the callbacks throw btf::Error (or CLI11 errors) and main turns them into messages.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void registerInfoCommand(CLI::App& app);
void registerEvalCommand(CLI::App& app);
void registerConvertCommand(CLI::App& app);
void registerPlotCommand(CLI::App& app);
void registerSampleCommand(CLI::App& app);
void registerBenchCommand(CLI::App& app);
void registerCompressCommands(CLI::App& app);  // compress, decompress and merge
void registerCompareCommand(CLI::App& app);
void registerRenderCommand(CLI::App& app);
void registerFitCommand(CLI::App& app);
void registerFitSceneCommand(CLI::App& app);

}  // namespace btf::cli
