// A growing codebook of unit-length vectors for vector quantization (compress/vq_btf.h), searched
// with FLANN (a kd-tree flann::Index grown by addPoints, one entry at a time).
//
// Reuse rule. A vector f is approximated by an entry e with its least-squares scale <f, e> / <e, e>;
// the relative L2 error of that approximation is sin(angle(f, e)). An entry is reusable for f when
// that relative error is <= epsilon. For unit vectors this is equivalent to a chord distance
// |f/|f| - e/|e|| <= 2 sin(asin(epsilon) / 2), so the search is a radius search in L2 (FLANN
// returns squared distances) with that radius.
//
// Determinism. FLANN 1.9's kd-tree shuffles its points with std::random_device whenever it
// (re)builds, and its "exact" single-tree search (unlimited checks) is in fact approximate: its
// lower bound adds the split distances of a feature split twice on a path, so it can prune a
// branch holding the nearest entry, and what it misses depends on the tree. A rebuilt tree thus
// made results differ from run to run (seen: compressed sizes varying by a few bytes). Here the
// tree is built from the first entry and grown only by addPoints without rebuilds (FLANN inserts
// each point into its leaf, splitting on the widest dimension: no randomness), so the tree and
// every search result are a function of the insertion order alone. The search is approximate
// kNN in that sense: it may miss a reusable entry (costing an extra entry, never accuracy: every
// returned match is within the radius); the tests measure how often it disagrees with a scan.
// Snapshots. Searches are const and may run in parallel (TBB) as long as nothing is inserted
// meanwhile; the compressor queries a frozen codebook in parallel, then inserts sequentially.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace btf {

class Codebook {
 public:
  // dimension >= 1. Entries are stored in blocks that never move: FLANN keeps pointers to them.
  explicit Codebook(int dimension);
  ~Codebook();
  Codebook(Codebook&&) noexcept;
  Codebook& operator=(Codebook&&) noexcept;

  int dimension() const { return dim_; }
  std::size_t size() const { return size_; }
  const float* entry(std::size_t i) const;

  // Appends an entry (any length; it is stored as given) and returns its index.
  std::uint32_t add(std::span<const float> values);

  struct Match {
    std::uint32_t index;
    float distance;  // chord distance between the unit directions of query and entry
  };
  // Up to max_matches entries whose direction lies within chord distance `radius` of the direction
  // of `unit_query` (which must have length 1), nearest first; deterministic, may miss entries
  // (see above). Thread-safe
  // against other searches.
  void search(std::span<const float> unit_query, float radius, std::size_t max_matches,
              std::vector<Match>& out) const;

  // The same by linear scan, for tests (FLANN must agree with it).
  void searchBruteForce(std::span<const float> unit_query, float radius, std::size_t max_matches,
                        std::vector<Match>& out) const;

  // Chord radius equivalent to a relative least-squares error epsilon (see above).
  static float chordRadius(float epsilon);

 private:
  struct Index;
  int dim_;
  std::size_t size_ = 0;
  std::vector<std::unique_ptr<float[]>> blocks_;
  std::vector<std::unique_ptr<float[]>> unit_blocks_;  // unit directions, indexed by FLANN
  std::unique_ptr<Index> index_;
};

}  // namespace btf
