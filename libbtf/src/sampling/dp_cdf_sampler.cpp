#include "btf/sampling/dp_cdf_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <span>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/cdf1d.h"

// The query paths are fused into the virtual entry points: a call between them would go through
// the PLT of the shared library and block the optimizer.
#if defined(__GNUC__)
#define BTF_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define BTF_ALWAYS_INLINE inline
#endif

namespace btf {
namespace {

constexpr std::size_t kLeadPad = 1, kTrailPad = 32;

// Value of the last (implicit) vertex, and the scale of a u in [0,1) to compare with the keys.
template <class Key>
constexpr float kTop = 1.0f;
template <>
constexpr float kTop<std::uint16_t> = 65535.0f;

// Number of entries <= v among the sorted p[0..n), n <= 32; may read p[0..32).
inline unsigned countLe32(const std::uint16_t* p, unsigned v, unsigned n) {
#if defined(__SSE2__)
  // Unsigned 16-bit compare with SSE2's signed one: flip the sign bits of both sides.
  const __m128i bias = _mm_set1_epi16(short(0x8000));
  const __m128i key = _mm_set1_epi16(short(v ^ 0x8000u));
  auto greater = [&](int i) {
    return _mm_cmpgt_epi16(_mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 8 * i)), bias), key);
  };
  const std::uint64_t lo = unsigned(_mm_movemask_epi8(_mm_packs_epi16(greater(0), greater(1))));
  const std::uint64_t hi = unsigned(_mm_movemask_epi8(_mm_packs_epi16(greater(2), greater(3))));
  // The keys are sorted, so the entries <= v are a prefix: its length is the first "greater"
  // lane (lanes past n belong to the next CDF and are cut by the min).
  const unsigned first_greater = unsigned(__builtin_ctzll(lo | hi << 16 | std::uint64_t(1) << 32));
  return std::min(first_greater, n);
#else
  unsigned c = 0;
  for (unsigned i = 0; i < n; ++i) c += p[i] <= v;
  return c;
#endif
}
inline unsigned countLe32(const std::uint8_t* p, unsigned v, unsigned n) {
#if defined(__SSE2__)
  // As the 16-bit version, on 2 x 16 bytes; v > 255 (a NaN column's wrapped index) counts all.
  const __m128i bias = _mm_set1_epi8(char(0x80));
  const __m128i key = _mm_set1_epi8(char(std::min(v, 255u) ^ 0x80u));
  auto greater = [&](int i) {
    return unsigned(_mm_movemask_epi8(
        _mm_cmpgt_epi8(_mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * i)), bias), key)));
  };
  const std::uint64_t mask = greater(0) | std::uint64_t(greater(1)) << 16;
  return std::min(unsigned(__builtin_ctzll(mask | std::uint64_t(1) << 32)), n);
#else
  unsigned c = 0;
  for (unsigned i = 0; i < n; ++i) c += p[i] <= v;
  return c;
#endif
}
inline unsigned countLe32(const float* p, float v, unsigned n) {
  unsigned c = 0;
  for (unsigned i = 0; i < n; ++i) c += p[i] <= v;
  return c;
}

// Number of entries <= v among the sorted p[0..n): `steps` bisection steps (enough to bring the
// longest CDF of the table down to 32 entries; a step on a range already that short is a no-op),
// then one block compare. Nothing here branches on the data or on n: a data-dependent branch
// (a bisection step, or a loop whose count follows n) was mispredicted about once per sample and
// cost more than the rest of the search.
template <class Key, class Value>
inline unsigned countLe(const Key* p, unsigned n, Value v, int steps) {
  unsigned base = 0;
  for (int i = 0; i < steps; ++i) {
    // A mask, not a ternary (which compiles to a branch); half = 0 reads p[base - 1] and adds 0.
    const unsigned half = (n / 2) & (0u - unsigned(n > 32));
    base += unsigned(p[int(base + half) - 1] <= v) * half;
    n -= half;
  }
  return base + countLe32(p + base, v, n);
}

