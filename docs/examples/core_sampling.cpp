// The sampling primitives of the core layer: hemisphere warps with their densities, a
// piecewise-constant 1D distribution built into caller storage, and a Douglas-Peucker reduction
// of its CDF (the building blocks of the tabulated samplers). Exit code 0 on success.
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include <btf/core/cdf1d.h>
#include <btf/core/dp_cdf.h>
#include <btf/core/rng.h>
#include <btf/core/warp.h>

int main() {
  btf::Rng rng(1);  // counter-based: the same numbers on any thread count

  // Cosine-weighted hemisphere: the estimate of the integral of cos(theta) over the hemisphere
  // (pi) is exact sample by sample, since the weight cos / pdf is constant.
  double integral = 0;
  const int n = 1000;
  for (int k = 0; k < n; ++k) {
    const glm::vec3 w = btf::squareToCosineHemisphere(rng.uniform2D());
    integral += w.z / btf::cosineHemispherePdf(w);
  }
  std::printf("cosine warp: integral of cos = %.6f (pi = %.6f)\n", integral / n, std::acos(-1.0));

  // A 1D distribution over [0, 1): 64 cells of f, its CDF written into a stack array.
  std::array<float, 64> f{};
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = std::exp(-0.5f * std::pow((float(i) - 20.0f) / 4.0f, 2.0f));
  std::array<float, 65> cdf{};
  const double mean = btf::buildCdf1D(f, cdf);
  const btf::Cdf1DSample s = btf::sampleCdf1D(cdf, 0.5f);  // the median
  std::printf("1D CDF: mean of f %.4f, median at x = %.4f (cell %zu), pdf there %.3f\n", mean, s.x, s.cell, s.pdf);
  if (s.pdf != btf::pdfCdf1D(cdf, s.x)) return 1;  // a draw reports the density pdfCdf1D gives

  // The fewest CDF vertices within epsilon of the full CDF (what the DP-CDF sampler stores).
  std::vector<btf::CdfVertex> vertices;
  btf::reduceCdf(cdf, 1e-3f, btf::CdfReduction::Fewest, vertices);
  std::printf("reduced CDF: %zu of %zu vertices, largest deviation %.2e\n", vertices.size(), cdf.size(),
              btf::cdfDeviation(cdf, vertices));
  const btf::VertexCdfSample v = btf::sampleVertexCdf(vertices, 0.5f);
  std::printf("median of the reduced CDF at x = %.4f, pdf %.3f\n", v.x, v.pdf);
  return btf::cdfDeviation(cdf, vertices) <= 1.01e-3 ? 0 : 1;
}
