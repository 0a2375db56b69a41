#include "btf/sampling/quadtree_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <span>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/core/cdf1d.h"

namespace btf {

struct QuadtreeSampler::BinTree {
  std::vector<std::uint32_t> nodes;  // children and leaves indexed locally (within the bin)
  std::vector<Leaf> leaves;
};

QuadtreeSampler::BinTree QuadtreeSampler::buildBin(std::size_t bin) const {
  BinTree tree;
  const int probes = options().quadtree_probes;
  std::vector<float> grid(std::size_t(probes + 1) * (probes + 1));
  // Depth-first; a node's slot exists before its children are appended, so indices are stable.
  auto build = [&](auto&& self, std::size_t node, float s0, float t0, float size, int depth) -> void {
    float max = 0.0f;
    double sum = 0.0;
    for (int a = 0; a <= probes; ++a)
      for (int b = 0; b <= probes; ++b) {
        const float v = target(bin, {std::min(s0 + size * float(a) / float(probes), 1.0f),
                                     std::min(t0 + size * float(b) / float(probes), 1.0f)});
        grid[std::size_t(a) * (probes + 1) + b] = v;
        max = std::max(max, v);
        sum += v;
      }
    const double mean = sum / double(grid.size());
    const bool split = depth < options().min_depth ||
                       (depth < options().max_depth && max > 0.0f && double(max) > options().threshold * mean);
    if (!split) {
      const float c00 = grid[0], c10 = grid[std::size_t(probes) * (probes + 1)];
      const float c01 = grid[std::size_t(probes)], c11 = grid.back();
      tree.nodes[node] = kLeafFlag | std::uint32_t(tree.leaves.size());
      tree.leaves.push_back({s0, t0, size, {c00, c10, c01, c11}, 0.0f});
      return;
    }
    const std::uint32_t first_child = std::uint32_t(tree.nodes.size());
    tree.nodes[node] = first_child;
    tree.nodes.resize(tree.nodes.size() + 4);
    const float half = 0.5f * size;
    // Child k covers the s half (k & 1) and the t half (k >> 1), matching pdfInBin's descent.
    for (int k = 0; k < 4; ++k)
      self(self, first_child + k, (k & 1) ? s0 + half : s0, (k >> 1) ? t0 + half : t0, half, depth + 1);
  };
  tree.nodes.resize(1);
  build(build, 0, 0.0f, 0.0f, 1.0f, 0);
  return tree;
}

QuadtreeSampler::QuadtreeSampler(std::shared_ptr<const Material> material, const SamplerOptions& options)
    : BinnedSampler(std::move(material), options) {
  std::vector<BinTree> trees(binCount());
  tbb::parallel_for(std::size_t(0), binCount(), [&](std::size_t bin) { trees[bin] = buildBin(bin); });
  bins_.resize(binCount());
  const double k = options.max_tries;
  for (std::size_t b = 0; b < binCount(); ++b) {
    BinTree& tree = trees[b];
    Bin& bin = bins_[b];
    bin.first_node = std::uint32_t(nodes_.size());
    bin.first_leaf = std::uint32_t(leaves_.size());
    bin.leaf_count = std::uint32_t(tree.leaves.size());
    bin.first_cdf = std::uint32_t(leaf_cdf_.size());
    double raw_integral = 0.0;
    for (const Leaf& leaf : tree.leaves)
      raw_integral += double(leaf.size) * leaf.size * 0.25 *
                      (double(leaf.corner[0]) + leaf.corner[1] + leaf.corner[2] + leaf.corner[3]);
    // The defensive share: a constant added to g, so that every leaf can be proposed.
    const float floor = float(options.defensive_fraction * raw_integral);
    std::vector<float> weights(tree.leaves.size());
    double z = 0.0, bound = 0.0;
    for (std::size_t i = 0; i < tree.leaves.size(); ++i) {
      Leaf& leaf = tree.leaves[i];
      for (float& c : leaf.corner) c += floor;
      leaf.max = std::max({leaf.corner[0], leaf.corner[1], leaf.corner[2], leaf.corner[3]});
      const double area = double(leaf.size) * leaf.size;
      z += area * 0.25 * (double(leaf.corner[0]) + leaf.corner[1] + leaf.corner[2] + leaf.corner[3]);
      bound += area * leaf.max;
      weights[i] = float(area * leaf.max);
    }
    leaf_cdf_.resize(leaf_cdf_.size() + weights.size() + 1);
    buildCdf1D(weights, std::span(leaf_cdf_).subspan(bin.first_cdf, weights.size() + 1));
    if (raw_integral > 0.0 && bound > 0.0) {
      const double a = std::min(z / bound, 1.0);
      const double miss_all = std::pow(1.0 - a, k);
      bin.acceptance = float(a);
      bin.target_weight = float((1.0 - miss_all) / z);
      bin.proposal_weight = float(miss_all / bound);
      bin.empty = false;
    }
    nodes_.insert(nodes_.end(), tree.nodes.begin(), tree.nodes.end());
    leaves_.insert(leaves_.end(), tree.leaves.begin(), tree.leaves.end());
  }
  reportInvalidEvaluations();
}

float QuadtreeSampler::bilinear(const Leaf& leaf, glm::vec2 st) {
  const float x = std::clamp((st.x - leaf.s0) / leaf.size, 0.0f, 1.0f);
  const float y = std::clamp((st.y - leaf.t0) / leaf.size, 0.0f, 1.0f);
  return (1.0f - y) * ((1.0f - x) * leaf.corner[0] + x * leaf.corner[1]) +
         y * ((1.0f - x) * leaf.corner[2] + x * leaf.corner[3]);
}

std::optional<glm::vec2> QuadtreeSampler::sampleInBin(std::size_t bin_index, glm::vec2 u, int& tries) const {
  const Bin& bin = bins_[bin_index];
  if (bin.empty) return std::nullopt;
  const std::span<const float> cdf(leaf_cdf_.data() + bin.first_cdf, bin.leaf_count + 1);
  Rng rng((std::uint64_t(std::bit_cast<std::uint32_t>(u.x)) << 32) | std::bit_cast<std::uint32_t>(u.y), bin_index);
  auto propose = [&](float u_leaf, float u_t, const Leaf*& leaf) {
    const DiscreteSample d = sampleDiscrete(cdf, u_leaf);
    leaf = &leaves_[bin.first_leaf + d.index];
    return glm::vec2{leaf->s0 + d.remapped * leaf->size, leaf->t0 + u_t * leaf->size};
  };
  const Leaf* leaf = nullptr;
  for (int k = 0; k < options().max_tries; ++k) {
    const glm::vec2 st = k == 0 ? propose(u.x, u.y, leaf) : propose(rng.uniform(), rng.uniform(), leaf);
    ++tries;
    if (rng.uniform() * leaf->max < bilinear(*leaf, st)) return st;
  }
  ++tries;
  return propose(rng.uniform(), rng.uniform(), leaf);  // the fallback draw from q
}

float QuadtreeSampler::pdfInBin(std::size_t bin_index, glm::vec2 st) const {
  const Bin& bin = bins_[bin_index];
  if (bin.empty) return 0.0f;
  std::uint32_t node = nodes_[bin.first_node];
  float s0 = 0.0f, t0 = 0.0f, size = 1.0f;
  while (!(node & kLeafFlag)) {
    size *= 0.5f;
    const int ks = st.x >= s0 + size ? 1 : 0, kt = st.y >= t0 + size ? 1 : 0;
    s0 += float(ks) * size;
    t0 += float(kt) * size;
    node = nodes_[bin.first_node + node + std::uint32_t(ks + 2 * kt)];
  }
  const Leaf& leaf = leaves_[bin.first_leaf + (node & ~kLeafFlag)];
  return bin.target_weight * bilinear(leaf, st) + bin.proposal_weight * leaf.max;
}

double QuadtreeSampler::acceptanceRate(const glm::vec3& wo) const {
  if (!(wo.z > 0.0f)) return 0.0;
  const Bin& bin = bins_[binOf(wo)];
  return bin.empty ? 0.0 : bin.acceptance;
}

SamplerStats QuadtreeSampler::stats() const {
  SamplerStats s;
  fillCommonStats(s);
  s.bytes = nodes_.size() * sizeof(std::uint32_t) + leaves_.size() * sizeof(Leaf) + leaf_cdf_.size() * sizeof(float) +
            bins_.size() * sizeof(Bin);
  s.elements = leaves_.size();
  double sum = 0.0, worst = 1.0;
  std::size_t non_empty = 0;
  for (const Bin& b : bins_) {
    if (b.empty) {
      ++s.empty_bins;
      continue;
    }
    ++non_empty;
    sum += b.acceptance;
    worst = std::min(worst, double(b.acceptance));
  }
  if (non_empty > 0) s.acceptance_rate = sum / double(non_empty), s.min_acceptance_rate = worst;
  return s;
}

}  // namespace btf
