// `btf bench bonn` (bench_bonn.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchBonnCommand(CLI::App& bench);

}  // namespace btf::cli
