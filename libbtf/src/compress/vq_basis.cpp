#include "vq_basis.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>

#include "btf/core/btf_ring_layout.h"
#include "vq_impl.h"

namespace btf {

std::vector<VqRingBasis> learnVqRingBases(const std::vector<Rgb>& view, std::size_t texels, const BtfRingLayout& layout,
                                          float step) {
  std::vector<VqRingBasis> bases(std::size_t(layout.ringCount()));
  for (int r = 0; r < layout.ringCount(); ++r) {
    const int n = layout.size(r);
    if (n == 1) continue;
    Eigen::MatrixXd moments = Eigen::MatrixXd::Zero(n, n);
    std::vector<double> u(static_cast<std::size_t>(n));
    std::size_t lit = 0;
    for (std::size_t t = 0; t < texels; ++t) {
      double len2 = 0;
      for (int a = 0; a < n; ++a) {
        u[std::size_t(a)] = view[std::size_t(layout.light(r, a)) * texels + t].luminance();
        len2 += u[std::size_t(a)] * u[std::size_t(a)];
      }
      if (!(len2 > 0)) continue;
      ++lit;
      const double inv = 1.0 / std::sqrt(len2);
      for (int a = 0; a < n; ++a)
        for (int b = 0; b <= a; ++b) moments(a, b) += u[std::size_t(a)] * u[std::size_t(b)] * inv * inv;
    }
    if (lit < std::size_t(kVqBasisVectorsPerValue) * std::size_t(n) * std::size_t(n)) continue;
    // Eigen's solver reads the lower triangle; its eigenvalues come in ascending order.
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(moments);
    if (solver.info() != Eigen::Success) continue;
    VqRingBasis& basis = bases[std::size_t(r)];
    basis.n = n;
    basis.step = step;
    basis.v.resize(std::size_t(n) * std::size_t(n));
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd column = solver.eigenvectors().col(n - 1 - j);
      // A fixed sign per direction (the solver's is arbitrary): the one with a non-negative sum.
      const double sign = column.sum() < 0 ? -1.0 : 1.0;
      for (int a = 0; a < n; ++a) basis.v[std::size_t(a) * std::size_t(n) + std::size_t(j)] = float(sign * column[a]);
    }
  }
  return bases;
}

void vqBasisCoefficients(const VqRingBasis& basis, std::span<const float> u, double budget, std::int32_t* coefficients) {
  const int n = basis.n;
  std::array<double, BtfRingLayout::kBandSize> c{};  // n <= the largest ring
  for (int a = 0; a < n; ++a)
    for (int j = 0; j < n; ++j)
      c[std::size_t(j)] += double(basis.v[std::size_t(a) * std::size_t(n) + std::size_t(j)]) * double(u[std::size_t(a)]);
  int kept = n;
  double tail = 0;
  while (kept > 1 && tail + c[std::size_t(kept - 1)] * c[std::size_t(kept - 1)] <= budget * budget) {
    tail += c[std::size_t(kept - 1)] * c[std::size_t(kept - 1)];
    --kept;
  }
  for (int j = 0; j < n; ++j)
    coefficients[j] = j < kept ? std::int32_t(std::lround(c[std::size_t(j)] / double(basis.step))) : 0;
}

void vqBasisCodes(const VqRingBasis& basis, const std::int32_t* coefficients, std::uint16_t* codes) {
  const int n = basis.n;
  for (int a = 0; a < n; ++a) {
    double value = 0;
    for (int j = 0; j < n; ++j)
      value += double(basis.v[std::size_t(a) * std::size_t(n) + std::size_t(j)]) * (double(coefficients[j]) * double(basis.step));
    codes[a] = encodeVqEntryValue(float(value));
  }
}

}  // namespace btf
