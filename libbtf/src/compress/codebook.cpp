#include "btf/compress/codebook.h"

#include <algorithm>
#include <cmath>

#include <flann/flann.hpp>

#include "btf/core/error.h"

namespace btf {

namespace {
constexpr std::size_t kBlockEntries = 1024;
}

struct Codebook::Index {
  // One kd-tree: the search is the single-tree "exact" mode (see the header).
  flann::Index<flann::L2<float>> flann;
  explicit Index(const flann::Matrix<float>& first) : flann(first, flann::KDTreeIndexParams(1)) { flann.buildIndex(); }
};

Codebook::Codebook(int dimension) : dim_(dimension) {
  if (dimension < 1) throw Error("codebook dimension " + std::to_string(dimension) + " is invalid: must be >= 1");
}
Codebook::~Codebook() = default;
Codebook::Codebook(Codebook&&) noexcept = default;
Codebook& Codebook::operator=(Codebook&&) noexcept = default;

const float* Codebook::entry(std::size_t i) const {
  return blocks_[i / kBlockEntries].get() + (i % kBlockEntries) * std::size_t(dim_);
}

float Codebook::chordRadius(float epsilon) {
  const float e = std::clamp(epsilon, 0.0f, 1.0f);
  return 2.0f * std::sin(0.5f * std::asin(e));
}

std::uint32_t Codebook::add(std::span<const float> values) {
  if (values.size() != std::size_t(dim_)) throw Error("codebook entry has the wrong dimension");
  if (size_ % kBlockEntries == 0) {
    blocks_.emplace_back(new float[kBlockEntries * std::size_t(dim_)]);
    unit_blocks_.emplace_back(new float[kBlockEntries * std::size_t(dim_)]);
  }
  const std::size_t slot = (size_ % kBlockEntries) * std::size_t(dim_);
  float* stored = blocks_.back().get() + slot;
  float* unit = unit_blocks_.back().get() + slot;
  double norm2 = 0;
  for (int k = 0; k < dim_; ++k) {
    stored[k] = values[std::size_t(k)];
    norm2 += double(values[std::size_t(k)]) * values[std::size_t(k)];
  }
  const float inv = norm2 > 0 ? float(1.0 / std::sqrt(norm2)) : 0.0f;
  for (int k = 0; k < dim_; ++k) unit[k] = stored[k] * inv;
  flann::Matrix<float> row(unit, 1, std::size_t(dim_));
  if (!index_)
    index_ = std::make_unique<Index>(row);
  else
    index_->flann.addPoints(row, 0.0f);  // never rebuild: see the header (determinism)
  return std::uint32_t(size_++);
}

void Codebook::search(std::span<const float> unit_query, float radius, std::size_t max_matches,
                      std::vector<Match>& out) const {
  out.clear();
  if (!index_ || max_matches == 0) return;
  std::vector<std::size_t> indices(max_matches);
  std::vector<float> dists(max_matches);
  flann::Matrix<float> query(const_cast<float*>(unit_query.data()), 1, std::size_t(dim_));
  flann::Matrix<std::size_t> index_matrix(indices.data(), 1, max_matches);
  flann::Matrix<float> dist_matrix(dists.data(), 1, max_matches);
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0.0f, true);
  params.max_neighbors = int(max_matches);
  params.cores = 1;
  // FLANN compares squared distances; a hair of slack so entries exactly at the radius count.
  const int found = index_->flann.radiusSearch(query, index_matrix, dist_matrix, radius * radius * (1.0f + 1e-6f), params);
  for (int i = 0; i < std::min(found, int(max_matches)); ++i) {
    if (indices[std::size_t(i)] == std::size_t(-1)) break;
    out.push_back({std::uint32_t(indices[std::size_t(i)]), std::sqrt(std::max(dists[std::size_t(i)], 0.0f))});
  }
}

void Codebook::searchBruteForce(std::span<const float> unit_query, float radius, std::size_t max_matches,
                                std::vector<Match>& out) const {
  out.clear();
  for (std::size_t i = 0; i < size_; ++i) {
    const float* unit = unit_blocks_[i / kBlockEntries].get() + (i % kBlockEntries) * std::size_t(dim_);
    float d2 = 0;
    for (int k = 0; k < dim_; ++k) {
      const float d = unit[k] - unit_query[std::size_t(k)];
      d2 += d * d;
    }
    if (d2 <= radius * radius * (1.0f + 1e-6f)) out.push_back({std::uint32_t(i), std::sqrt(d2)});
  }
  std::stable_sort(out.begin(), out.end(), [](const Match& a, const Match& b) { return a.distance < b.distance; });
  if (out.size() > max_matches) out.resize(max_matches);
}

}  // namespace btf
