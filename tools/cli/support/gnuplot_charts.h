// Charts drawn by gnuplot (Debian gnuplot-nox) run as a subprocess on a generated script, each as
// PNG (pngcairo when gnuplot has it, else png) and SVG. The data is inlined in the script ($name
// data blocks), so the script left beside the charts reproduces them alone. Every image is
// rendered to a temporary name and renamed only once gnuplot succeeded: no half-drawn chart.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace btf::tools {

struct GnuplotChart {
  std::string stem;  // file name without extension
  std::string body;  // gnuplot commands after the terminal and output are set (title, axes, plot)
};

struct GnuplotOutcome {
  std::vector<std::filesystem::path> files;  // written; empty when gnuplot is missing or failed
  std::string message;                       // why nothing was drawn, else empty
};

// A string as a gnuplot double-quoted literal.
std::string gnuplotQuote(const std::string& text);

// Writes `folder/script_name` (header + data blocks + one section per chart and format) and runs it.
GnuplotOutcome drawGnuplotCharts(const std::filesystem::path& folder, const std::string& script_name,
                                 const std::string& data_blocks, const std::vector<GnuplotChart>& charts);

}  // namespace btf::tools
