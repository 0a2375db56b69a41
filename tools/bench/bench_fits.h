// `btf bench fits` (bench_fits.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchFitsCommand(CLI::App& bench);

}  // namespace btf::cli
