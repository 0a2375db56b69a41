// Quadtree rejection sampler after Montes, Urena, Garcia and Lastra 2008 ("An Importance Sampling
// Method for Arbitrary BRDFs"), with one deliberate change that makes pdf() exact.
//
// Build, per outgoing bin: a quadtree over the (s, t) square of binned_sampler.h. Every cell is
// probed on a (quadtree_probes + 1)^2 grid of f cos values (its corners included); it is split
// into four while depth < min_depth, or while max > threshold * mean over its probes and
// depth < max_depth. A leaf keeps its four corner values.
//
// Target. Rejection against the material's own f cos would need the exact integral of f cos to
// state pdf = f cos / integral; any quadrature misses it by far more than the 1e-4 that the
// chi-square harness resolves, and a bound from finitely many probes is never guaranteed (a safety
// factor only makes a miss rarer). So the sampled density is, exactly, proportional to g: the
// bilinear interpolant of each leaf's corner values (plus the defensive share). Its leaf maximum M
// is the largest corner (a guaranteed bound, no safety factor) and its integral Z is the sum of
// leaf areas times mean corner values (exact). f enters only through the probes, which decide
// where leaves are small; g follows f as well as the leaves are fine.
//
// Sampling: propose q = choose a leaf with probability M * area / sum(M * area), then a uniform
// point in it; accept with probability g / M. After max_tries rejections, return one more
// proposal from q unconditionally. The density of that procedure, with acceptance a = Z / sum(M
// area) (the same for every try), is
//   p(x) = (1 - (1 - a)^K) g(x) / Z + (1 - a)^K q(x),   K = max_tries,
// which is what pdf() returns: exact, bounded work (at most K + 1 proposals), never a loop.
// Since g/M >= 1/4 on every bilinear leaf (the mean of four non-negative corners is at least a
// quarter of their max), a >= 1/4: acceptance cannot collapse here; what degrades on near-mirror
// lobes is how well g follows f (see the stability tests and the weight variance they report).
// The first proposal uses u itself (leaf from u.x, remapped, and u.y), later numbers come from a
// counter-based Rng keyed by u, so sample() stays a pure function of its arguments.
#pragma once

#include <cstdint>
#include <vector>

#include "btf/sampling/binned_sampler.h"

namespace btf {

class QuadtreeSampler final : public BinnedSampler {
 public:
  QuadtreeSampler(std::shared_ptr<const Material> material, const SamplerOptions& options = {});

  SamplerKind kind() const override { return SamplerKind::Quadtree; }
  SamplerStats stats() const override;
  // Probability that one proposal is accepted, in the bin of wo (0 for an empty bin or wo.z <= 0).
  double acceptanceRate(const glm::vec3& wo) const;

 protected:
  std::optional<glm::vec2> sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const override;
  float pdfInBin(std::size_t bin, glm::vec2 st) const override;

 private:
  struct Leaf {
    float s0, t0, size;
    float corner[4];  // g at (s0, t0), (s0 + size, t0), (s0, t0 + size), (s0 + size, t0 + size)
    float max;        // largest corner: the exact bound of g on the leaf
  };
  static constexpr std::uint32_t kLeafFlag = 0x80000000u;
  struct Bin {
    std::uint32_t first_node = 0, first_leaf = 0, leaf_count = 0, first_cdf = 0;
    float target_weight = 0;    // (1 - (1 - a)^K) / Z
    float proposal_weight = 0;  // (1 - a)^K / sum(M area)
    float acceptance = 0;       // a
    bool empty = true;
  };
  struct BinTree;  // build-time per-bin storage
  BinTree buildBin(std::size_t bin) const;
  static float bilinear(const Leaf& leaf, glm::vec2 st);

  std::vector<std::uint32_t> nodes_;  // per node: index of the first of 4 children, or kLeafFlag | leaf
  std::vector<Leaf> leaves_;
  std::vector<float> leaf_cdf_;  // per bin: leaf_count + 1 entries over M * area
  std::vector<Bin> bins_;
};

}  // namespace btf
