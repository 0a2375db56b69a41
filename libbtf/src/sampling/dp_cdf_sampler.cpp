#include "btf/sampling/dp_cdf_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <span>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/sampling/cdf1d.h"

namespace btf {

DpCdfSampler::DpCdfSampler(std::shared_ptr<const Material> material, const SamplerOptions& options)
    : BinnedSampler(std::move(material), options), nu_(options.cos_theta_bins), nv_(options.phi_bins) {
  const std::vector<float> grid = tabulateGrid(nu_, nv_);
  const std::size_t cdfs_per_bin = std::size_t(nu_) + 1;
  // Reduce each bin on its own (in parallel), then concatenate in bin order: the layout does not
  // depend on the thread count.
  struct BinCdfs {
    std::vector<CdfVertex> vertices;
    std::vector<std::uint32_t> sizes;
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
    auto reduce = [&](std::span<const float> full) {
      const std::size_t before = out.vertices.size();
      out.sizes.push_back(std::uint32_t(reduceCdf(full, options.epsilon, options.reduction, out.vertices)));
      out.deviation = std::max(out.deviation, cdfDeviation(full, std::span(out.vertices).subspan(before)));
    };
    reduce(marginal);
    for (int i = 0; i < nu_; ++i) reduce(std::span(rows).subspan(std::size_t(i) * (nv_ + 1), nv_ + 1));
  });
  refs_.reserve(binCount() * cdfs_per_bin);
  empty_.resize(binCount());
  std::vector<std::uint16_t> guide;
  auto pushGuide = [&] {
    for (std::size_t g = 0; g < guide.size(); g += 2)
      words_.push_back(std::uint32_t(guide[g]) | (g + 1 < guide.size() ? std::uint32_t(guide[g + 1]) << 16 : 0u));
  };
  for (std::size_t bin = 0; bin < binCount(); ++bin) {
    const CdfVertex* v = bins[bin].vertices.data();
    for (std::uint32_t n : bins[bin].sizes) {
      // Half a cell per segment: the scan then takes one or two steps within the vertex run
      // (cheap: same or next cache line), for half the guide memory of one cell per segment.
      const std::size_t segments = n - 1, last = segments - 1, cells = guideCellsFor((segments + 1) / 2);
      const std::size_t words = words_.size() + 2 * guideWords(cells) + 2 * std::size_t(n);
      if (words > UINT32_MAX) throw Error("DpCdfSampler: tables beyond 2^32 words; use a coarser grid or a larger epsilon");
      guide.resize(cells);
      buildGuide([&](std::size_t i) { return v[i].cdf; }, last, std::span(guide));
      pushGuide();
      refs_.push_back({std::uint32_t(words_.size()), std::uint16_t(last), std::uint16_t(std::countr_zero(cells))});
      for (std::uint32_t k = 0; k < n; ++k) {
        words_.push_back(std::bit_cast<std::uint32_t>(v[k].x));
        words_.push_back(std::bit_cast<std::uint32_t>(v[k].cdf));
      }
      buildGuide([&](std::size_t i) { return v[i].x; }, last, std::span(guide));
      pushGuide();
      v += n;
      vertex_count_ += n;
    }
    empty_[bin] = bins[bin].empty ? 1 : 0;
    max_deviation_ = std::max(max_deviation_, bins[bin].deviation);
  }
  words_.shrink_to_fit();
  reportInvalidEvaluations();
}

namespace {

float vertexX(const std::uint32_t* w, std::size_t k) { return std::bit_cast<float>(w[2 * k]); }
float vertexCdf(const std::uint32_t* w, std::size_t k) { return std::bit_cast<float>(w[2 * k + 1]); }
CdfVertex vertexAt(const std::uint32_t* w, std::size_t k) { return {vertexX(w, k), vertexCdf(w, k)}; }
// Entry g of a guide of 16-bit entries packed two per word, low half first.
std::size_t guideEntry(const std::uint32_t* guide, std::size_t g) { return (guide[g >> 1] >> ((g & 1) * 16)) & 0xffffu; }
// The density of segment k, as pdfVertexCdf computes it.
float slope(const std::uint32_t* w, std::size_t k) {
  return (vertexCdf(w, k + 1) - vertexCdf(w, k)) / (vertexX(w, k + 1) - vertexX(w, k));
}

}  // namespace

inline std::size_t DpCdfSampler::segmentByCdf(const CdfRef& c, float u) const {
  const std::uint32_t* w = vertexWords(c);
  const std::size_t cells = std::size_t(1) << c.guide_log2;
  const std::uint32_t* guide = w - guideWords(cells);
  return guidedSearch([w](std::size_t i) { return vertexCdf(w, i); }, c.last_segment,
                      [guide](std::size_t g) { return guideEntry(guide, g); }, cells, u);
}

