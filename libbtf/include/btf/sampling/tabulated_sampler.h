// The reference tabulated sampler: per outgoing bin, the piecewise-constant density of f cos over
// the (cos theta_i, phi_i) grid (binned_sampler.h), sampled by inversion of the full CDFs: a
// marginal CDF over rows (s = cos theta_i) and one conditional CDF per row over columns (phi_i).
// Both are searched through a guide table (cdf1d.h, guidedSearch: one 16-bit cell index per
// power-of-two cell of u, about one per two CDF entries), which gives the bisection's cell in
// about two branch-free steps. pdf = cell value / bin total, times the grid's cell count, over 2 pi: the cell of (s, t)
// is computed, no search. This is the baseline for memory (stats().bytes is full_cdf_bytes plus
// the guides and a byte per bin) and speed.
#pragma once

#include <vector>

#include "btf/sampling/binned_sampler.h"

namespace btf {

class TabulatedSampler final : public BinnedSampler {
 public:
  TabulatedSampler(std::shared_ptr<const Material> material, const SamplerOptions& options = {});

  SamplerKind kind() const override { return SamplerKind::Tabulated; }
  SamplerStats stats() const override;

 protected:
  std::optional<DirectionSample> sampleQuery(const BinQuery& q, glm::vec2 u, int& tries) const final;
  float pdfQuery(const BinQuery& q, const glm::vec3& wi) const final;
  std::optional<glm::vec2> sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const override;
  float pdfInBin(std::size_t bin, glm::vec2 st) const override;

 private:
  int nu_, nv_;
  std::size_t bin_stride_;   // floats per bin: (nu + 1) marginal + nu (nv + 1) conditional
  std::vector<float> cdfs_;  // all bins, each [marginal | conditional row 0 | row 1 | ...]
  std::vector<unsigned char> empty_;  // per bin: 1 if f cos vanished everywhere
  std::size_t row_cells_, col_cells_;  // guide cells of the marginal and of each conditional
  std::size_t guide_stride_;           // guide entries per bin: row_cells + nu col_cells
  std::vector<std::uint16_t> guides_;  // all bins, each [marginal | row 0 | row 1 | ...]
};

}  // namespace btf
