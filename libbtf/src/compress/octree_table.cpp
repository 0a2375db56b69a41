#include "btf/compress/octree_table.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "btf/core/error.h"

namespace btf {
namespace {

using Box = OctreeTable::Box;
using Leaf = OctreeTable::Leaf;
using Node = OctreeTable::Node;

float roundedDown(double v) {
  const float f = float(v);
  return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float roundedUp(double v) {
  const float f = float(v);
  return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// What a finished subtree tells its parent: a uniform block (a leaf not yet placed, which may
// still consolidate with its siblings) or a placed internal node.
struct Subtree {
  bool uniform = true;
  bool measured = true;              // uniform only: the state of every cell
  Leaf lo{}, hi{};                   // uniform only: raw range per channel
  std::uint32_t first_child = 0;     // internal only
  bool has_measured = false;
  double f_min = 0, f_max = 0;       // over measured cells
};

struct Builder {
  const MerlTable* table;
  double tolerance;
  std::vector<Node> nodes;
  std::vector<Leaf> leaves;

  Subtree cell(int i, int j, int k) const {
    const std::size_t c = MerlTable::index(i, j, k);
    Subtree s;
    s.measured = s.has_measured = table->isMeasured(c);
    for (int ch = 0; ch < 3; ++ch) s.lo[ch] = s.hi[ch] = table->raw(ch, c);
    if (s.measured) {
      s.f_min = std::numeric_limits<double>::infinity();
      s.f_max = -s.f_min;
      for (int ch = 0; ch < 3; ++ch) {
        s.f_min = std::min(s.f_min, s.lo[ch] * MerlTable::kChannelScale[ch]);
        s.f_max = std::max(s.f_max, s.hi[ch] * MerlTable::kChannelScale[ch]);
      }
    }
    return s;
  }

  Node place(const Subtree& s) {
    Node n;
    n.f_min = s.has_measured ? roundedDown(s.f_min) : 0.0f;
    n.f_max = s.has_measured ? roundedUp(s.f_max) : 0.0f;
    if (!s.uniform) {
      n.ref = s.first_child;
      return n;
    }
    Leaf value;
    // lo + (hi - lo) / 2 is exactly lo when the cells are equal (tolerance 0: bit for bit).
    for (int ch = 0; ch < 3; ++ch) value[ch] = s.lo[ch] + (s.hi[ch] - s.lo[ch]) / 2;
    n.ref = OctreeTable::kLeaf | std::uint32_t(leaves.size());
    leaves.push_back(value);
    return n;
  }

  // Consolidates children into one uniform block when the tolerance allows, else places them
  // contiguously and returns the internal node over them.
  Subtree combine(const std::vector<Subtree>& children) {
    Subtree s;
    for (const Subtree& c : children) {
      if (!c.has_measured) continue;
      s.f_min = s.has_measured ? std::min(s.f_min, c.f_min) : c.f_min;
      s.f_max = s.has_measured ? std::max(s.f_max, c.f_max) : c.f_max;
      s.has_measured = true;
    }
    const bool all_uniform = std::all_of(children.begin(), children.end(), [](const Subtree& c) { return c.uniform; });
    const bool same_state = std::all_of(children.begin(), children.end(),
                                        [&](const Subtree& c) { return c.measured == children[0].measured; });
    if (all_uniform && same_state) {
      s.measured = children[0].measured;
      s.lo = children[0].lo;
      s.hi = children[0].hi;
      for (const Subtree& c : children)
        for (int ch = 0; ch < 3; ++ch) {
          s.lo[ch] = std::min(s.lo[ch], c.lo[ch]);
          s.hi[ch] = std::max(s.hi[ch], c.hi[ch]);
        }
      bool within = true;
      for (int ch = 0; ch < 3; ++ch) {
        const double spread = s.hi[ch] - s.lo[ch];
        // Holes are kept exactly: unmeasured cells merge only when equal.
        within = within && (s.measured ? spread <= tolerance * (std::abs(s.hi[ch]) + std::abs(s.lo[ch])) : spread == 0);
      }
      if (within) return s;
    }
    s.uniform = false;
    s.first_child = std::uint32_t(nodes.size());
    std::vector<Node> placed;
    placed.reserve(children.size());
    for (const Subtree& c : children) placed.push_back(place(c));
    nodes.insert(nodes.end(), placed.begin(), placed.end());
    return s;
  }

  Subtree build(const Box& box) {
    const std::array<int, 3> splits = octreeSplits(box);
    const int count = splits[0] * splits[1] * splits[2];
    if (count == 1) return cell(box.lo[0], box.lo[1], box.lo[2]);
    std::vector<Subtree> children;
    children.reserve(std::size_t(count));
    for (int c = 0; c < count; ++c) children.push_back(build(octreeChild(box, c)));
    return combine(children);
  }

  // Appends another builder's nodes and leaves, shifting its references; returns `s` shifted.
  Subtree append(const Builder& other, Subtree s) {
    const auto node_offset = std::uint32_t(nodes.size()), leaf_offset = std::uint32_t(leaves.size());
    for (Node n : other.nodes) {
      n.ref = (n.ref & OctreeTable::kLeaf) ? (n.ref + leaf_offset) : (n.ref + node_offset);
      nodes.push_back(n);
    }
    leaves.insert(leaves.end(), other.leaves.begin(), other.leaves.end());
    if (!s.uniform) s.first_child += node_offset;
    return s;
  }
};

bool contains(const Box& outer, const Box& inner) {
  for (int a = 0; a < 3; ++a)
    if (inner.lo[a] < outer.lo[a] || inner.hi[a] > outer.hi[a]) return false;
  return true;
}
bool overlaps(const Box& a, const Box& b) {
  for (int d = 0; d < 3; ++d)
    if (a.hi[d] <= b.lo[d] || b.hi[d] <= a.lo[d]) return false;
  return true;
}

// Depth-first walk from the root (the last node) of a tree already checked by fromParts or
// made by build: `visit(node, box)` sees each node reached and returns whether to go into its
// children (ignored at leaves).
template <class Visit>
void walkTree(const std::vector<Node>& nodes, Visit&& visit) {
  struct Step {
    std::uint32_t node;
    Box box;
  };
  std::vector<Step> stack{{std::uint32_t(nodes.size() - 1), Box{}}};
  while (!stack.empty()) {
    const Step step = stack.back();
    stack.pop_back();
    const Node& n = nodes[step.node];
    if (!visit(n, step.box) || (n.ref & OctreeTable::kLeaf)) continue;
    const std::array<int, 3> s = octreeSplits(step.box);
    for (int c = 0; c < s[0] * s[1] * s[2]; ++c) stack.push_back({n.ref + std::uint32_t(c), octreeChild(step.box, c)});
  }
}

}  // namespace

std::array<int, 3> octreeSplits(const Box& box) {
  std::array<int, 3> s{};
  for (int a = 0; a < 3; ++a) s[a] = box.hi[a] - box.lo[a] > 1 ? 2 : 1;
  return s;
}

Box octreeChild(const Box& box, int child) {
  const std::array<int, 3> s = octreeSplits(box);
  const int half[3] = {child / (s[1] * s[2]), (child / s[2]) % s[1], child % s[2]};
  Box b = box;
  for (int a = 0; a < 3; ++a) {
    if (s[a] == 1) continue;
    const int mid = box.lo[a] + (box.hi[a] - box.lo[a]) / 2;
    if (half[a] == 0) b.hi[a] = mid;
    else b.lo[a] = mid;
  }
  return b;
}

OctreeTable OctreeTable::build(const MerlTable& table, double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    throw Error("octree tolerance must be a finite number >= 0, got " + std::to_string(tolerance));
  if (table.values.size() != 3 * MerlTable::kEntriesPerChannel)
    throw Error("octree: the table holds " + std::to_string(table.values.size()) + " values, expected " +
                std::to_string(3 * MerlTable::kEntriesPerChannel));

  // The root's children are independent subtrees: built in parallel, joined in their order.
  const Box root_box;
  const std::array<int, 3> s = octreeSplits(root_box);
  const int count = s[0] * s[1] * s[2];
  std::vector<Builder> parts(static_cast<std::size_t>(count), Builder{&table, tolerance, {}, {}});
  std::vector<Subtree> children(static_cast<std::size_t>(count));
  tbb::parallel_for(0, count, [&](int c) { children[std::size_t(c)] = parts[std::size_t(c)].build(octreeChild(root_box, c)); });

  Builder joined{&table, tolerance, {}, {}};
  for (int c = 0; c < count; ++c) children[std::size_t(c)] = joined.append(parts[std::size_t(c)], children[std::size_t(c)]);
  const Subtree root = joined.combine(children);
  joined.nodes.push_back(joined.place(root));

  OctreeTable octree;
  octree.nodes_ = std::move(joined.nodes);
  octree.leaves_ = std::move(joined.leaves);
  octree.tolerance_ = tolerance;
  return octree;
}

OctreeTable OctreeTable::fromParts(std::vector<Node> nodes, std::vector<Leaf> leaves, double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) throw Error("the tolerance " + std::to_string(tolerance) + " is not a finite number >= 0");
  if (nodes.empty()) throw Error("the octree has no nodes");
  if (nodes.size() >= kLeaf || leaves.size() >= kLeaf) throw Error("the octree has too many nodes or leaves");
  for (std::size_t l = 0; l < leaves.size(); ++l)
    for (double v : leaves[l])
      if (!std::isfinite(v)) throw Error("leaf " + std::to_string(l) + " holds a value that is not finite");

  std::vector<std::uint8_t> node_seen(nodes.size(), 0), leaf_seen(leaves.size(), 0);
  // Depth-first from the root with an explicit stack: every child index is below its parent's, so
  // the walk ends, and each node may be reached once only.
  struct Visit {
    std::uint32_t node;
    Box box;
  };
  std::vector<Visit> stack{{std::uint32_t(nodes.size() - 1), Box{}}};
  node_seen.back() = 1;
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    const Node& n = nodes[v.node];
    const std::string where = "node " + std::to_string(v.node);
    if (!(std::isfinite(n.f_min) && std::isfinite(n.f_max) && n.f_min <= n.f_max))
      throw Error(where + " has the f range [" + std::to_string(n.f_min) + ", " + std::to_string(n.f_max) + "]");
    if (n.ref & kLeaf) {
      const std::uint32_t l = n.ref & ~kLeaf;
      if (l >= leaves.size()) throw Error(where + " refers to leaf " + std::to_string(l) + " of " + std::to_string(leaves.size()));
      if (leaf_seen[l]++) throw Error("leaf " + std::to_string(l) + " is referred to twice");
      const Leaf& value = leaves[l];
      if (value[0] >= 0 && value[1] >= 0 && value[2] >= 0)
        for (int ch = 0; ch < 3; ++ch) {
          const double f = value[ch] * MerlTable::kChannelScale[ch];
          if (f < double(n.f_min) || f > double(n.f_max)) throw Error(where + ": its leaf lies outside its f range");
        }
      continue;
    }
    const std::array<int, 3> s = octreeSplits(v.box);
    const std::uint32_t count = std::uint32_t(s[0] * s[1] * s[2]);
    if (count == 1) throw Error(where + " covers one cell but is not a leaf");
    if (n.ref >= v.node || count > v.node - n.ref)
      throw Error(where + " refers to children " + std::to_string(n.ref) + ".." + std::to_string(std::uint64_t(n.ref) + count - 1) +
                  ", not all stored before it");
    for (std::uint32_t c = 0; c < count; ++c) {
      const std::uint32_t child = n.ref + c;
      if (node_seen[child]++) throw Error("node " + std::to_string(child) + " is referred to twice");
      const Node& cn = nodes[child];
      if (cn.f_max > n.f_max || (cn.f_max > 0 && cn.f_min < n.f_min))
        throw Error("node " + std::to_string(child) + ": its f range is not within its parent's");
      stack.push_back({child, octreeChild(v.box, int(c))});
    }
  }
  if (std::find(node_seen.begin(), node_seen.end(), 0) != node_seen.end()) throw Error("the octree holds nodes outside the tree");
  if (std::find(leaf_seen.begin(), leaf_seen.end(), 0) != leaf_seen.end()) throw Error("the octree holds leaves no node refers to");