inline std::size_t DpCdfSampler::segmentByX(const CdfRef& c, float x, std::size_t hint) const {
  // pdfVertexCdf's rule: the largest k <= last_segment with v[1..k].x <= x (x >= v[0].x).
  const std::uint32_t* w = vertexWords(c);
  if (hint <= c.last_segment && vertexX(w, hint) <= x && (hint == c.last_segment || x < vertexX(w, hint + 1)))
    return hint;
  const std::uint32_t* guide = w + 2 * (std::size_t(c.last_segment) + 2);
  return guidedSearch([w](std::size_t i) { return vertexX(w, i); }, c.last_segment,
                      [guide](std::size_t g) { return guideEntry(guide, g); }, std::size_t(1) << c.guide_log2, x);
}

inline float DpCdfSampler::pdfWithHints(const BinQuery& q, const glm::vec3& wi, std::size_t s_hint, std::size_t row_hint,
                                 std::size_t t_hint) const {
  // The same steps as the generic BinnedSampler::pdfQuery + pdfInBin, without the virtual calls.
  if (!(wi.z > 0.0f)) return 0.0f;
  const glm::vec2 st = directionToSquare(q.toBinFrame(wi));
  if (!(st.x < 1.0f) || empty_[q.bin]) return 0.0f;
  const std::size_t first = q.bin * (std::size_t(nu_) + 1);
  const CdfRef& m = refs_[first];
  const std::uint32_t* mw = vertexWords(m);
  // Outside the first and last vertex the density is 0 (pdfVertexCdf); s and t are in [0, 1) and
  // reduceCdf keeps the nodes 0 and 1, so this never triggers for the sampler's own CDFs.
  if (!(st.x >= vertexX(mw, 0) && st.x <= vertexX(mw, m.last_segment + 1u))) return 0.0f;
  const std::size_t ks = segmentByX(m, st.x, s_hint);
  const std::size_t row = rowOf(st.x);
  const CdfRef& c = refs_[first + 1 + row];
  const std::uint32_t* cw = vertexWords(c);
  if (!(st.y >= vertexX(cw, 0) && st.y <= vertexX(cw, c.last_segment + 1u))) return 0.0f;
  const std::size_t kt = segmentByX(c, st.y, row == row_hint ? t_hint : kNoHint);
  return slope(mw, ks) * slope(cw, kt) * kInv2Pi;
}

float DpCdfSampler::pdfQuery(const BinQuery& q, const glm::vec3& wi) const {
  return pdfWithHints(q, wi, kNoHint, kNoHint, kNoHint);
}

inline VertexCdfSample DpCdfSampler::sampleCdf(std::size_t index, float u) const {
  const CdfRef& c = refs_[index];
  const std::size_t k = segmentByCdf(c, u);
  return invertVertexSegment(vertexAt(vertexWords(c), k), vertexAt(vertexWords(c), k + 1), k, u);
}

float DpCdfSampler::pdfCdf(std::size_t index, float x) const {
  const CdfRef& c = refs_[index];
  const std::uint32_t* w = vertexWords(c);
  if (!(x >= vertexX(w, 0) && x <= vertexX(w, c.last_segment + 1u))) return 0.0f;
  return slope(w, segmentByX(c, x, kNoHint));
}

std::optional<BinnedSampler::DirectionSample> DpCdfSampler::sampleQuery(const BinQuery& q, glm::vec2 u,
                                                                        int& tries) const {
  if (empty_[q.bin]) return std::nullopt;
  tries = 1;
  const std::size_t first = q.bin * (std::size_t(nu_) + 1);
  const VertexCdfSample s = sampleCdf(first, u.x);
  const std::size_t row = rowOf(s.x);
  const VertexCdfSample t = sampleCdf(first + 1 + row, u.y);
  const glm::vec3 wi = glm::normalize(q.fromBinFrame(squareToDirection({s.x, t.x})));
  const float p = pdfWithHints(q, wi, s.segment, row, t.segment);
  if (!(p > 0.0f)) return std::nullopt;  // only on a boundary of a zero-density cell
  return DirectionSample{wi, p};
}

// The generic entry points (the fast path above does not use them; they define the same density).
// The helpers above are "inline" (private, this file only) so that the query paths fuse them.
std::optional<glm::vec2> DpCdfSampler::sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const {
  if (empty_[bin]) return std::nullopt;
  tries = 1;
  const std::size_t first = bin * (std::size_t(nu_) + 1);
  const float s = sampleCdf(first, u.x).x;
  return glm::vec2{s, sampleCdf(first + 1 + rowOf(s), u.y).x};
}

float DpCdfSampler::pdfInBin(std::size_t bin, glm::vec2 st) const {
  if (empty_[bin]) return 0.0f;
  const std::size_t first = bin * (std::size_t(nu_) + 1);
  return pdfCdf(first, st.x) * pdfCdf(first + 1 + rowOf(st.x), st.y);
}

SamplerStats DpCdfSampler::stats() const {
  SamplerStats s;
  fillCommonStats(s);
  s.bytes = words_.size() * sizeof(std::uint32_t) + refs_.size() * sizeof(CdfRef) + empty_.size();
  s.elements = vertex_count_;
  s.mean_elements_per_cdf = double(vertex_count_) / double(refs_.size());
  s.empty_bins = std::size_t(std::count(empty_.begin(), empty_.end(), 1));
  return s;
}

}  // namespace btf
