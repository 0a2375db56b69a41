// `btf bench compressibility` (bench_compressibility.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchCompressibilityCommand(CLI::App& bench);

}  // namespace btf::cli