// Segment k of a CDF with m interior vertices at keys[0..m) / nodes[0..m) and implicit end points
// (node 0, value 0) and (node n, value top). The loads are unconditional (the arrays are padded),
// the selections arithmetic (k == 0 or k == m is data-dependent: a branch would be mispredicted).
template <class Key>
struct CdfSegment {
  float q0, dq, x0, dx;
};
template <class Key, class Node>
inline CdfSegment<Key> segmentAt(const Key* q, const Node* x, unsigned k, unsigned m, int n) {
  const unsigned not_first = unsigned(k != 0), last = unsigned(k == m);
  const int xa = int(x[int(k) - 1] * not_first), xk = x[k], xb = xk + int(last) * (n - xk);
  float qa, qb;
  if constexpr (std::is_same_v<Key, std::uint16_t>) {
    qa = float(int(q[int(k) - 1] * not_first));
    qb = float(int(q[k] | (0xffffu * last)));
  } else {
    qa = q[int(k) - 1] * float(not_first);
    qb = last ? 1.0f : q[k];
  }
  return {qa, qb - qa, float(xa), float(xb - xa)};
}

// The one expression for the density, shared by sample() and pdf() so that both agree bit for bit.
inline float pdfOf(float dq_s, float dx_s, float dq_t, float dx_t, float scale) {
  return (dq_s / dx_s) * (dq_t / dx_t) * scale;
}

// Draws inside the segment of u: the position in grid units (within [x0, x1) of the segment).
template <class Key>
inline float invert(const CdfSegment<Key>& seg, float uq) {
  const float t = (uq - seg.q0) / seg.dq;  // in [0, 1): q0 <= uq < q0 + dq
  const float g = seg.x0 + t * seg.dx, end = seg.x0 + seg.dx;
  // Stay below the segment's end node (a positive integer: its float below is its bits - 1).
  return std::min(g, std::bit_cast<float>(std::bit_cast<std::uint32_t>(end) - 1u));
}

// True if the position g (grid units, cell width 1) is at least margin inside its cell.
inline bool wellInside(float g, float margin) {
  const float frac = g - float(int(g));
  return frac >= margin && frac <= 1.0f - margin;
}

}  // namespace

