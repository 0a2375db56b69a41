// `btf bench compression` (bench_compression.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchCompressionCommand(CLI::App& bench);

}  // namespace btf::cli
