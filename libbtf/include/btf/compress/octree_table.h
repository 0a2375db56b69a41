// A MERL-layout table (theta_h, theta_d, phi_d; 90 x 90 x 180 cells) stored as an octree, after
// Knoll, Wald, Parker and Hansen 2006 ("Interactive Isosurface Ray Tracing of Large Octree
// Volumes"), applied to reflectance instead of density.
//
// Structure. A node covers a box of cell indices [lo, hi) in each of the three coordinates and
// splits every coordinate whose extent exceeds 1 at its midpoint (lo + (hi - lo) / 2), so a node
// has 2, 4 or 8 children and the tree needs no padding of 90 or 180 to a power of two. Children
// are stored contiguously, ordered theta_h-major, then theta_d, then phi_d (lower half first), so
// a node stores only where its first child is. Point location walks from the root comparing each
// coordinate with the midpoints: at most 8 levels.
//
// Build (bottom-up, as Knoll et al. consolidate): children that are all leaves are consolidated
// into one leaf when, in every channel, their cells satisfy max - min <= tolerance * (|max| + |min|);
// the leaf stores (max + min) / 2. So every cell of a leaf is within tolerance * |leaf value| of
// it, in every channel. At tolerance 0 only equal cells consolidate and the table is reproduced
// bit for bit. Measured and unmeasured cells (MerlTable::isMeasured) never share a leaf, and
// unmeasured cells consolidate only when equal, so holes stay exactly where they were.
//
// Every node also stores the range of f (1/sr, all channels, over its measured cells; 0 and 0
// when it has none), rounded outwards to float: the bound a rejection sampler or a culling step
// reads without visiting the leaves.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "btf/io/merl.h"

namespace btf {

class OctreeTable {
 public:
  struct Node {
    std::uint32_t ref = 0;  // kLeaf | index into leaves(), or the index of the first child
    float f_min = 0;        // range of f over the node's measured cells (all channels)
    float f_max = 0;
  };
  static constexpr std::uint32_t kLeaf = 0x80000000u;
  // Raw values of a leaf's cells, exactly as MerlTable stores them (negative: unmeasured).
  using Leaf = std::array<double, 3>;
  // A box of cell indices, [lo, hi) per coordinate (theta_h, theta_d, phi_d).
  struct Box {
    std::array<int, 3> lo{0, 0, 0};
    std::array<int, 3> hi{MerlTable::kThetaHalfRes, MerlTable::kThetaDiffRes, MerlTable::kPhiDiffRes};
  };

  // Builds the tree of `table` (parallel over the root's children; the result does not depend on
  // the thread count). Throws Error for a negative or non-finite tolerance.
  static OctreeTable build(const MerlTable& table, double tolerance);
  // Adopts stored parts (the file reader): checks that they form exactly one tree of this layout,
  // every node reached once, children stored before their parent, the root last, no leaf unused,
  // finite values, ordered float ranges. Throws Error naming the first problem.
  static OctreeTable fromParts(std::vector<Node> nodes, std::vector<Leaf> leaves, double tolerance);

  // Raw values of cell (i, j, k): point location from the root.
  const Leaf& raw(int theta_h, int theta_d, int phi_d) const;
  // Raw values of the 8 cells {theta_h[a]} x {theta_d[b]} x {phi_d[c]} at [4a + 2b + c] (the corners
  // of an interpolating lookup). One walk from the root while all eight lie in the same child, then
  // a short walk per cell from the node that holds them all: adjacent cells part only near the
  // leaves, so this takes about a quarter of the steps of eight raw() calls.
  using Block = std::array<const Leaf*, 8>;
  Block rawBlock(std::array<int, 2> theta_h, std::array<int, 2> theta_d, std::array<int, 2> phi_d) const;
  // The whole table back (values of each leaf written to all of its cells).
  MerlTable expand() const;
  // The largest f (1/sr) over the measured cells of `box`, from the ranges of the nodes that cover
  // it (whole nodes: an upper bound, exact at leaf level).
  float maxOver(const Box& box) const;

  double tolerance() const { return tolerance_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<Leaf>& leaves() const { return leaves_; }
  const Node& root() const { return nodes_.back(); }
  // Bytes of the tree in memory: nodes and leaves (the file adds its header and zstd).
  std::size_t bytes() const { return nodes_.size() * sizeof(Node) + leaves_.size() * sizeof(Leaf); }

 private:
  OctreeTable() = default;
  std::vector<Node> nodes_;  // children before parents; the root is the last node
  std::vector<Leaf> leaves_;
  double tolerance_ = 0;
};

// Children of a box: the number along each coordinate (1 or 2) and the box of child c (ordered
// theta_h-major as above). Shared by the builder, point location and the file checks.
std::array<int, 3> octreeSplits(const OctreeTable::Box& box);
OctreeTable::Box octreeChild(const OctreeTable::Box& box, int child);

// The .octree file: the .btfz container (container.h) with sections "header" (JSON: format
// "libbtf-octree", version 1, tolerance, node and leaf counts), "nodes" (u32 ref, f32 f_min, f32
// f_max each) and "leaves" (3 f64 each), both zstd-compressed. Written atomically; the reader
// throws FileError naming the file for anything the container or fromParts rejects.
void writeOctreeFile(const std::filesystem::path& path, const OctreeTable& octree);
OctreeTable readOctreeFile(const std::filesystem::path& path);

}  // namespace btf
