#include "btf/core/bilinear_warp2d.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "btf/core/error.h"

namespace btf {
namespace {

// The largest i in [0, n - 2] with below(i) true, or 0 if there is none; below must be true on a
// prefix of the indices (a monotone predicate), as it is for a CDF compared with a target.
template <typename Predicate>
int findInterval(int n, const Predicate& below) {
  int lo = 0, hi = n - 2;  // answer in [lo, hi]
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (below(mid)) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// The t in [0, 1] at which a density that is linear from d0 (t = 0) to d1 (t = 1) has integrated
// to `mass`: d0 t + (d1 - d0) t^2 / 2 = mass. This form of the quadratic's root has no
// cancellation and needs no special case for d0 == d1 (where it gives mass / d0).
float solveLinearCdf(float d0, float d1, float mass) {
  const float denom = d0 + std::sqrt(std::max(d0 * d0 + 2.0f * (d1 - d0) * mass, 0.0f));
  if (!(denom > 0.0f)) return 0.0f;
  return std::clamp(2.0f * mass / denom, 0.0f, 1.0f);
}

float lerp(float a, float b, float t) { return (1.0f - t) * a + t * b; }

// The cell of a width x height node grid that p falls in (its lower-left node) and p's position
// within it, for p in [0,1]^2; p = 1 lies in the last cell at t = 1. A NaN coordinate (a query
// direction too degenerate to normalize) reads cell 0 and gives a NaN position instead of
// converting NaN to int, which is undefined and read far outside the tables; the AVX2 lanes
// (bilinear_warp2d_lanes.h) do the same.
struct GridCell {
  int col, row;
  float tx, ty;
};
GridCell cellOf(glm::vec2 p, int width, int height) {
  const float x = p.x * (width - 1), y = p.y * (height - 1);
  const int col = x >= 0.0f ? std::min(static_cast<int>(x), width - 2) : 0;
  const int row = y >= 0.0f ? std::min(static_cast<int>(y), height - 2) : 0;
  return {col, row, x - col, y - row};
}

}  // namespace

BilinearWarp2D::BilinearWarp2D(int width, int height, std::span<const float> data,
                               std::vector<std::vector<float>> param_values, Mode mode)
    : width_(width), height_(height), mode_(mode), param_values_(std::move(param_values)) {
  if (width < 2 || height < 2) throw Error("bilinear warp: the grid needs at least 2 x 2 nodes");
  if (param_values_.size() > kMaxParams) throw Error("bilinear warp: more than 3 parameters");
  std::size_t slices = 1;
  for (int d = static_cast<int>(param_values_.size()) - 1; d >= 0; --d) {
    const auto& values = param_values_[d];
    if (values.empty()) throw Error("bilinear warp: a parameter has no values");
    for (std::size_t i = 1; i < values.size(); ++i)
      if (!(values[i] > values[i - 1]))
        throw Error("bilinear warp: parameter " + std::to_string(d) + " is not strictly increasing");
    param_strides_[d] = static_cast<std::uint32_t>(slices);
    slices *= values.size();
  }
  const std::size_t slice_size = static_cast<std::size_t>(width) * height;
  if (data.size() != slices * slice_size)
    throw Error("bilinear warp: expected " + std::to_string(slices * slice_size) + " values, got " +
                std::to_string(data.size()));
  for (std::size_t i = 0; i < data.size(); ++i)
    if (!std::isfinite(data[i])) throw Error("bilinear warp: value " + std::to_string(i) + " is not finite");
  values_.assign(data.begin(), data.end());
  if (mode == Mode::Distribution) {
    row_cdf_.resize(values_.size());
    marginal_cdf_.resize(slices * height);
    for (std::size_t s = 0; s < slices; ++s) buildDistribution(s);
  }
}

void BilinearWarp2D::buildDistribution(std::size_t slice) {
  const std::size_t slice_size = static_cast<std::size_t>(width_) * height_;
  float* values = values_.data() + slice * slice_size;
  float* row_cdf = row_cdf_.data() + slice * slice_size;
  float* marginal = marginal_cdf_.data() + slice * height_;
  const double dx = 1.0 / (width_ - 1), dy = 1.0 / (height_ - 1);
  for (std::size_t i = 0; i < slice_size; ++i)
    if (values[i] < 0.0f)
      throw Error("bilinear warp: slice " + std::to_string(slice) + " holds a negative density value");
  // Integrals of the bilinear function, in double so that 128 x 128 sums keep float precision.
  std::vector<double> row_integral(height_);
  for (int y = 0; y < height_; ++y) {
    double sum = 0.0;
    for (int x = 0; x + 1 < width_; ++x)
      sum += 0.5 * dx * (double(values[y * width_ + x]) + double(values[y * width_ + x + 1]));
    row_integral[y] = sum;
  }
  double total = 0.0;
  for (int y = 0; y + 1 < height_; ++y) total += 0.5 * dy * (row_integral[y] + row_integral[y + 1]);
  if (!(total > 0.0) || !std::isfinite(total))
    throw Error("bilinear warp: slice " + std::to_string(slice) + " has no mass (all values are 0)");
  const double norm = 1.0 / total;
  for (std::size_t i = 0; i < slice_size; ++i) values[i] = static_cast<float>(values[i] * norm);
  double cumulative = 0.0;
  for (int y = 0; y < height_; ++y) {
    double sum = 0.0;
    row_cdf[y * width_] = 0.0f;
    for (int x = 0; x + 1 < width_; ++x) {
      sum += 0.5 * dx * (double(values[y * width_ + x]) + double(values[y * width_ + x + 1]));
      row_cdf[y * width_ + x + 1] = static_cast<float>(sum);
    }
    if (y > 0) cumulative += 0.5 * dy * (row_integral[y - 1] + row_integral[y]) * norm;
    marginal[y] = static_cast<float>(cumulative);
  }
}

BilinearWarp2D::SliceBlend BilinearWarp2D::blendFor(std::span<const float> params) const {
  SliceBlend blend;
  blend.count = 1;
  blend.slice[0] = 0;
  blend.weight[0] = 1.0f;
  for (std::size_t d = 0; d < param_values_.size(); ++d) {
    const auto& values = param_values_[d];
    const int n = static_cast<int>(values.size());
    if (n == 1) continue;
    const float p = d < params.size() ? params[d] : values.front();
    const int i = findInterval(n, [&](int k) { return values[k] <= p; });
    const float t = std::clamp((p - values[i]) / (values[i + 1] - values[i]), 0.0f, 1.0f);
    // Each existing corner splits into its lower (weight 1 - t) and upper (weight t) neighbour;
    // corners of zero weight are dropped so that exact node values read a single slice.
    SliceBlend next;
    for (int k = 0; k < blend.count; ++k) {
      const std::uint32_t base = blend.slice[k] + static_cast<std::uint32_t>(i) * param_strides_[d];
      if (t < 1.0f) {
        next.slice[next.count] = base;
        next.weight[next.count++] = blend.weight[k] * (1.0f - t);
      }
      if (t > 0.0f) {
        next.slice[next.count] = base + param_strides_[d];
        next.weight[next.count++] = blend.weight[k] * t;
      }
    }
    blend = next;
  }
  return blend;
}

float BilinearWarp2D::blended(const std::vector<float>& values, std::size_t stride, std::size_t index,
                              const SliceBlend& blend) {
  float sum = 0.0f;
  for (int k = 0; k < blend.count; ++k) sum += blend.weight[k] * values[blend.slice[k] * stride + index];
  return sum;
}

BilinearWarp2D::Fixed BilinearWarp2D::fixed(std::span<const float> params) const { return {*this, blendFor(params)}; }

BilinearWarp2D::Fixed BilinearWarp2D::fixedLeading(std::span<const float> leading) const {
  if (param_values_.empty() || leading.size() + 1 != param_values_.size())
    throw Error("bilinear warp: evalAtEveryLastValue needs the leading parameters and one output per last value");
  // The blend at the last parameter's first value: that dimension then splits nothing (its weight
  // is exactly 1, as it is at any tabulated value), and value k is k slices of it further on.
  std::array<float, kMaxParams> params{};
  std::copy(leading.begin(), leading.end(), params.begin());
  params[leading.size()] = param_values_.back().front();
  return {*this, blendFor(std::span<const float>(params.data(), param_values_.size()))};
}

BilinearWarp2D::Point BilinearWarp2D::sample(glm::vec2 u, std::span<const float> params) const {
  return fixed(params).sample(u);
}
BilinearWarp2D::Point BilinearWarp2D::invert(glm::vec2 p, std::span<const float> params) const {
  return fixed(params).invert(p);
}
float BilinearWarp2D::eval(glm::vec2 p, std::span<const float> params) const { return fixed(params).eval(p); }
void BilinearWarp2D::evalAtEveryLastValue(glm::vec2 p, std::span<const float> leading, std::span<float> out) const {
  fixedLeading(leading).evalAtEveryLastValue(p, out);
}

BilinearWarp2D::Point BilinearWarp2D::Fixed::sample(glm::vec2 u) const {
  const BilinearWarp2D& w = *warp_;
  if (w.mode_ != Mode::Distribution) throw Error("bilinear warp: sample() needs a distribution");
  u = glm::clamp(u, 0.0f, 1.0f);
  const SliceBlend& blend = blend_;
  const int width = w.width_, height = w.height_;
  const std::size_t slice_size = static_cast<std::size_t>(width) * height;
  const float dx = 1.0f / (width - 1), dy = 1.0f / (height - 1);

  // Row: the marginal density in y is linear within a row of cells, from r0 to r1 (row integrals).
  const int row = findInterval(height, [&](int y) { return blended(w.marginal_cdf_, height, y, blend) < u.y; });
  const std::size_t row0 = static_cast<std::size_t>(row) * width, row1 = row0 + width;
  const float r0 = blended(w.row_cdf_, slice_size, row0 + width - 1, blend);
  const float r1 = blended(w.row_cdf_, slice_size, row1 + width - 1, blend);
  const float ty = solveLinearCdf(r0, r1, (u.y - blended(w.marginal_cdf_, height, row, blend)) / dy);

  // Column: the conditional CDF at this y blends the two rows' CDFs; its total is the marginal
  // density lerp(r0, r1, ty), so u.x scaled by it is the mass to reach.
  const float target = u.x * lerp(r0, r1, ty);
  auto cdf_at = [&](int x) {
    return lerp(blended(w.row_cdf_, slice_size, row0 + x, blend), blended(w.row_cdf_, slice_size, row1 + x, blend), ty);
  };
  const int col = findInterval(width, [&](int x) { return cdf_at(x) < target; });
  const float c0 = lerp(blended(w.values_, slice_size, row0 + col, blend), blended(w.values_, slice_size, row1 + col, blend), ty);
  const float c1 = lerp(blended(w.values_, slice_size, row0 + col + 1, blend),
                        blended(w.values_, slice_size, row1 + col + 1, blend), ty);
  const float tx = solveLinearCdf(c0, c1, (target - cdf_at(col)) / dx);

  return {{std::min((col + tx) * dx, 1.0f), std::min((row + ty) * dy, 1.0f)}, lerp(c0, c1, tx)};
}

BilinearWarp2D::Point BilinearWarp2D::Fixed::invert(glm::vec2 p) const {
  const BilinearWarp2D& w = *warp_;
  if (w.mode_ != Mode::Distribution) throw Error("bilinear warp: invert() needs a distribution");
  p = glm::clamp(p, 0.0f, 1.0f);
  const SliceBlend& blend = blend_;
  const int width = w.width_, height = w.height_;
  const std::size_t slice_size = static_cast<std::size_t>(width) * height;
  const float dx = 1.0f / (width - 1), dy = 1.0f / (height - 1);
  const auto [col, row, tx, ty] = cellOf(p, width, height);
  const std::size_t row0 = static_cast<std::size_t>(row) * width, row1 = row0 + width;

  const float c0 = lerp(blended(w.values_, slice_size, row0 + col, blend), blended(w.values_, slice_size, row1 + col, blend), ty);
  const float c1 = lerp(blended(w.values_, slice_size, row0 + col + 1, blend),
                        blended(w.values_, slice_size, row1 + col + 1, blend), ty);
  const float cdf_col = lerp(blended(w.row_cdf_, slice_size, row0 + col, blend),
                             blended(w.row_cdf_, slice_size, row1 + col, blend), ty);
  const float r0 = blended(w.row_cdf_, slice_size, row0 + width - 1, blend);
  const float r1 = blended(w.row_cdf_, slice_size, row1 + width - 1, blend);
  const float row_mass = lerp(r0, r1, ty);

  glm::vec2 u;
  const float mass_x = cdf_col + dx * tx * (c0 + 0.5f * (c1 - c0) * tx);
  u.x = row_mass > 0.0f ? std::min(mass_x / row_mass, 1.0f) : 0.0f;
  u.y = blended(w.marginal_cdf_, height, row, blend) + dy * ty * (r0 + 0.5f * (r1 - r0) * ty);
  return {glm::min(u, glm::vec2(1.0f)), lerp(c0, c1, tx)};
}

float BilinearWarp2D::Fixed::eval(glm::vec2 p) const {
  const BilinearWarp2D& w = *warp_;
  p = glm::clamp(p, 0.0f, 1.0f);
  const int width = w.width_, height = w.height_;
  const std::size_t slice_size = static_cast<std::size_t>(width) * height;
  const auto [col, row, tx, ty] = cellOf(p, width, height);
  const std::size_t i00 = static_cast<std::size_t>(row) * width + col, i01 = i00 + width;
  const float v0 = lerp(blended(w.values_, slice_size, i00, blend_), blended(w.values_, slice_size, i00 + 1, blend_), tx);
  const float v1 = lerp(blended(w.values_, slice_size, i01, blend_), blended(w.values_, slice_size, i01 + 1, blend_), tx);
  return lerp(v0, v1, ty);
}

void BilinearWarp2D::Fixed::evalAtEveryLastValue(glm::vec2 p, std::span<float> out) const {
  const BilinearWarp2D& w = *warp_;
  if (w.param_values_.empty() || out.size() != w.param_values_.back().size())
    throw Error("bilinear warp: evalAtEveryLastValue needs the leading parameters and one output per last value");
  p = glm::clamp(p, 0.0f, 1.0f);
  const int width = w.width_, height = w.height_;
  const std::size_t slice_size = static_cast<std::size_t>(width) * height;
  const auto [col, row, tx, ty] = cellOf(p, width, height);
  const std::size_t i00 = static_cast<std::size_t>(row) * width + col, i01 = i00 + width;
  const std::uint32_t last_stride = w.param_strides_[w.param_values_.size() - 1];
  for (std::size_t k = 0; k < out.size(); ++k) {
    SliceBlend blend = blend_;
    for (int j = 0; j < blend.count; ++j) blend.slice[j] += static_cast<std::uint32_t>(k) * last_stride;
    const float v0 = lerp(blended(w.values_, slice_size, i00, blend), blended(w.values_, slice_size, i00 + 1, blend), tx);
    const float v1 = lerp(blended(w.values_, slice_size, i01, blend), blended(w.values_, slice_size, i01 + 1, blend), tx);
    out[k] = lerp(v0, v1, ty);
  }
}

}  // namespace btf
