// The in-memory form of a FactorBtf (compress/factor_btf.h), private to src/compress/: the stored
// integer codes and their steps (what the file holds) and the decoded float factors every lookup
// reads.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "btf/compress/factor_btf.h"

namespace btf {

struct FactorBtf::Impl {
  int width = 0, height = 0;
  std::string name;
  BtfViewSet views;
  FactorOptions options;
  FactorStats stats;
  FactorColorModel color_model = FactorColorModel::Linear;
  std::array<float, 9> color{};  // Linear: K, row-major: channel c = sum_i K[3c + i] rgb_i
  float log_offset = 0;          // LogLuminance: o
  // LogLuminance: added to channel 0 at each pair before the exponential (empty: none). A Bonn
  // file's cosine flag becomes -log cos(theta_light) here.
  std::vector<float> pair_offset;

  // Components kept per channel; channel c's occupy [offset[c], offset[c] + k[c]) of a row.
  std::array<int, 3> k{}, offset{};
  int k_total = 0;
  std::size_t pairs = 0;  // (view, light) pairs of the held views
  // Per view of the set: the first pair of its lights among the held views' pairs (-1: not held).
  std::vector<std::int64_t> view_pair;

  // Stored: coefficient codes (k_total planes of texels, row order) times coefficient_step, and
  // basis codes (k_total planes of pairs) divided by basis_scale[j].
  double coefficient_step = 0;
  std::vector<double> basis_scale;
  std::vector<std::int32_t> coefficient_codes, basis_codes;

  // Decoded (float), row-major: coefficients[t * k_total + j], basis[p * k_total + j].
  std::vector<float> coefficients, basis;

  // Fills k_total, offset, view_pair, pairs, and the decoded factors from the codes.
  void prepare();
  std::size_t texels() const { return std::size_t(width) * std::size_t(height); }
  // The decoded value of texel t at pair p (value() and loadView() share it).
  Rgb decode(std::size_t t, std::size_t p) const;
  // The channels' sums a at pair p to RGB (the colour model, clamped at 0).
  Rgb finish(const float a[3], std::size_t p) const;
};

// Integer planes as bytes: a flag (0 raw, 1 differences to the previous value), then zigzag LEB128
// varints; the shorter of the two. decodeFactorPlane throws FileError naming `path` and `what`
// for a truncated or overlong plane.
void encodeFactorPlane(const std::int32_t* values, std::size_t count, std::vector<std::byte>& out);
void decodeFactorPlane(const std::byte*& in, const std::byte* end, std::int32_t* values, std::size_t count,
                       const std::filesystem::path& path, const std::string& what);

}  // namespace btf
