#include "btf/core/dp_cdf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "btf/core/error.h"

namespace btf {
namespace {

double nodeX(std::size_t k, std::size_t n) { return double(k) / double(n); }

// Vertical distance of node k from the chord between nodes a and b.
double chordDistance(std::span<const float> cdf, std::size_t a, std::size_t b, std::size_t k) {
  const double t = double(k - a) / double(b - a);
  return std::abs(double(cdf[k]) - ((1.0 - t) * cdf[a] + t * cdf[b]));
}

void douglasPeucker(std::span<const float> cdf, double epsilon, std::vector<std::size_t>& kept) {
  // An explicit stack: recursion depth could reach n on adversarial data.
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, cdf.size() - 1}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = -1.0;
    std::size_t worst_k = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d = chordDistance(cdf, a, b, k);
      if (d > worst) worst = d, worst_k = k;
    }
    if (worst > epsilon) {
      kept.push_back(worst_k);
      stack.push_back({a, worst_k});
      stack.push_back({worst_k, b});
    }
  }
}

void fewestVertices(std::span<const float> cdf, double epsilon, std::vector<std::size_t>& kept) {
  const std::size_t last = cdf.size() - 1;
  constexpr std::size_t kUnreached = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> hops(last + 1, kUnreached), previous(last + 1, 0);
  hops[0] = 0;
  // Nodes in order: every shortcut goes forward, so hops[i] is final when i is reached.
  for (std::size_t i = 0; i < last; ++i) {
    if (hops[i] == kUnreached) continue;
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (std::size_t j = i + 1; j <= last; ++j) {
      const double dx = nodeX(j, last) - nodeX(i, last);
      const double rise = double(cdf[j]) - double(cdf[i]);
      // Chord i -> j passes within epsilon of every node strictly between (cone [lo, hi]), with
      // a relative slack so that rounding of the slopes does not forbid exact-tolerance chords.
      const double slope = rise / dx, slack = 1e-12 * (1.0 + std::abs(slope));
      if (slope >= lo - slack && slope <= hi + slack && hops[i] + 1 < hops[j]) {
        hops[j] = hops[i] + 1;
        previous[j] = i;
      }
      lo = std::max(lo, (rise - epsilon) / dx);
      hi = std::min(hi, (rise + epsilon) / dx);
      if (lo > hi + 1e-12 * (1.0 + std::abs(hi))) break;  // no chord from i can pass node j
    }
  }
  for (std::size_t k = previous[last]; k != 0; k = previous[k]) kept.push_back(k);
}

}  // namespace

std::size_t reduceCdf(std::span<const float> cdf, float epsilon, CdfReduction method, std::vector<CdfVertex>& out) {
  if (cdf.size() < 2) throw Error("reduceCdf: a CDF needs at least 2 entries");
  if (!(epsilon >= 0.0f)) throw Error("reduceCdf: epsilon must be >= 0, got " + std::to_string(epsilon));
  const std::size_t n = cdf.size() - 1;
  std::vector<std::size_t> kept{0, n};
  if (method == CdfReduction::DouglasPeucker)
    douglasPeucker(cdf, epsilon, kept);
  else
    fewestVertices(cdf, epsilon, kept);
  std::sort(kept.begin(), kept.end());
  for (std::size_t k : kept) out.push_back({float(nodeX(k, n)), cdf[k]});
  out[out.size() - kept.size()].cdf = 0.0f;
  out.back().cdf = 1.0f;
  return kept.size();
}

double cdfDeviation(std::span<const float> cdf, std::span<const CdfVertex> vertices) {
  const std::size_t n = cdf.size() - 1;
  double worst = 0.0;
  std::size_t seg = 0;
  for (std::size_t k = 0; k <= n; ++k) {
    const double x = nodeX(k, n);
    while (seg + 2 < vertices.size() && x > vertices[seg + 1].x) ++seg;
    const CdfVertex& a = vertices[seg];
    const CdfVertex& b = vertices[seg + 1];
    const double t = std::clamp((x - a.x) / (double(b.x) - a.x), 0.0, 1.0);
    worst = std::max(worst, std::abs(double(cdf[k]) - ((1.0 - t) * a.cdf + t * b.cdf)));
  }
  return worst;
}

VertexCdfSample sampleVertexCdf(std::span<const CdfVertex> v, float u) {
  // The segment k with v[k].cdf <= u < v[k+1].cdf; flat segments (no mass) are never chosen.
  const auto it = std::upper_bound(v.begin() + 1, v.end() - 1, u,
                                   [](float value, const CdfVertex& vertex) { return value < vertex.cdf; });
  const std::size_t k = static_cast<std::size_t>(it - v.begin()) - 1;
  return invertVertexSegment(v[k], v[k + 1], k, u);
}

float pdfVertexCdf(std::span<const CdfVertex> v, float x) {
  if (!(x >= v.front().x && x <= v.back().x)) return 0.0f;
  const auto it = std::upper_bound(v.begin() + 1, v.end() - 1, x,
                                   [](float value, const CdfVertex& vertex) { return value < vertex.x; });
  const std::size_t k = static_cast<std::size_t>(it - v.begin()) - 1;
  return (v[k + 1].cdf - v[k].cdf) / (v[k + 1].x - v[k].x);
}

}  // namespace btf