DpCdfSampler::DpCdfSampler(std::shared_ptr<const Material> material, const SamplerOptions& options)
    : BinnedSampler(std::move(material), options), nu_(gridRows()), nv_(gridColumns()) {
  narrow_ = options.epsilon >= kNarrowEpsilon && std::max(nu_, nv_) < 65536;
  byte_nodes_ = std::max(nu_, nv_) <= 256;
  const float top = narrow_ ? 65535.0f : 1.0f;
  pdf_scale_ = float(double(nu_) * double(nv_) / (double(top) * double(top)) * (0.5 / std::numbers::pi));
  const std::vector<float> grid = tabulateGrid(nu_, nv_);
  const std::size_t cdfs_per_bin = std::size_t(nu_) + 1;
  // Reduce and quantize each bin on its own (in parallel), then concatenate in bin order: the
  // layout does not depend on the thread count.
  struct BinCdfs {
    std::vector<std::uint16_t> nodes, cdf16;
    std::vector<float> cdf32;
    std::vector<std::uint32_t> sizes;  // interior vertices per CDF
    double deviation = 0;
    bool empty = false;
  };
  std::vector<BinCdfs> bins(binCount());
  tbb::parallel_for(std::size_t(0), binCount(), [&](std::size_t bin) {
    BinCdfs& out = bins[bin];
    std::vector<float> rows(std::size_t(nu_) * (nv_ + 1)), row_integrals(nu_), marginal(nu_ + 1);
    for (int i = 0; i < nu_; ++i)
      row_integrals[i] = float(buildCdf1D(std::span(grid).subspan((bin * nu_ + i) * nv_, nv_),
                                          std::span(rows).subspan(std::size_t(i) * (nv_ + 1), nv_ + 1)));
    out.empty = buildCdf1D(row_integrals, marginal) == 0.0;
    std::vector<CdfVertex> v, stored;
    std::vector<long> q;
    auto reduce = [&](std::span<const float> full, float tolerance) {
      const std::size_t n = full.size() - 1;
      v.clear();
      reduceCdf(full, tolerance, options.reduction, v);
      const std::size_t m = v.size() - 2;
      stored = v;
      if (narrow_) {
        // Round to the quantum, keeping the values non-decreasing and every segment that has
        // mass at >= 1 quantum (a forward then a backward pass; always feasible, as there are at
        // most n <= 65535 segments).
        q.assign(v.size(), 0);
        q.back() = 65535;
        for (std::size_t j = 1; j <= m; ++j)
          q[j] = std::max(std::lround(double(v[j].cdf) * 65535.0), q[j - 1] + long(v[j].cdf > v[j - 1].cdf));
        for (std::size_t j = m; j >= 1; --j)
          q[j] = std::min(q[j], q[j + 1] - long(v[j + 1].cdf > v[j].cdf));
        for (std::size_t j = 0; j < v.size(); ++j) stored[j].cdf = float(double(q[j]) / 65535.0);
      }
      for (std::size_t j = 1; j <= m; ++j) {
        out.nodes.push_back(static_cast<std::uint16_t>(std::lround(double(v[j].x) * double(n))));
        if (narrow_)
          out.cdf16.push_back(static_cast<std::uint16_t>(q[j]));
        else
          out.cdf32.push_back(v[j].cdf);
      }
      out.sizes.push_back(std::uint32_t(m));
      out.deviation = std::max(out.deviation, cdfDeviation(full, stored));
    };
    // The marginal is one CDF of nu + 1 per bin, but every draw goes through it and an error there
    // scales the density of a whole row: a tighter tolerance there lowers the variance of glossy
    // half-vector tables markedly, for few more bytes (the marginal is a small part of the tables).
    reduce(marginal, options.epsilon / kMarginalTighter);
    for (int i = 0; i < nu_; ++i) reduce(std::span(rows).subspan(std::size_t(i) * (nv_ + 1), nv_ + 1), options.epsilon);
  });
  starts_.reserve(binCount() * cdfs_per_bin + 1);
  empty_.resize(binCount());
  nodes16_.assign(kLeadPad, 0);
  if (narrow_)
    cdf16_.assign(kLeadPad, 0);
  else
    cdf32_.assign(kLeadPad, 0.0f);
  for (std::size_t bin = 0; bin < binCount(); ++bin) {
    const BinCdfs& b = bins[bin];
    std::size_t next = nodes16_.size();
    for (std::uint32_t m : b.sizes) {
      starts_.push_back(std::uint32_t(next));
      next += m;
      vertex_count_ += m + 2;
    }
    if (next + kTrailPad > UINT32_MAX)
      throw Error("DpCdfSampler: tables beyond 2^32 vertices; use a coarser grid or a larger epsilon");
    nodes16_.insert(nodes16_.end(), b.nodes.begin(), b.nodes.end());
    cdf16_.insert(cdf16_.end(), b.cdf16.begin(), b.cdf16.end());
    cdf32_.insert(cdf32_.end(), b.cdf32.begin(), b.cdf32.end());
    empty_[bin] = b.empty ? 1 : 0;
    max_deviation_ = std::max(max_deviation_, b.deviation);
  }
  starts_.push_back(std::uint32_t(nodes16_.size()));
  // Bisection steps that bring the longest CDF down to 32 entries (n -> n - n / 2 per step).
  std::uint32_t longest = 0;
  for (std::size_t c = 0; c + 1 < starts_.size(); ++c) longest = std::max(longest, starts_[c + 1] - starts_[c]);
  for (std::uint32_t n = longest; n > 1; ++full_search_steps_) n -= n / 2;
  for (search_steps_ = 0; longest > 32; ++search_steps_) longest -= longest / 2;
  nodes16_.resize(nodes16_.size() + kTrailPad, 0xffff);
  if (byte_nodes_) {  // every index is <= 255 (the padding becomes 0xff)
    nodes8_.assign(nodes16_.begin(), nodes16_.end());
    std::vector<std::uint16_t>().swap(nodes16_);
  }
  if (narrow_)
    cdf16_.resize(cdf16_.size() + kTrailPad, 0xffff);
  else
    cdf32_.resize(cdf32_.size() + kTrailPad, 2.0f);
  cdf16_.shrink_to_fit(), cdf32_.shrink_to_fit();
  reportInvalidEvaluations();
}

