// `btf bench compression --scaling` (bench_compression_scaling.cpp): how VQ compression time grows
// with the texel count and with the direction count.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace btf::cli {

struct CompressionScalingOptions {
  std::string pattern = "fabric";
  std::uint64_t seed = 1;
  float epsilon = 0.02f;
  std::vector<int> sides{16, 32, 64};  // texels per side of the texel study
  int direction_side = 32;             // texels per side of the direction study
  int scattered = 200;                 // views and lights per view of the scattered set
};

// Compresses the pattern (generated once per size and set, held in memory so that generation is not
// timed) on the Bonn dome and the 81-direction set at every side, and on the 81, dome and a
// scattered set at direction_side; prints texel-directions per second per core and the exponents of
// time against texels and against (view, light) pairs; writes compression_scaling.csv and a chart.
void benchCompressionScaling(const std::filesystem::path& folder, const CompressionScalingOptions& options);

}  // namespace btf::cli
