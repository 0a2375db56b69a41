#include "btf/render/photon_kdtree.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/parallel_invoke.h>

#include "btf/core/error.h"

namespace btf::render {

static_assert(sizeof(PhotonKdTree::Node) == 8, "nodes are packed in 8 bytes");

namespace {

using Node = PhotonKdTree::Node;

constexpr std::uint32_t kLeafTag = 3;
// Below this depth splits are sliding-midpoint; from it on they are median splits. Sliding splits
// may cut off as few as kMinLeafSize points per level, so without a cap a skewed cloud (say,
// photons piling up geometrically towards a point) could nest arbitrarily deep; median splits
// finish any subtree of < 2^32 points within 27 more levels, which bounds the query stack.
constexpr std::size_t kBalancedDepth = 64;
constexpr std::size_t kMaxDepth = kBalancedDepth + 28;
// Subtrees of at least this many points are built as parallel tasks: smaller ones cost less
// than a task's overhead and the concatenation of its nodes.
constexpr std::uint32_t kParallelGrain = 1u << 15;

struct Item {  // a point with its input index, moved together while partitioning
  glm::vec3 p;
  std::uint32_t index;
};

struct Box {
  glm::vec3 lower, upper;
};

Box boundsOf(const Item* first, const Item* last) {
  Box box{first->p, first->p};
  for (const Item* it = first + 1; it != last; ++it) {
    box.lower = glm::min(box.lower, it->p);
    box.upper = glm::max(box.upper, it->p);
  }
  return box;
}

// The midpoint of [a, b], always inside it: halving before adding cannot overflow, and rounding
// to nearest keeps the sum between the representable a and b.
float midpoint(float a, float b) { return 0.5f * a + 0.5f * b; }

Node leafNode(std::uint32_t begin, std::uint32_t count) { return {kLeafTag | (count << 2), begin}; }

Node innerNode(int axis, float split, std::size_t right_offset) {
  return {static_cast<std::uint32_t>(axis) | static_cast<std::uint32_t>(right_offset << 2),
          std::bit_cast<std::uint32_t>(split)};
}

class Builder {
 public:
  Builder(Item* items, bool parallel) : items_(items), parallel_(parallel) {}

  // Appends the nodes of the subtree over items_[begin, end) to `out`; returns its depth.
  std::size_t build(std::uint32_t begin, std::uint32_t end, const Box& box, std::size_t depth,
                    std::vector<Node>& out) const {
    const std::uint32_t n = end - begin;
    if (n <= PhotonKdTree::kMaxLeafSize) {
      out.push_back(leafNode(begin, n));
      return 0;
    }
    const glm::vec3 extent = box.upper - box.lower;
    const int axis = extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    Item* first = items_ + begin;
    Item* last = items_ + end;
    const auto less = [axis](const Item& a, const Item& b) { return a.p[axis] < b.p[axis]; };
    constexpr std::uint32_t kMin = PhotonKdTree::kMinLeafSize;
    std::uint32_t m;
    if (depth >= kBalancedDepth) {
      m = n / 2;
      std::nth_element(first, first + m, last, less);
    } else {
      const float mid = midpoint(box.lower[axis], box.upper[axis]);
      m = static_cast<std::uint32_t>(
          std::partition(first, last, [axis, mid](const Item& it) { return it.p[axis] < mid; }) - first);
      // Slide the plane: the side that is too small takes the points nearest to it from the other.
      if (m < kMin) {
        std::nth_element(first + m, first + kMin, last, less);
        m = kMin;
      } else if (m > n - kMin) {
        std::nth_element(first, first + (n - kMin), first + m, less);
        m = n - kMin;
      }
    }
    const Box left_box = boundsOf(first, first + m);
    const Box right_box = boundsOf(first + m, last);
    // Anywhere in the gap between the sides is a valid plane; its middle keeps the pruning bound
    // equally tight for queries on either side.
    const float split = midpoint(left_box.upper[axis], right_box.lower[axis]);
    const std::uint32_t mid_index = begin + m;

    if (parallel_ && n >= kParallelGrain) {
      std::vector<Node> left, right;
      std::size_t left_depth = 0, right_depth = 0;
      tbb::parallel_invoke([&] { left_depth = build(begin, mid_index, left_box, depth + 1, left); },
                           [&] { right_depth = build(mid_index, end, right_box, depth + 1, right); });
      out.push_back(innerNode(axis, split, 1 + left.size()));
      out.insert(out.end(), left.begin(), left.end());
      out.insert(out.end(), right.begin(), right.end());
      return 1 + std::max(left_depth, right_depth);
    }
    const std::size_t self = out.size();
    out.push_back({});
    const std::size_t left_depth = build(begin, mid_index, left_box, depth + 1, out);
    out[self] = innerNode(axis, split, out.size() - self);
    const std::size_t right_depth = build(mid_index, end, right_box, depth + 1, out);
    return 1 + std::max(left_depth, right_depth);
  }

