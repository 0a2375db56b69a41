// A growing codebook of unit-length vectors for vector quantization (compress/vq_btf.h), searched
// with FLANN kd-trees.
//
// Reuse rule. A vector f is approximated by an entry e with its least-squares scale <f, e> / <e, e>;
// the relative L2 error of that approximation is sin(angle(f, e)). An entry is reusable for f when
// that relative error is <= epsilon. For unit vectors this is equivalent to a chord distance
// |f/|f| - e/|e|| <= 2 sin(asin(epsilon) / 2), so the search is a radius search in L2 (FLANN
// returns squared distances) with that radius.
//
// Index. Entries are appended unindexed; index() turns them into a segment, an immutable FLANN
// KDTreeSingleIndex (a bucket kd-tree built once by sliding-midpoint splits: no randomness), and
// merges it with the last segments while those are not larger (the logarithmic method of Bentley
// and Saxe: segments shrink from oldest to newest, and when index() is called with similar
// numbers of new entries, as the compressor does per chunk, their sizes are a binary counter's:
// O(log n) segments, each entry re-indexed O(log n) times). Unindexed entries are scanned linearly.
// (FLANN's own incremental KDTreeIndex, grown point by point by addPoints, made search cost grow
// about linearly with the codebook: its tree is deep and unbalanced, its "exact" search visits
// most leaves, its bounded search allocates O(n) per query, and its rebuilds shuffle with
// std::random_device.) Everything is a function of the sequence of add() and index() calls.
// Search. Exact by default: KDTreeSingleIndex bounds each cell by its true distance, so search()
// finds what a linear scan finds, up to float rounding at the radius. With max_visits > 0 each
// kd-tree stops descending after that many node visits (approximate kNN, depth first from the
// query's own cell: it may miss a reusable entry, which costs an extra entry but never accuracy,
// since every returned match is within the radius); still deterministic.
// Snapshots. Searches are const and may run in parallel (TBB) as long as nothing is added or
// indexed meanwhile; the compressor queries a frozen codebook in parallel, then adds sequentially.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace btf {

class Codebook {
 public:
  // dimension >= 1. Entries are stored in blocks that never move (entry() pointers stay valid).
  explicit Codebook(int dimension);
  ~Codebook();
  Codebook(Codebook&&) noexcept;
  Codebook& operator=(Codebook&&) noexcept;

  int dimension() const { return dim_; }
  std::size_t size() const { return size_; }
  const float* entry(std::size_t i) const;

  // Appends an entry (dimension() values, stored as given) and returns its index. It is found by
  // search() at once, by a linear scan until index() (or until kMaxUnindexed entries wait).
  std::uint32_t add(std::span<const float> values);
  // Indexes the entries added since the last call (when at least kMinSegment wait; fewer stay in
  // the linear scan).
  void index();
  static constexpr std::size_t kMinSegment = 64, kMaxUnindexed = 8192;

  struct Match {
    std::uint32_t index;
    float distance;  // chord distance between the unit directions of query and entry
  };
  struct SearchOptions {
    std::uint32_t first = 0;  // only entries with index >= first
    int max_visits = 0;       // > 0: approximate, at most about this many node visits per kd-tree
  };
  // Up to max_matches entries whose direction lies within chord distance `radius` of the direction
  // of `unit_query` (which must have length 1), nearest first (ties: lowest index first); exact
  // unless options.max_visits > 0 (see above). Thread-safe against other searches.
  void search(std::span<const float> unit_query, float radius, std::size_t max_matches,
              std::vector<Match>& out, const SearchOptions& options) const;
  void search(std::span<const float> unit_query, float radius, std::size_t max_matches,
              std::vector<Match>& out) const {
    search(unit_query, radius, max_matches, out, SearchOptions{});
  }

  // The same by linear scan, for tests (FLANN must agree with it).
  void searchBruteForce(std::span<const float> unit_query, float radius, std::size_t max_matches,
                        std::vector<Match>& out) const;

  // Chord radius equivalent to a relative least-squares error epsilon (see above).
  static float chordRadius(float epsilon);

 private:
  struct Segment;
  void buildSegment(std::size_t end);
  int dim_;
  std::size_t size_ = 0;
  std::vector<std::unique_ptr<float[]>> blocks_;    // the entries as given
  std::vector<std::unique_ptr<Segment>> segments_;  // kd-trees over consecutive entries, largest first
  std::size_t indexed_ = 0;                         // entries [0, indexed_) are in segments
  std::vector<float> tail_units_;                   // unit directions of the entries [indexed_, size_)
};

}  // namespace btf
