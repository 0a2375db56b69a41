#include "btf/compress/codebook.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <flann/flann.hpp>

#include "btf/core/error.h"

namespace btf {

namespace {

constexpr std::size_t kBlockEntries = 1024;
// Points per kd-tree leaf: 5 rather than FLANN's default 10 makes the compressor's (visit-limited)
// searches faster on its 40-dimensional chroma keys and the builds cheaper
// (bench_btf_vq_compress.cpp).
constexpr int kLeafSize = 5;

// The unit direction of `values` (zero stays zero); the one normalization used everywhere, so that
// the segments, the unindexed entries and the brute-force scan see bit-identical directions.
void normalizeInto(const float* values, int dim, float* unit) {
  double norm2 = 0;
  for (int k = 0; k < dim; ++k) norm2 += double(values[k]) * values[k];
  const float inv = norm2 > 0 ? float(1.0 / std::sqrt(norm2)) : 0.0f;
  for (int k = 0; k < dim; ++k) unit[k] = values[k] * inv;
}

float squaredDistance(const float* a, const float* b, int dim) {
  float d2 = 0;
  for (int k = 0; k < dim; ++k) {
    const float d = a[k] - b[k];
    d2 += d * d;
  }
  return d2;
}

// The k nearest within a radius, through FLANN's result-set interface: one instance collects the
// matches of every segment and of the unindexed entries (its shrinking worst distance prunes the
// later ones). Ties are broken by entry index. The visit budget: KDTreeSingleIndex asks
// worstDist() once per node it visits and prunes every branch whose bound exceeds it, so
// answering -1 once the budget is spent ends the search after the current descent (FLANN 1.9
// offers no check limit for this index; a later FLANN that asked less often would only search more).
class NearestWithin final : public flann::ResultSet<float> {
 public:
  NearestWithin(std::size_t capacity, float radius2, std::uint32_t first, std::vector<Codebook::Match>& out)
      : capacity_(capacity), radius2_(radius2), first_(first), out_(out) {
    out_.clear();
  }
  void startTree(std::size_t base, int budget) {
    base_ = base;
    visits_left_ = budget > 0 ? budget : -1;
  }
  bool full() const override { return out_.size() == capacity_; }
  float worstDist() const override {
    if (visits_left_ == 0) return -1.0f;
    if (visits_left_ > 0) --visits_left_;
    return worst();
  }
  float worst() const { return full() ? out_.back().distance : radius2_; }
  void addPoint(float dist, std::size_t index) override {
    const std::size_t entry = base_ + index;
    if (dist > radius2_ || entry < first_) return;
    const Codebook::Match m{std::uint32_t(entry), dist};
    auto less = [](const Codebook::Match& a, const Codebook::Match& b) {
      return a.distance < b.distance || (a.distance == b.distance && a.index < b.index);
    };
    if (full()) {
      if (!less(m, out_.back())) return;
      out_.pop_back();
    }
    out_.insert(std::upper_bound(out_.begin(), out_.end(), m, less), m);
  }

 private:
  std::size_t capacity_;
  float radius2_;
  std::uint32_t first_;
  std::vector<Codebook::Match>& out_;  // squared distances until search() finishes
  std::size_t base_ = 0;
  mutable int visits_left_ = -1;  // -1: unlimited
};

}  // namespace

// One immutable kd-tree over the entries [begin, begin + count).
struct Codebook::Segment {
  std::size_t begin, count;
  flann::KDTreeSingleIndex<flann::L2<float>> flann;
  // `units` holds the entries' unit directions (count x dim). FLANN copies them in tree order
  // (reorder) and reads only that copy when searching, so the caller frees `units` after building.
  Segment(std::size_t begin_, std::size_t count_, float* units, int dim)
      : begin(begin_), count(count_),
        flann(flann::Matrix<float>(units, count_, std::size_t(dim)), flann::KDTreeSingleIndexParams(kLeafSize, true)) {
    flann.buildIndex();
  }
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
  if (size_ >= std::size_t(std::numeric_limits<std::uint32_t>::max())) throw Error("codebook is full (2^32 - 1 entries)");
  if (size_ % kBlockEntries == 0) blocks_.emplace_back(new float[kBlockEntries * std::size_t(dim_)]);
  float* stored = blocks_.back().get() + (size_ % kBlockEntries) * std::size_t(dim_);
  std::copy(values.begin(), values.end(), stored);
  const std::size_t at = tail_units_.size();
  tail_units_.resize(at + std::size_t(dim_));
  normalizeInto(stored, dim_, tail_units_.data() + at);
  const std::uint32_t id = std::uint32_t(size_++);
  if (size_ - indexed_ >= kMaxUnindexed) index();
  return id;
}

void Codebook::index() {
  if (size_ - indexed_ < kMinSegment) return;
  // Merge with the last segments while they are at most as large as what is being built.
  std::size_t begin = indexed_;
  while (!segments_.empty() && segments_.back()->count <= size_ - begin) {
    begin = segments_.back()->begin;
    segments_.pop_back();
  }
  const std::size_t count = size_ - begin, reindexed = indexed_ - begin;
  std::vector<float> units(count * std::size_t(dim_));
  for (std::size_t i = 0; i < reindexed; ++i) normalizeInto(entry(begin + i), dim_, units.data() + i * std::size_t(dim_));
  std::copy(tail_units_.begin(), tail_units_.end(), units.begin() + std::ptrdiff_t(reindexed * std::size_t(dim_)));
  segments_.push_back(std::make_unique<Segment>(begin, count, units.data(), dim_));
  indexed_ = size_;
  tail_units_.clear();
}

void Codebook::search(std::span<const float> unit_query, float radius, std::size_t max_matches,
                      std::vector<Match>& out, const SearchOptions& options) const {
  // FLANN compares squared distances; a hair of slack so entries exactly at the radius count.
  NearestWithin result(max_matches, radius * radius * (1.0f + 1e-6f), options.first, out);
  if (max_matches == 0) return;
  const flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false);
  for (const auto& segment : segments_) {
    if (segment->begin + segment->count <= options.first) continue;
    result.startTree(segment->begin, options.max_visits);
    segment->flann.findNeighbors(result, unit_query.data(), params);
  }
  result.startTree(indexed_, 0);
  for (std::size_t i = options.first > indexed_ ? options.first - indexed_ : 0; i < size_ - indexed_; ++i) {
    const float d2 = squaredDistance(tail_units_.data() + i * std::size_t(dim_), unit_query.data(), dim_);
    if (d2 <= result.worst()) result.addPoint(d2, i);
  }
  for (Match& m : out) m.distance = std::sqrt(std::max(m.distance, 0.0f));
}

void Codebook::searchBruteForce(std::span<const float> unit_query, float radius, std::size_t max_matches,
                                std::vector<Match>& out) const {
  out.clear();
  std::vector<float> unit(static_cast<std::size_t>(dim_));
  for (std::size_t i = 0; i < size_; ++i) {
    normalizeInto(entry(i), dim_, unit.data());
    const float d2 = squaredDistance(unit.data(), unit_query.data(), dim_);
    if (d2 <= radius * radius * (1.0f + 1e-6f)) out.push_back({std::uint32_t(i), std::sqrt(d2)});
  }
  std::stable_sort(out.begin(), out.end(), [](const Match& a, const Match& b) { return a.distance < b.distance; });
  if (out.size() > max_matches) out.resize(max_matches);
}

}  // namespace btf
