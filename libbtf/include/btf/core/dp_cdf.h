// Compressed 1D CDFs (Lawrence, Rusinkiewicz and Ramamoorthi 2005, "Adaptive Numerical Cumulative
// Distribution Functions for Efficient Importance Sampling"): the CDF of a piecewise-constant
// function on a regular grid is a polyline through n + 1 nodes; keeping only some nodes gives a
// coarser polyline, which is itself the exact CDF of a piecewise-constant density (constant between
// kept vertices). Sampling and pdf use that coarser density, so an estimator stays unbiased at any
// tolerance; the tolerance only trades memory for how closely the density follows the function.
//
// Tolerance: the largest vertical distance |F(x_k) - G(x_k)| over the grid nodes between the full
// CDF F and the simplified G. Both are linear between nodes, so the distance at nodes is the
// distance everywhere. Two reductions are offered:
// - DouglasPeucker: recursive splitting at the node farthest from the chord (what Lawrence et al.
//   used); fast, but not always the fewest vertices.
// - Fewest: the minimum number of vertices within the tolerance, by a shortest path over the nodes
//   where a shortcut i -> j is allowed when the chord's slope lies within the "cone" of slopes
//   that pass within epsilon of every node in between (O(n^2) at worst, O(n * span) in practice).
// Both always keep the first and last node; epsilon = 0 keeps every node off its neighbours'
// chord (collinear runs, i.e. constant stretches of the function, still collapse).
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace btf {

struct CdfVertex {
  float x;    // position in [0, 1]
  float cdf;  // CDF value at x; non-decreasing, 0 at the first vertex and 1 at the last
};

enum class CdfReduction { DouglasPeucker, Fewest };

// cdf: n + 1 values at x_k = k / n (as buildCdf1D writes them), n >= 1. Appends the kept vertices
// to out and returns how many. Throws btf::Error for epsilon < 0 or NaN, or fewer than 2 entries.
std::size_t reduceCdf(std::span<const float> cdf, float epsilon, CdfReduction method, std::vector<CdfVertex>& out);

// Largest |F(x_k) - G(x_k)| over the grid nodes (the reduction's error, for tests and reports).
double cdfDeviation(std::span<const float> cdf, std::span<const CdfVertex> vertices);

struct VertexCdfSample {
  float x;       // in [vertices.front().x, vertices.back().x)
  float pdf;     // density of x
  std::size_t segment;
};
// Binary search for the segment whose CDF range holds u in [0,1), then inversion of its linear
// piece. vertices.size() >= 2 and the last vertex's cdf is 1.
VertexCdfSample sampleVertexCdf(std::span<const CdfVertex> vertices, float u);
// The inversion step of sampleVertexCdf for a known segment k (its search result for u) from
// vertex a = v[k] to b = v[k + 1]; inline
// so that samplers with their own (guided) search share the arithmetic.
inline VertexCdfSample invertVertexSegment(CdfVertex a, CdfVertex b, std::size_t k, float u) {
  const float mass = b.cdf - a.cdf, width = b.x - a.x;
  const float t = mass > 0.0f ? std::clamp((u - a.cdf) / mass, 0.0f, 1.0f) : 0.0f;
  // Stay below b.x, so that pdfVertexCdf (which gives x == b.x to the next segment) agrees. b.x is
  // positive and finite (it exceeds a.x >= 0), so the float just below it is its bit pattern - 1:
  // std::nextafter without the library call.
  const float below_b = std::bit_cast<float>(std::bit_cast<std::uint32_t>(b.x) - 1u);
  const float x = std::min(a.x + t * width, below_b);
  return {std::max(x, a.x), mass / width, k};
}
// Density at x of what sampleVertexCdf draws: the slope of the segment holding x (binary search on
// x), 0 outside [first x, last x].
float pdfVertexCdf(std::span<const CdfVertex> vertices, float x);

}  // namespace btf
