// Piecewise-constant 1D distributions on a regular grid over [0,1], built into storage the caller
// provides (a std::array on the stack, a slice of a flat table), so that sampling a small function
// built on the fly (a BTF's texel or view weights) allocates nothing.
//
// A function of n values f[0..n) is read as constant on each cell [k/n, (k+1)/n). Its CDF has n+1
// entries, cdf[0] = 0 and cdf[n] = 1; sampling inverts it by binary search, and the density at x
// is n * (cdf[k+1] - cdf[k]) for the cell k holding x. A function with no mass (all zero, or
// nothing positive and finite) gets the uniform CDF, so nothing divides by zero; callers that must
// not sample such a function check the integral that buildCdf1D returns.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

namespace btf {

// Writes the CDF of f (n values) into cdf (n + 1 entries) and returns the integral of f over
// [0,1] (the mean of f). Negative or non-finite values count as 0. Throws btf::Error if the sizes
// disagree or f is empty.
double buildCdf1D(std::span<const float> f, std::span<float> cdf);

struct Cdf1DSample {
  float x;         // in [0, 1)
  float pdf;       // density with respect to x on [0, 1]
  std::size_t cell;  // the cell holding x
  float remapped;  // u's position inside the chosen cell, uniform in [0,1) again (reusable)
};

// Continuous sample for u in [0,1): binary search for the cell, then a uniform point in it.
Cdf1DSample sampleCdf1D(std::span<const float> cdf, float u);
// Density at x in [0,1] of what sampleCdf1D draws (0 outside [0,1]).
float pdfCdf1D(std::span<const float> cdf, float x);

// Discrete sample: the cell index alone, with probability cdf[k+1] - cdf[k] (for choosing one of
// a few texels, views or lobes), and that probability.
struct DiscreteSample {
  std::size_t index;
  float probability;
  float remapped;  // as in Cdf1DSample
};
DiscreteSample sampleDiscrete(std::span<const float> cdf, float u);
// sampleCdf1D once the cell k (sampleDiscrete's index for u) is known, e.g. from guidedSearch.
Cdf1DSample sampleCdf1DInCell(std::span<const float> cdf, std::size_t k, float u);

// Guide tables (the cutpoint method of Chen and Asau 1974): for a non-decreasing sequence
// key(0..last+1) over [0, 1] and a power-of-two number of cells, guide[g] is the search result
// for u = g / cells (exact in float). It is a lower bound of the result for every u in the cell,
// so a search starts there and steps forward over the few keys left in the cell: with one cell
// per one or two keys the scan is one or two steps (taken without branches), against log2(n)
// unpredictable branches of a bisection. The result is the same index std::upper_bound gives, for every u in [0, 1].
//
// Result: the largest k in [0, last] with key(1..k) <= u (the segment or cell holding u).
// guide(g) returns entry g (an accessor, so that tables can be packed as the caller likes).
template <class Key, class Guide>
inline std::size_t guidedSearch(const Key& key, std::size_t last, const Guide& guide, std::size_t cells, float u) {
  const float scaled = u * float(cells);
  std::size_t k = guide(scaled > 0.0f ? std::min(static_cast<std::size_t>(scaled), cells - 1) : 0);
  // Two steps without branches (key(k + 1) exists for k <= last; the flags are added, so nothing
  // is mispredicted), then a loop that rarely runs: a cell seldom holds more than two keys.
  k += std::size_t((key(k + 1) <= u) & (k < last));
  k += std::size_t((key(k + 1) <= u) & (k < last));
  while (k < last && key(k + 1) <= u) ++k;
  return k;
}
// Cells for a sequence of `segments` searchable intervals: the power of two >= segments, at most
// 2^16 (so that every guide entry, a segment index < 2^16 under that cap, fits in 16 bits).
std::size_t guideCellsFor(std::size_t segments);
// Fills guide (a power-of-two size) for key(0..last+1). Throws btf::Error if last >= 2^16.
template <class Key>
void buildGuide(const Key& key, std::size_t last, std::span<std::uint16_t> guide);
// The guide of a CDF as buildCdf1D writes it (n + 1 entries, cells = n).
void buildCdfGuide(std::span<const float> cdf, std::span<std::uint16_t> guide);

void throwGuideTooLong(std::size_t last);

template <class Key>
void buildGuide(const Key& key, std::size_t last, std::span<std::uint16_t> guide) {
  if (last >= (std::size_t(1) << 16)) throwGuideTooLong(last);
  std::size_t k = 0;
  for (std::size_t g = 0; g < guide.size(); ++g) {
    const float u = float(g) / float(guide.size());
    while (k < last && key(k + 1) <= u) ++k;
    guide[g] = static_cast<std::uint16_t>(k);
  }
}

}  // namespace btf