template <class Key, class Node>
BTF_ALWAYS_INLINE float DpCdfSampler::pdfImpl(std::size_t bin, glm::vec2 st, const DrawnCells* drawn) const {
  // st in [0, 1)^2 (checked by the callers); the cells as rowOf would give them, with 32-bit
  // conversions (a float -> size_t conversion is a branchy sequence on x86-64).
  const int row = std::min(int(st.x * float(nu_)), nu_ - 1), col = std::min(int(st.y * float(nv_)), nv_ - 1);
  // In the drawn row, the row's conditional is the drawn one; countLe finds the segment holding a
  // cell, so for cells in both drawn spans the searches below would return the drawn segments.
  if (drawn && row == drawn->row && float(row) >= drawn->s_x0 && float(row) < drawn->s_x0 + drawn->s_dx &&
      float(col) >= drawn->t_x0 && float(col) < drawn->t_x0 + drawn->t_dx)
    return drawn->density;
  const Key* q = keys<Key>();
  const std::uint32_t* starts = starts_.data() + bin * (std::size_t(nu_) + 1);
  const std::uint32_t ms = starts[0], ns = starts[1] - ms, mt = starts[1 + row], nt = starts[2 + row] - mt;
  const Node* x = nodes<Node>();
  const unsigned ks = countLe(x + ms, ns, unsigned(row), search_steps_);
  const unsigned kt = countLe(x + mt, nt, unsigned(col), search_steps_);
  const CdfSegment<Key> s = segmentAt(q + ms, x + ms, ks, ns, nu_);
  const CdfSegment<Key> t = segmentAt(q + mt, x + mt, kt, nt, nv_);
  return pdfOf(s.dq, s.dx, t.dq, t.dx, pdf_scale_);
}

float DpCdfSampler::pdfQuery(const BinQuery& q, const glm::vec3& wi) const { return pdfQueryNear(q, wi, nullptr); }

float DpCdfSampler::pdfQueryNear(const BinQuery& q, const glm::vec3& wi, const DrawnCells* drawn) const {
  // The same steps as the generic BinnedSampler::pdfQuery + pdfInBin, without the virtual calls.
  if (!(wi.z > 0.0f)) return 0.0f;
  const std::optional<SquarePoint> p = incomingToSquare(q.toBinFrame(wi), q.wo);
  if (!p || empty_[q.bin]) return 0.0f;
  const float v = withTableTypes(
      [&](auto key, auto node) { return pdfImpl<decltype(key), decltype(node)>(q.bin, p->st, drawn); });
  // pdf_scale_ holds Incident's 1 / (2 pi); Half's factor is 1 / (16 pi r^2 wo.h).
  return parameterization() == Parameterization::Half ? v * (kTwoPi * p->to_solid_angle) : v;
}

