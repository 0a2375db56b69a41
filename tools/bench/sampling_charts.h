// The charts of `btf bench sampling`, drawn by gnuplot (Debian gnuplot-nox) run as a subprocess on
// a generated script, each as PNG (pngcairo if gnuplot has it, else png) and SVG:
//   sampling_memory_vs_error   bytes of the tables against rel_error_vs_reference (log-log)
//   sampling_speed_vs_error    samples_per_s against rel_error_vs_reference (log-log)
//   sampling_efficiency        efficiency per material at the first view, one bar per sampler (log)
//   sampling_vs_own_MATERIAL   efficiency / the material's own sampler's against theta_o: tabulated
//                              and DP-CDF (middle epsilon; single queries and stream) per
//                              parameterization
//   sampling_variance_vs_own_MATERIAL  variance per sample, own / ours, against theta_o: under the
//                              environment and of f cos alone, with the environment bound of an
//                              exactly proportional sampler
// The data is inlined in the script, so the script alone reproduces the charts.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sampling_table.h"

namespace btf::cli {

struct ChartOutcome {
  std::vector<std::filesystem::path> files;  // written, empty when gnuplot is missing or failed
  std::string message;                       // why nothing was drawn, else empty
};

// Writes the charts into `folder` atomically (each image rendered to a temporary name, then
// renamed); the script stays beside them as sampling_charts.gp.
ChartOutcome drawSamplingCharts(const std::filesystem::path& folder, const std::vector<SamplingRow>& rows);

}  // namespace btf::cli
