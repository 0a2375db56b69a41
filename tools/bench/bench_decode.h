// `btf bench decode` (bench_decode.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchDecodeCommand(CLI::App& bench);

}  // namespace btf::cli