template <class Key, class Node>
BTF_ALWAYS_INLINE std::optional<BinnedSampler::DirectionSample> DpCdfSampler::sampleImpl(const BinQuery& q, glm::vec2 u) const {
  const Key* keys_ = keys<Key>();
  const Node* nodes = this->nodes<Node>();
  const std::uint32_t* starts = starts_.data() + q.bin * (std::size_t(nu_) + 1);
  // Keys compared with u scaled to them: for 16-bit keys, key <= u * 65535 iff key <= its floor.
  const float us = u.x * kTop<Key>, ut = u.y * kTop<Key>;
  auto searchKey = [](float uq) {
    if constexpr (std::is_same_v<Key, std::uint16_t>)
      return unsigned(int(uq));
    else
      return uq;
  };
  // Marginal: segment, position in grid units, row.
  const std::uint32_t ms = starts[0], ns = starts[1] - ms;
  const unsigned ks = countLe(keys_ + ms, ns, searchKey(us), search_steps_);
  const CdfSegment<Key> seg_s = segmentAt(keys_ + ms, nodes + ms, ks, ns, nu_);
  const float gs = invert(seg_s, us);
  const float s = gs / float(nu_);
  const int row = std::min(int(s * float(nu_)), nu_ - 1);  // rowOf(s), as pdf() takes it
  // The row's conditional.
  const std::uint32_t mt = starts[1 + row], nt = starts[2 + row] - mt;
  const unsigned kt = countLe(keys_ + mt, nt, searchKey(ut), search_steps_);
  const CdfSegment<Key> seg_t = segmentAt(keys_ + mt, nodes + mt, kt, nt, nv_);
  const float gt = invert(seg_t, ut);
  const float t = gt / float(nv_);
  const bool half = parameterization() == Parameterization::Half;
  const std::optional<glm::vec3> wi_bin = half ? squareToIncoming({s, t}, q.wo) : squareToDirection({s, t});
  if (!wi_bin) return std::nullopt;  // a half vector whose reflection is below the horizon
  const glm::vec3 wi = glm::normalize(q.fromBinFrame(*wi_bin));
  // The pdf of wi as pdf() computes it: the shortcut when (s, t) is well inside its grid cell
  // (then the round trip through wi lands in the same cell, row and segments), else pdf()'s path,
  // which skips its searches where wi's cell lies in the drawn row and segments. Half maps always
  // take pdf()'s path: the reflection and the half vector's renormalization make a longer round
  // trip, and the Jacobian depends on wi.
  const float density = pdfOf(seg_s.dq, seg_s.dx, seg_t.dq, seg_t.dx, pdf_scale_);
  float p;
  if (!half && wellInside(gs, kCellMargin * float(nu_)) && wellInside(gt, kCellMargin * float(nv_))) {
    p = density;
  } else {
    const DrawnCells drawn{row, seg_s.x0, seg_s.dx, seg_t.x0, seg_t.dx, density};
    p = pdfQueryNear(q, wi, &drawn);
  }
  if (!(p > 0.0f)) return std::nullopt;  // only on a boundary of a zero-density cell
  return DirectionSample{wi, p};
}

std::optional<BinnedSampler::DirectionSample> DpCdfSampler::sampleQuery(const BinQuery& q, glm::vec2 u,
                                                                        int& tries) const {
  if (empty_[q.bin]) return std::nullopt;
  tries = 1;
  return withTableTypes([&](auto key, auto node) { return sampleImpl<decltype(key), decltype(node)>(q, u); });
}

// The generic entry points (the fast paths above do not use them; they define the same density).
std::optional<glm::vec2> DpCdfSampler::sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const {
  if (empty_[bin]) return std::nullopt;
  tries = 1;
  const BinQuery q{bin, 1.0f, 0.0f, binDirection(bin)};
  const auto d =
      withTableTypes([&](auto key, auto node) { return sampleImpl<decltype(key), decltype(node)>(q, u); });
  if (!d) return std::nullopt;
  const std::optional<SquarePoint> p = incomingToSquare(d->wi, q.wo);
  if (!p) return std::nullopt;
  return p->st;
}

float DpCdfSampler::pdfInBin(std::size_t bin, glm::vec2 st) const {
  if (empty_[bin] || !(st.x >= 0.0f && st.x < 1.0f && st.y >= 0.0f && st.y < 1.0f)) return 0.0f;
  return withTableTypes([&](auto key, auto node) { return pdfImpl<decltype(key), decltype(node)>(bin, st); }) * kTwoPi;
}

SamplerStats DpCdfSampler::stats() const {
  SamplerStats s;
  fillCommonStats(s);
  s.bytes = nodes8_.size() + (nodes16_.size() + cdf16_.size()) * sizeof(std::uint16_t) + cdf32_.size() * sizeof(float) +
            starts_.size() * sizeof(std::uint32_t) + empty_.size();
  s.elements = vertex_count_;
  s.mean_elements_per_cdf = double(vertex_count_) / double(starts_.size() - 1);
  s.empty_bins = std::size_t(std::count(empty_.begin(), empty_.end(), 1));
  return s;
}

}  // namespace btf
