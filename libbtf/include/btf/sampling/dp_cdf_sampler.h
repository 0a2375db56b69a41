// The tabulated sampler with compressed CDFs (dp_cdf.h): the same grid as TabulatedSampler, but
// the marginal CDF of each bin and the conditional CDF of each row keep only the vertices that the
// chosen reduction needs to stay within options.epsilon of the full CDF. Sampling: a search of the
// marginal's vertices (continuous s, inverting the linear segment), the row holding s chooses the
// conditional, a search of its vertices gives t (both searches guided, as below; they find the
// segment a bisection would). pdf(s, t) = marginal slope at s times the
// conditional's slope at t, over 2 pi: exact for any epsilon (it is the density of the coarser
// polylines, which are what sample() inverts).
//
// Memory: one flat array of 32-bit words holding, per CDF and contiguous, a guide table over u
// (for sampling), the (x, cdf) float pairs of its vertices, and a guide table over x (for pdf);
// plus an 8-byte reference per CDF. The guides (cdf1d.h, guidedSearch) hold 16-bit segment
// indices, two per word, in guideCellsFor(segments) / 2 cells each; they replace the four
// bisections of a sample + pdf by about one or two steps each. Each guide sits next to the end of
// the vertex run it indexes, so a search mostly touches neighbouring cache lines (the tables of a
// MERL-size material exceed the L2 cache). The guides and references cost about +35% of the bytes
// at epsilon = 1e-3 on a MERL-size GGX table (counted in stats().bytes).
//
// Speed: sampleQuery remembers the segments and the row it drew and hands them to the pdf of the
// final float direction as hints; a hint is used only after checking that the recomputed (s, t)
// lies in that segment (the rule pdfVertexCdf applies), so the pdf is the one pdf() computes,
// bit for bit, and the guided search runs only when rounding moved (s, t) across a vertex.
#pragma once

#include <cstdint>
#include <vector>

#include "btf/sampling/binned_sampler.h"

namespace btf {

class DpCdfSampler final : public BinnedSampler {
 public:
  DpCdfSampler(std::shared_ptr<const Material> material, const SamplerOptions& options = {});

  SamplerKind kind() const override { return SamplerKind::DpCdf; }
  SamplerStats stats() const override;
  // Largest deviation of any reduced CDF from its full CDF (<= epsilon up to float rounding).
  double maxCdfDeviation() const { return max_deviation_; }

 protected:
  std::optional<DirectionSample> sampleQuery(const BinQuery& q, glm::vec2 u, int& tries) const final;
  float pdfQuery(const BinQuery& q, const glm::vec3& wi) const final;
  std::optional<glm::vec2> sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const override;
  float pdfInBin(std::size_t bin, glm::vec2 st) const override;

 private:
  struct CdfRef {
    std::uint32_t first;         // word of vertex 0 in words_; the u guide ends there
    std::uint16_t last_segment;  // vertices - 2
    std::uint16_t guide_log2;    // cells of each guide = 1 << guide_log2
  };
  // No hint: the pdf searches.
  static constexpr std::size_t kNoHint = ~std::size_t(0);
  std::size_t rowOf(float s) const { return std::min(static_cast<std::size_t>(s * float(nu_)), std::size_t(nu_ - 1)); }
  static std::size_t guideWords(std::size_t cells) { return (cells + 1) / 2; }
  const std::uint32_t* vertexWords(const CdfRef& c) const { return words_.data() + c.first; }
  std::size_t segmentByCdf(const CdfRef& c, float u) const;
  std::size_t segmentByX(const CdfRef& c, float x, std::size_t hint) const;
  float pdfWithHints(const BinQuery& q, const glm::vec3& wi, std::size_t s_hint, std::size_t row_hint,
                     std::size_t t_hint) const;
  VertexCdfSample sampleCdf(std::size_t index, float u) const;
  float pdfCdf(std::size_t index, float x) const;

  int nu_, nv_;
  std::vector<std::uint32_t> words_;  // all CDFs, bin-major: marginal then rows 0..nu-1
  std::vector<CdfRef> refs_;          // one per CDF, same order
  std::size_t vertex_count_ = 0;
  std::vector<unsigned char> empty_;
  double max_deviation_ = 0;
};

}  // namespace btf
