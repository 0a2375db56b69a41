// The tabulated sampler with compressed CDFs (dp_cdf.h): the same grid as TabulatedSampler, but
// the conditional CDF of each row keeps only the vertices that the chosen reduction needs to stay
// within options.epsilon of the full CDF, and the marginal CDF of each bin those within
// epsilon / kMarginalTighter. Sampling: a search of the
// marginal's vertices (continuous s, inverting the linear segment), the row holding s chooses the
// conditional, a search of its vertices gives t. pdf(s, t) = marginal slope at s times the
// conditional's slope at t, over 2 pi: exact for any epsilon (it is the density of the stored
// polylines, which are what sample() inverts).
//
// Memory. Kept vertices are grid nodes, so a vertex is stored as its node index (8 bits when the
// grid has at most 256 cells per side, as MERL-size tables do, else 16) and its CDF value; the first (node 0, CDF 0) and last (node n, CDF 1) vertex of every CDF are
// implicit. CDF values are 16-bit fixed point (value * 65535) when epsilon >= kNarrowEpsilon, else
// floats. Quantizing moves each vertex by at most half a quantum (7.6e-6), so the stored polyline
// stays within epsilon + quantum / 2 of the full CDF (segments with mass keep at least one quantum,
// so the density stays > 0 wherever the tabulated one is; that may move a vertex by a little more
// in degenerate CDFs). maxCdfDeviation() is measured on the stored polylines, whatever they are.
// Per CDF there is one 32-bit index of its first vertex (the count is the next index minus it);
// no guide tables: a search bisects (branch-free, a fixed number of steps per table) down to 32
// entries, then compares those 32 at once (SSE2, part of x86-64) and counts the leading matches.
// About 3 bytes per kept interior vertex (4 with 16-bit nodes) plus 4 per CDF.
//
// Cells and segments. The pdf of (s, t) takes the grid cell c = floor(s * nu) (the row) and the
// marginal segment = the number of interior vertices at nodes <= c; the same for t in the row's
// conditional. sample() draws inside a segment and returns pdf(wi, wo) of its final float wi:
// when the drawn (s, t) lies at least kCellMargin (in units of the square) inside its grid cell,
// the round trip (s, t) -> wi -> (s, t) (error < 1e-6) cannot leave the cell, so the pdf is
// computed from the segments just drawn, by the same expression pdf() uses (bit for bit equal);
// otherwise (a fraction ~ 2 kCellMargin (nu + nv) of the draws) it runs pdf()'s own path on wi.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "btf/sampling/binned_sampler.h"

namespace btf {

class DpCdfSampler final : public BinnedSampler {
 public:
  DpCdfSampler(std::shared_ptr<const Material> material, const SamplerOptions& options = {});

  // From this epsilon on, CDF values are stored in 16 bits (the quantum then adds at most 1/64
  // of epsilon to the deviation); below it as floats.
  static constexpr float kNarrowEpsilon = 32.0f / 65535.0f;
  // The marginal CDF of each bin is reduced to epsilon / kMarginalTighter (dp_cdf_sampler.cpp).
  static constexpr float kMarginalTighter = 16.0f;
  // How far inside its grid cell (in units of s and t) a draw must be for the pdf shortcut.
  static constexpr float kCellMargin = 1e-5f;

  SamplerKind kind() const override { return SamplerKind::DpCdf; }
  SamplerStats stats() const override;
  // Largest deviation of any stored CDF from its full CDF, measured on the stored (quantized)
  // polylines: <= epsilon + cdfQuantum() / 2 up to float rounding.
  double maxCdfDeviation() const { return max_deviation_; }
  // Step of the stored CDF values: 1 / 65535 for 16-bit storage, 0 for floats.
  double cdfQuantum() const { return narrow_ ? 1.0 / 65535.0 : 0.0; }

