#include "btf/sampling/tabulated_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <span>

#include "btf/core/math.h"
#include "btf/core/cdf1d.h"

namespace btf {

TabulatedSampler::TabulatedSampler(std::shared_ptr<const Material> material, const SamplerOptions& options)
    : BinnedSampler(std::move(material), options), nu_(gridRows()), nv_(gridColumns()) {
  bin_stride_ = std::size_t(nu_ + 1) + std::size_t(nu_) * (nv_ + 1);
  const std::vector<float> grid = tabulateGrid(nu_, nv_);
  cdfs_.resize(binCount() * bin_stride_);
  empty_.assign(binCount(), 0);
  // Half a guide cell per CDF cell, as in DpCdfSampler: guidedSearch's two branch-free steps
  // cover the usual two keys per cell, for half the guide memory.
  row_cells_ = guideCellsFor((std::size_t(nu_) + 1) / 2);
  col_cells_ = guideCellsFor((std::size_t(nv_) + 1) / 2);
  guide_stride_ = row_cells_ + std::size_t(nu_) * col_cells_;
  guides_.resize(binCount() * guide_stride_);
  tbb::parallel_for(std::size_t(0), binCount(), [&](std::size_t bin) {
    std::span<float> all(cdfs_.data() + bin * bin_stride_, bin_stride_);
    std::vector<float> row_integrals(nu_);
    for (int i = 0; i < nu_; ++i)
      row_integrals[i] = float(buildCdf1D(std::span(grid).subspan((bin * nu_ + i) * nv_, nv_),
                                          all.subspan(nu_ + 1 + std::size_t(i) * (nv_ + 1), nv_ + 1)));
    if (buildCdf1D(row_integrals, all.first(nu_ + 1)) == 0.0) empty_[bin] = 1;
    std::span<std::uint16_t> guides(guides_.data() + bin * guide_stride_, guide_stride_);
    buildCdfGuide(all.first(nu_ + 1), guides.first(row_cells_));
    for (int i = 0; i < nu_; ++i)
      buildCdfGuide(all.subspan(nu_ + 1 + std::size_t(i) * (nv_ + 1), nv_ + 1),
                    guides.subspan(row_cells_ + std::size_t(i) * col_cells_, col_cells_));
  });
  reportInvalidEvaluations();
}

std::optional<glm::vec2> TabulatedSampler::sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const {
  if (empty_[bin]) return std::nullopt;
  tries = 1;
  const float* base = cdfs_.data() + bin * bin_stride_;
  const Cdf1DSample row = sampleCdf1D(std::span(base, nu_ + 1), u.x);
  const Cdf1DSample col = sampleCdf1D(std::span(base + nu_ + 1 + row.cell * (nv_ + 1), nv_ + 1), u.y);
  return glm::vec2{row.x, col.x};
}

std::optional<BinnedSampler::DirectionSample> TabulatedSampler::sampleQuery(const BinQuery& q, glm::vec2 u,
                                                                            int& tries) const {
  if (empty_[q.bin]) return std::nullopt;
  tries = 1;
  const float* base = cdfs_.data() + q.bin * bin_stride_;
  const std::uint16_t* guides = guides_.data() + q.bin * guide_stride_;
  const std::span<const float> marginal(base, nu_ + 1);
  const std::size_t i = guidedSearch([base](std::size_t k) { return base[k]; }, std::size_t(nu_ - 1),
                                     [guides](std::size_t g) { return guides[g]; }, row_cells_, u.x);
  const Cdf1DSample row = sampleCdf1DInCell(marginal, i, u.x);
  const float* cond = base + nu_ + 1 + row.cell * (nv_ + 1);
  const std::uint16_t* col_guide = guides + row_cells_ + row.cell * col_cells_;
  const std::size_t j = guidedSearch([cond](std::size_t k) { return cond[k]; }, std::size_t(nv_ - 1),
                                     [col_guide](std::size_t g) { return col_guide[g]; }, col_cells_, u.y);
  const Cdf1DSample col = sampleCdf1DInCell(std::span(cond, nv_ + 1), j, u.y);
  // pdf of the final float direction, as pdf() computes it (its cell is computed, not searched,
  // so there is nothing to gain from remembering (i, j)).
  const std::optional<glm::vec3> wi_bin = squareToIncoming({row.x, col.x}, q.wo);
  if (!wi_bin) return std::nullopt;  // a half vector whose reflection is below the horizon
  const glm::vec3 wi = glm::normalize(q.fromBinFrame(*wi_bin));
  const float p = pdfQuery(q, wi);
  if (!(p > 0.0f)) return std::nullopt;  // only on a boundary of a zero-density cell
  return DirectionSample{wi, p};
}

float TabulatedSampler::pdfQuery(const BinQuery& q, const glm::vec3& wi) const {
  // BinnedSampler::pdfQuery without the virtual call to pdfInBin.
  if (!(wi.z > 0.0f)) return 0.0f;
  const std::optional<SquarePoint> p = incomingToSquare(q.toBinFrame(wi), q.wo);
  if (!p) return 0.0f;
  return TabulatedSampler::pdfInBin(q.bin, p->st) * p->to_solid_angle;
}

float TabulatedSampler::pdfInBin(std::size_t bin, glm::vec2 st) const {
  if (empty_[bin]) return 0.0f;
  const float* base = cdfs_.data() + bin * bin_stride_;
  const std::size_t i = std::min(std::size_t(st.x * float(nu_)), std::size_t(nu_ - 1));
  const std::size_t j = std::min(std::size_t(st.y * float(nv_)), std::size_t(nv_ - 1));
  const float* row = base + nu_ + 1 + i * (nv_ + 1);
  return (base[i + 1] - base[i]) * float(nu_) * (row[j + 1] - row[j]) * float(nv_);
}

SamplerStats TabulatedSampler::stats() const {
  SamplerStats s;
  fillCommonStats(s);
  s.bytes = cdfs_.size() * sizeof(float) + guides_.size() * sizeof(std::uint16_t) + empty_.size();
  s.elements = cdfs_.size();
  s.empty_bins = std::size_t(std::count(empty_.begin(), empty_.end(), 1));
  return s;
}

}  // namespace btf
