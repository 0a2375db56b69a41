// `btf bench ...`: the experiments, registered by the program beside the verbs (tools/cli/main.cpp).
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

// Adds `bench` and its sub-verbs (sampling, compression, compressibility, fits, render, decode).
void registerBenchCommand(CLI::App& app);

}  // namespace btf::cli
