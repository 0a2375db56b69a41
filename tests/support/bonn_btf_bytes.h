// Bonn .btf files built byte by byte from the format's description (btf/io/bonn_btf.h), without
// libbtf's writer: the reader's tests check it against these, so that a mistake shared by our
// reader and our writer cannot hide. Also where the bad-input tests cut and corrupt files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace btf::test {

struct BonnAngles {
  float theta_rad = 0, phi_rad = 0;
};

// One factorisation, row-major: U (rows x components) and S.V (columns x components); for PVF,
// U is the components (dimension x k), sv the weights, mean the subtracted mean (dimension).
struct BonnFactorBytes {
  int scalar_bytes = 4;
  std::uint32_t rows = 0, columns = 0, components = 0;
  std::vector<double> sigma, u, sv, mean;
};

struct BonnFileSpec {
  std::string signature = "!DFMF08FCR";
  std::uint32_t meta_version = 4;
  std::vector<std::string> channel_names = {"R", "G", "B"};
  bool cosine_flag = false;
  std::string xml = "<measurement/>";
  std::vector<BonnAngles> views;
  std::vector<std::vector<BonnAngles>> lights;  // per view
  std::uint32_t width = 1, height = 1;
  std::uint32_t rotations = 0;  // written (as identity matrices) when the signature ends in R
  // DFMF
  std::int32_t color_model = 0;
  float color_mean[3] = {0, 0, 0};
  float color_transform[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  // FMF (extended header)
  int fmf_header_version = 1;
  std::uint32_t dynamic_range_reduction = 0;
  std::uint32_t height_map_width = 0, height_map_height = 0;
  // PVF
  bool legacy_pvf = false;
  std::vector<BonnFactorBytes> factors;  // DFMF: per channel; FMF: one; PVF: per view
};

struct BonnFileOffsets {
  std::size_t meta = 0, sampling = 0, size = 0, rotations = 0, layout = 0, first_factor = 0, end = 0;
};

std::vector<unsigned char> bonnFileBytes(const BonnFileSpec& spec, BonnFileOffsets* offsets = nullptr);
void writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes);

}  // namespace btf::test
