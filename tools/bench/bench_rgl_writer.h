// `btf bench rgl-writer` (bench_rgl_writer.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchRglWriterCommand(CLI::App& bench);

}  // namespace btf::cli