  // 32 queries per step in AVX2 lanes (gathers for the searches, the scalar path's arithmetic
  // operation for operation, so the results are the single queries' bit for bit); lanes whose
  // draw lies within kCellMargin of a cell border (Incident) or whose wi maps back into another
  // cell (Half) take the scalar pdf. Used for isotropic materials with 16-bit CDFs on CPUs with
  // AVX2, in either parameterization; otherwise the single queries run in a loop.
  void sampleDirections(std::span<const glm::vec3> wo, std::span<const glm::vec2> u,
                        std::span<DirectionSample> out) const override;
  void pdfs(std::span<const glm::vec3> wi, std::span<const glm::vec3> wo, std::span<float> out) const override;
  // True when sampleDirections and pdfs take the vector path on this machine.
  bool vectorized() const;

 protected:
  std::optional<DirectionSample> sampleQuery(const BinQuery& q, glm::vec2 u, int& tries) const final;
  float pdfQuery(const BinQuery& q, const glm::vec3& wi) const final;
  std::optional<glm::vec2> sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const override;
  float pdfInBin(std::size_t bin, glm::vec2 st) const override;

 private:
  struct LaneTables;  // the tables as the vector path reads them (dp_cdf_batch.cpp)
  LaneTables laneTables() const;
  template <class Key, class Node>
  std::optional<DirectionSample> sampleImpl(const BinQuery& q, glm::vec2 u) const;
  // A draw's row, the grid-cell spans [x0, x0 + dx) of its two segments and their density: where
  // pdf()'s searches for a cell in that row and those spans would find the same segments.
  struct DrawnCells {
    int row;
    float s_x0, s_dx, t_x0, t_dx;
    float density;
  };
  // The density of the cell at st: the drawn one's where it lies in `drawn`, else by searching.
  template <class Key, class Node>
  float pdfImpl(std::size_t bin, glm::vec2 st, const DrawnCells* drawn = nullptr) const;
  // pdfQuery, passing `drawn` to pdfImpl (sample() after a draw, for its round trip through wi).
  float pdfQueryNear(const BinQuery& q, const glm::vec3& wi, const DrawnCells* drawn) const;
  // Calls f(Key{}, Node{}) with the key and node types of the tables.
  template <class F>
  decltype(auto) withTableTypes(F&& f) const {
    if (narrow_)
      return byte_nodes_ ? f(std::uint16_t{}, std::uint8_t{}) : f(std::uint16_t{}, std::uint16_t{});
    return byte_nodes_ ? f(float{}, std::uint8_t{}) : f(float{}, std::uint16_t{});
  }
  template <class Key>
  const Key* keys() const {
    if constexpr (std::is_same_v<Key, std::uint16_t>)
      return cdf16_.data();
    else
      return cdf32_.data();
  }
  template <class Node>
  const Node* nodes() const {
    if constexpr (std::is_same_v<Node, std::uint8_t>)
      return nodes8_.data();
    else
      return nodes16_.data();
  }

  int nu_, nv_;
  bool narrow_;
  bool byte_nodes_;  // node indices in 8 bits (grid <= 256 cells per side)
  int search_steps_ = 0;  // bisection steps of every search (countLe), from the longest CDF
  int full_search_steps_ = 0;  // bisection steps down to one entry (the vector path's searches)
  float pdf_scale_;  // nu nv / (top^2 2 pi): pdf = (dq_s / dx_s) (dq_t / dx_t) pdf_scale_
  // Interior vertices of all CDFs, bin-major (marginal, then rows 0..nu-1), one leading and 32
  // trailing padding entries so that the searches may read a little outside a CDF.
  std::vector<std::uint16_t> cdf16_;  // narrow: CDF value * 65535
  std::vector<float> cdf32_;          // wide: CDF value
  std::vector<std::uint16_t> nodes16_;  // grid node index of each vertex (1..n-1), unless byte_nodes_
  std::vector<std::uint8_t> nodes8_;    // the same in 8 bits when byte_nodes_
  std::vector<std::uint32_t> starts_;  // per CDF, its first vertex; one more at the end
  std::size_t vertex_count_ = 0;       // including the implicit end points
  std::vector<unsigned char> empty_;
  double max_deviation_ = 0;
};

}  // namespace btf
