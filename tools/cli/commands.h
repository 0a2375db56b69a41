// The verbs of `btf`, one source file each in verbs/. Every register function adds its verb to the
// app; the callbacks throw btf::Error (or CLI11 errors) and main turns them into messages. main
// decides the order and the groups of `btf --help`.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void registerInfoCommand(CLI::App& app);
void registerEvalCommand(CLI::App& app);
void registerConvertCommand(CLI::App& app);
void registerPlotCommand(CLI::App& app);
void registerSampleCommand(CLI::App& app);
void registerCompressCommand(CLI::App& app);
void registerDecompressCommand(CLI::App& app);
void registerMergeCommand(CLI::App& app);
void registerExportCommand(CLI::App& app);
void registerCompareCommand(CLI::App& app);
void registerRenderCommand(CLI::App& app);
void registerFitCommand(CLI::App& app);
void registerFitSceneCommand(CLI::App& app);

}  // namespace btf::cli
