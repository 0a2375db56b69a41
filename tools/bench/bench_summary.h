// The printed conclusions of `btf bench sampling`, from its rows (sampling_table.h):
// - the quadtree table: per material and threshold, acceptance rate, samples/s and efficiency,
//   beside the best DP-CDF efficiency of the material, and one line naming the materials where the
//   quadtree's best efficiency beats the DP sampler's best and those where it loses;
// - the memory target "DP-CDF memory <= 1/10 of the full tabulated CDF at equal efficiency within
//   5%": per material and epsilon, bytes / full_cdf_bytes and efficiency / tabulated efficiency,
//   with the epsilons meeting both marked.
// - against the material's own sampler (for an RGL file, the file's warp): per material, theta_o,
//   parameterization and setting, the single-query and stream efficiency ratios and the variance
//   ratios with and without the environment;
// - against the Dupuy-Jakob warp of the material written as an RGL file (dj-warp): per material
//   and view, the best DP-CDF setting within the warp's bytes, its efficiency ratios, and how many
//   materials it reaches the warp's efficiency on.
// Summaries compare rows of one material, theta_o and parameterization (SamplingRow::group).
// Efficiency is a measurement (a variance estimate times a wall time), so a ratio near 0.95 is
// within its noise; the table says so rather than hiding it.
#pragma once

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sampling_table.h"

namespace btf::cli {

void printQuadtreeSummary(std::FILE* out, const std::vector<SamplingRow>& rows);
void printMemoryTargetSummary(std::FILE* out, const std::vector<SamplingRow>& rows);
void printOwnSamplerSummary(std::FILE* out, const std::vector<SamplingRow>& rows);
// DP-CDF at no more bytes than the dj-warp row of the same material and view, against it: per
// dj-warp row, the DP-CDF row of the highest efficiency within the warp's bytes (any epsilon and
// parameterization; null when none fits) and the ratios.
struct WarpComparison {
  std::string material;
  double theta_o_deg = 0, warp_bytes = 0;
  const SamplingRow* dp = nullptr;
  double efficiency_ratio = 0;                        // DP-CDF / warp, single queries
  std::optional<double> stream_ratio, variance_ratio;  // stream efficiencies; warp's variance / DP-CDF's
};
std::vector<WarpComparison> compareWithWarp(const std::vector<SamplingRow>& rows);
void printWarpSummary(std::FILE* out, const std::vector<SamplingRow>& rows);
// DIR/warp_comparison.csv: one row per WarpComparison.
void writeWarpComparisonCsv(const std::filesystem::path& path, const std::vector<WarpComparison>& comparisons);

}  // namespace btf::cli
