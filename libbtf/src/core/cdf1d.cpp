#include "btf/core/cdf1d.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "btf/core/error.h"

namespace btf {

double buildCdf1D(std::span<const float> f, std::span<float> cdf) {
  const std::size_t n = f.size();
  if (n == 0 || cdf.size() != n + 1)
    throw Error("buildCdf1D: need n >= 1 values and n + 1 CDF entries, got " + std::to_string(n) + " and " +
                std::to_string(cdf.size()));
  // Accumulate in double: float sums of thousands of cells lose the small ones entirely.
  double sum = 0.0;
  cdf[0] = 0.0f;
  for (std::size_t k = 0; k < n; ++k) {
    const float v = f[k];
    if (std::isfinite(v) && v > 0.0f) sum += v;
    cdf[k + 1] = static_cast<float>(sum);
  }
  if (!(sum > 0.0)) {
    for (std::size_t k = 0; k <= n; ++k) cdf[k] = static_cast<float>(double(k) / double(n));
    return 0.0;
  }
  const double inv = 1.0 / sum;
  double running = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const float v = f[k];
    if (std::isfinite(v) && v > 0.0f) running += v;
    cdf[k + 1] = static_cast<float>(running * inv);
  }
  cdf[n] = 1.0f;  // exact, whatever the rounding of the running sum
  return sum / double(n);
}

namespace {
// Index of the first of cdf[1 .. n-1] greater than u (n for none), as std::upper_bound gives it.
// Up to kLinearCells cells, counting the entries not greater than u is branch-free and several
// times faster than bisection on random u (the BTF sampler's rings have 1 to 24 cells); since the
// CDF is sorted, the count is that index, also for a NaN u (every comparison false: n).
constexpr std::size_t kLinearCells = 32;
std::size_t firstAbove(std::span<const float> cdf, float u) {
  const std::size_t n = cdf.size() - 1;
  if (n > kLinearCells) return static_cast<std::size_t>(std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u) - cdf.begin());
  std::size_t count = 1;
  for (std::size_t i = 1; i < n; ++i) count += !(u < cdf[i]);
  return count;
}

// Cell k's probability and u's place in it, in [0, 1) also for u outside the cell or NaN (0), so
// that a u outside [0, 1) cannot carry a point out of its cell.
DiscreteSample inCell(std::span<const float> cdf, std::size_t k, float u) {
  const std::size_t n = cdf.size() - 1;
  const float lo = cdf[k], width = cdf[k + 1] - lo;
  const float r = width > 0.0f ? (u - lo) / width : 0.0f;
  return {std::min(k, n - 1), width, r >= 0.0f ? std::min(r, 0x1.fffffep-1f) : 0.0f};
}
}  // namespace

DiscreteSample sampleDiscrete(std::span<const float> cdf, float u) {
  // First entry > u, minus one: the cell k with cdf[k] <= u < cdf[k+1]. Empty cells (equal
  // neighbours) are never chosen, since u < cdf[k+1] = cdf[k] <= u is impossible.
  return inCell(cdf, firstAbove(cdf, u) - 1, u);
}

namespace {
// The cell pdfCdf1D assigns to x; sampleCdf1D keeps its x where this agrees with its own cell.
std::size_t cellOf(float x, std::size_t n) { return std::min(static_cast<std::size_t>(x * float(n)), n - 1); }
}  // namespace

Cdf1DSample sampleCdf1D(std::span<const float> cdf, float u) {
  // The cell as in sampleDiscrete.
  return sampleCdf1DInCell(cdf, firstAbove(cdf, u) - 1, u);
}

Cdf1DSample sampleCdf1DInCell(std::span<const float> cdf, std::size_t k, float u) {
  const std::size_t n = cdf.size() - 1;
  const DiscreteSample d = inCell(cdf, k, u);
  float x = (float(d.index) + d.remapped) / float(n);
  // Rounding can put x on the neighbouring cell's side of a boundary; step back one ulp at a time
  // (at most a few steps) so that sample and pdf name the same cell.
  const float centre = (float(d.index) + 0.5f) / float(n);
  while (cellOf(x, n) != d.index) x = std::nextafter(x, centre);
  return {x, d.probability * float(n), d.index, d.remapped};
}

float pdfCdf1D(std::span<const float> cdf, float x) {
  const std::size_t n = cdf.size() - 1;
  if (!(x >= 0.0f && x <= 1.0f)) return 0.0f;
  const std::size_t k = cellOf(x, n);
  return (cdf[k + 1] - cdf[k]) * float(n);
}

std::size_t guideCellsFor(std::size_t segments) {
  return std::min(std::bit_ceil(std::max<std::size_t>(segments, 1)), std::size_t(1) << 16);
}

void buildCdfGuide(std::span<const float> cdf, std::span<std::uint16_t> guide) {
  buildGuide([&](std::size_t i) { return cdf[i]; }, cdf.size() - 2, guide);
}

void throwGuideTooLong(std::size_t last) {
  throw Error("guide table: " + std::to_string(last + 1) + " segments, at most 65536 are supported");
}

}  // namespace btf