  OctreeTable octree;
  octree.nodes_ = std::move(nodes);
  octree.leaves_ = std::move(leaves);
  octree.tolerance_ = tolerance;
  return octree;
}

namespace {

// One step of point location: the index of the child of a node over `box` that holds cell `at`;
// `box` becomes that child's box.
std::uint32_t childHolding(Box& box, const int at[3]) {
  const std::array<int, 3> s = octreeSplits(box);
  int child = 0;
  for (int a = 0; a < 3; ++a) {
    int half = 0;
    if (s[a] == 2) {
      const int mid = box.lo[a] + (box.hi[a] - box.lo[a]) / 2;
      half = at[a] >= mid;
      (half ? box.lo[a] : box.hi[a]) = mid;
    }
    child = child * s[a] + half;
  }
  return std::uint32_t(child);
}

}  // namespace

const Leaf& OctreeTable::raw(int theta_h, int theta_d, int phi_d) const {
  const int at[3] = {theta_h, theta_d, phi_d};
  Box box;
  const Node* n = &nodes_.back();
  while (!(n->ref & kLeaf)) n = &nodes_[n->ref + childHolding(box, at)];
  return leaves_[n->ref & ~kLeaf];
}

OctreeTable::Block OctreeTable::rawBlock(std::array<int, 2> theta_h, std::array<int, 2> theta_d,
                                         std::array<int, 2> phi_d) const {
  const std::array<int, 2>* axes[3] = {&theta_h, &theta_d, &phi_d};
  Box box;
  const Node* n = &nodes_.back();
  // The shared walk: on while, along every split coordinate, both of the block's indices fall in
  // the same half.
  for (;;) {
    if (n->ref & kLeaf) break;
    const std::array<int, 3> s = octreeSplits(box);
    bool together = true;
    for (int a = 0; a < 3 && together; ++a) {
      if (s[a] == 1) continue;
      const int mid = box.lo[a] + (box.hi[a] - box.lo[a]) / 2;
      together = ((*axes[a])[0] >= mid) == ((*axes[a])[1] >= mid);
    }
    if (!together) break;
    const int at[3] = {theta_h[0], theta_d[0], phi_d[0]};
    n = &nodes_[n->ref + childHolding(box, at)];
  }
  Block block;
  for (int c = 0; c < 8; ++c) {
    const int at[3] = {theta_h[c >> 2], theta_d[(c >> 1) & 1], phi_d[c & 1]};
    Box b = box;
    const Node* m = n;
    while (!(m->ref & kLeaf)) m = &nodes_[m->ref + childHolding(b, at)];
    block[std::size_t(c)] = &leaves_[m->ref & ~kLeaf];
  }
  return block;
}

MerlTable OctreeTable::expand() const {
  MerlTable table;
  walkTree(nodes_, [&](const Node& n, const Box& box) {
    if (!(n.ref & kLeaf)) return true;
    const Leaf& value = leaves_[n.ref & ~kLeaf];
    for (int i = box.lo[0]; i < box.hi[0]; ++i)
      for (int j = box.lo[1]; j < box.hi[1]; ++j)
        for (int k = box.lo[2]; k < box.hi[2]; ++k)
          for (int ch = 0; ch < 3; ++ch) table.raw(ch, MerlTable::index(i, j, k)) = value[ch];
    return false;
  });
  return table;
}

float OctreeTable::maxOver(const Box& query) const {
  float result = 0;
  walkTree(nodes_, [&](const Node& n, const Box& box) {
    // Nothing below can raise the result, or the box misses the query.
    if (n.f_max <= result || !overlaps(box, query)) return false;
    // A leaf, or a node wholly inside the query: its range answers.
    if ((n.ref & kLeaf) || contains(query, box)) {
      result = n.f_max;
      return false;
    }
    return true;
  });
  return result;
}

}  // namespace btf
