#include "vq_prune.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "btf/core/error.h"

namespace btf {

namespace {

constexpr std::uint32_t kDropped = std::numeric_limits<std::uint32_t>::max();

// New index of every entry: kept ones (used, or entry 0) numbered in order, the rest kDropped.
std::vector<std::uint32_t> renumbering(const std::vector<bool>& used) {
  std::vector<std::uint32_t> to(used.size(), kDropped);
  std::uint32_t next = 0;
  for (std::size_t e = 0; e < used.size(); ++e)
    if (used[e] || e == 0) to[e] = next++;
  return to;
}

// Keeps the kept entries (of `width` elements each) of `values`, in order.
template <class T>
void compact(std::vector<T>& values, std::size_t width, const std::vector<std::uint32_t>& to) {
  std::size_t out = 0;
  for (std::size_t e = 0; e < to.size(); ++e) {
    if (to[e] == kDropped) continue;
    for (std::size_t i = 0; i < width; ++i) values[out * width + i] = values[e * width + i];
    ++out;
  }
  values.resize(out * width);
}

void mark(std::vector<bool>& used, std::uint32_t index, const char* what) {
  if (index >= used.size()) throw Error(std::string("pruneVqCodebooks: a ") + what + " index is out of its codebook");
  used[index] = true;
}

}  // namespace

void pruneVqCodebooks(VqBtf::Impl& books, std::span<VqBtf::Impl* const> materials) {
  const int levels = books.options.levels;
  // Level 2: reached from the level-3 entries (3 levels) or the top streams (2 levels).
  if (levels >= 2) {
    std::vector<bool> used(books.l2Count(), false);
    for (const VqBtf::Impl* m : materials)
      for (std::uint32_t e : levels == 3 ? m->l3_index : m->top_index) mark(used, e, "level-2");
    const auto to = renumbering(used);
    compact(books.l2_index, books.ringCount(), to);
    compact(books.l2_scale, books.ringCount(), to);
    compact(books.l2_chroma, books.ringCount(), to);
    for (VqBtf::Impl* m : materials)
      for (std::uint32_t& e : levels == 3 ? m->l3_index : m->top_index) e = to[e];
  }
  // Level 1 and chromaticity, per ring: reached from the level-2 entries or (1 level) the top stream.
  for (int r = 0; r < int(books.ringCount()); ++r) {
    const std::size_t ring = std::size_t(r), n = std::size_t(books.ringSize(r));
    std::vector<bool> used1(books.l1Count(r), false), used_c(books.chromaCount(r), false);
    // Every (level-1 entry, chroma entry) pair of ring r that a code holds.
    auto visit = [&](auto&& f) {
      if (levels >= 2) {
        for (std::size_t k = ring; k < books.l2_index.size(); k += books.ringCount()) f(books.l2_index[k], books.l2_chroma[k]);
      } else {
        for (VqBtf::Impl* m : materials)
          for (std::size_t k = ring; k < m->top_index.size(); k += books.ringCount()) f(m->top_index[k], m->top_chroma[k]);
      }
    };
    visit([&](std::uint32_t e, std::uint32_t c) {
      mark(used1, e, "level-1");
      mark(used_c, c, "chromaticity");
    });
    const auto to1 = renumbering(used1), to_c = renumbering(used_c);
    compact(books.l1[ring], n, to1);
    if (!books.l1_coef[ring].empty()) compact(books.l1_coef[ring], n, to1);
    compact(books.chroma[ring], 2 * n, to_c);
    visit([&](std::uint32_t& e, std::uint32_t& c) {
      e = to1[e];
      c = to_c[c];
    });
  }
}

}  // namespace btf
