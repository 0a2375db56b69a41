// `btf bench render` (bench_render.cpp), added to `btf bench` by bench.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace btf::cli {

void addBenchRenderCommand(CLI::App& bench);

}  // namespace btf::cli