 private:
  Item* items_;
  bool parallel_;
};

inline float distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

// Squared distance from q to [lower, upper] along one axis.
inline float outside2(float q, float lower, float upper) {
  const float d = q < lower ? lower - q : (q > upper ? q - upper : 0.0f);
  return d * d;
}

// Visits, nearer child first, every leaf whose cell may hold a point within `limit` of the
// query; `limit` may shrink as leaves are visited. A cell's bound is the squared distance to
// the box made of the split planes on the way down (per axis, the nearest plane crossed), summed
// in the same order and rounding as a point's distance2, so a bound never exceeds the distance of
// a point in the cell and a point exactly at `limit` is never pruned.
template <class VisitLeaf>
void traverse(const Node* nodes, const glm::vec3& q, const glm::vec3& lower, const glm::vec3& upper, const float& limit,
              VisitLeaf&& visit_leaf) {
  struct Pending {
    std::uint32_t node;
    float bound;
    glm::vec3 off;  // per-axis squared distances to the cell
  };
  Pending stack[kMaxDepth + 1];
  std::size_t top = 0;

  std::uint32_t node = 0;
  glm::vec3 off{outside2(q.x, lower.x, upper.x), outside2(q.y, lower.y, upper.y), outside2(q.z, lower.z, upper.z)};
  float bound = off.x + off.y + off.z;
  if (!(bound <= limit)) return;
  for (;;) {
    const Node n = nodes[node];
    const std::uint32_t axis = n.bits & 3u;
    if (axis == kLeafTag) {
      visit_leaf(n.value, n.bits >> 2);
      for (;;) {
        if (top == 0) return;
        const Pending& p = stack[--top];
        if (p.bound <= limit) {
          node = p.node;
          bound = p.bound;
          off = p.off;
          break;
        }
      }
      continue;
    }
    const float diff = q[axis] - std::bit_cast<float>(n.value);
    std::uint32_t near = node + 1;
    std::uint32_t far = node + (n.bits >> 2);
    if (diff >= 0.0f) std::swap(near, far);
    glm::vec3 far_off = off;
    far_off[axis] = diff * diff;
    const float far_bound = far_off.x + far_off.y + far_off.z;
    if (far_bound <= limit) stack[top++] = {far, far_bound, far_off};
    node = near;
  }
}

// The k-nearest result kept as a max-heap on distance2 in the caller's vector.
struct HeapLess {
  bool operator()(const PhotonKdTree::Neighbor& a, const PhotonKdTree::Neighbor& b) const {
    return a.distance2 < b.distance2;
  }
};

// Replaces the heap's top (its farthest) by `x` and restores the heap.
inline void replaceTop(PhotonKdTree::Neighbor* heap, std::size_t size, PhotonKdTree::Neighbor x) {
  std::size_t i = 0;
  for (;;) {
    std::size_t child = 2 * i + 1;
    if (child >= size) break;
    if (child + 1 < size && heap[child + 1].distance2 > heap[child].distance2) ++child;
    if (!(heap[child].distance2 > x.distance2)) break;
    heap[i] = heap[child];
    i = child;
  }
  heap[i] = x;
}

}  // namespace

PhotonKdTree::PhotonKdTree(std::vector<glm::vec3> points, Build build) {
  if (points.size() > std::numeric_limits<std::uint32_t>::max())
    throw Error("PhotonKdTree: " + std::to_string(points.size()) +
                " points are more than the 2^32 - 1 that 32-bit indices address.");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec3& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error("PhotonKdTree: point " + std::to_string(i) + " of " + std::to_string(points.size()) + " is not finite (" +
                  std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                  "); photon positions must be finite numbers.");
  }
  if (points.empty()) return;

  const auto n = static_cast<std::uint32_t>(points.size());
  std::vector<Item> items(n);
  for (std::uint32_t i = 0; i < n; ++i) items[i] = {points[i], i};
  const Box box = boundsOf(items.data(), items.data() + n);
  lower_ = box.lower;
  upper_ = box.upper;
  nodes_.reserve(2 * (n / kMinLeafSize) + 1);
  depth_ = Builder(items.data(), build == Build::parallel).build(0, n, box, 0, nodes_);

  points_ = std::move(points);
  order_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    points_[i] = items[i].p;
    order_[i] = items[i].index;
  }
}

void PhotonKdTree::knn(const glm::vec3& query, std::size_t k, float max_distance2, std::vector<Neighbor>& out) const {
  out.clear();
  if (nodes_.empty() || k == 0 || !(max_distance2 >= 0.0f)) return;
  const std::size_t capacity = std::min(k, points_.size());
  out.resize(capacity);
  Neighbor* heap = out.data();
  std::size_t count = 0;
  float limit = max_distance2;
  const glm::vec3* pts = points_.data();
  traverse(nodes_.data(), query, lower_, upper_, limit, [&](std::uint32_t begin, std::uint32_t n) {
    for (std::uint32_t i = begin; i < begin + n; ++i) {
      const float d = distance2(query, pts[i]);
      if (d <= limit) {
        if (count < capacity) {
          heap[count++] = {i, d};
          if (count == capacity) {
            std::make_heap(heap, heap + count, HeapLess{});
            limit = heap[0].distance2;
          }
        } else {
          replaceTop(heap, count, {i, d});
          limit = heap[0].distance2;
        }
      }
    }
  });
  out.resize(count);
  std::sort(out.begin(), out.end(), HeapLess{});
}

void PhotonKdTree::withinRadius(const glm::vec3& query, float radius2, std::vector<Neighbor>& out) const {
  out.clear();
  if (nodes_.empty() || !(radius2 >= 0.0f)) return;
  const glm::vec3* pts = points_.data();
  traverse(nodes_.data(), query, lower_, upper_, radius2, [&](std::uint32_t begin, std::uint32_t n) {
    for (std::uint32_t i = begin; i < begin + n; ++i) {
      const float d = distance2(query, pts[i]);
      if (d <= radius2) out.push_back({i, d});
    }
  });
}

std::vector<PhotonKdTree::LeafRange> PhotonKdTree::leaves() const {
  std::vector<LeafRange> result;
  for (const Node& n : nodes_)
    if ((n.bits & 3u) == kLeafTag) result.push_back({n.value, n.bits >> 2});
  return result;
}

}  // namespace btf::render
