// Chi-square goodness-of-fit test of a direction sampler against the density it claims, in the
// manner of nori's warptest and Mitsuba's chi2 tests. The sphere is cut into theta_bins x phi_bins
// equal-area cells (uniform in cos theta and phi); N draws are histogrammed and compared with the
// pdf integrated over each cell by adaptive Gauss-Legendre quadrature, which also follows the jumps
// of piecewise-constant pdfs (tabulated samplers) along lines of constant theta or phi by bisection,
// so such cells come out exact to about 1e-6 of their count (see chi2.cpp). Cells expecting fewer than
// min_expected draws are pooled into one (with the next-smallest cells added until the pool
// reaches min_expected). One more term compares the draws that returned nothing with
// N (1 - int pdf), allowing the integral a relative error of 1e-4 (the float precision of very
// sharp lobes), so a pdf that does not integrate to the probability of a sample is caught too.
//
// A drawn direction that is not a finite unit vector, or at which pdf is not > 0, fails the test at
// once with a message naming the sample. Keep theta_bins even so that the horizon, where
// hemispherical pdfs jump, is a cell boundary. The sampler and pdf are called from several threads
// at once; the result does not depend on how many (fixed chunks with their own RNG streams).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "btf/material/material.h"

namespace btf {

struct Chi2Options {
  int theta_bins = 20;
  int phi_bins = 40;
  std::uint64_t sample_count = 1'000'000;
  double min_expected = 5.0;
  double significance = 0.01;
  std::uint64_t seed = 1;
};

struct Chi2Result {
  double statistic = 0;
  int degrees_of_freedom = 0;
  double p_value = 0;
  bool accepted = false;
  std::uint64_t sample_count = 0;
  std::uint64_t failed_samples = 0;  // draws that returned no direction
  int pooled_cells = 0;              // cells merged into the pooled cell
  int theta_bins = 0, phi_bins = 0;
  std::vector<double> observed, expected;  // per cell, row-major theta x phi (theta from +z down)
  std::string message;                     // one-line human summary
};

using DirectionSampler = std::function<std::optional<glm::vec3>(glm::vec2 u)>;
using DirectionPdf = std::function<double(const glm::vec3&)>;

// Throws btf::Error for invalid options (non-positive bins or counts, significance outside (0, 1)).
Chi2Result chi2Test(const DirectionSampler& sampler, const DirectionPdf& pdf, const Chi2Options& options = {});

// Tests material.sample(wo, uv, .) against material.pdf(., wo, uv).
Chi2Result chi2TestMaterial(const Material& material, const glm::vec3& wo, glm::vec2 uv = {},
                            const Chi2Options& options = {});

}  // namespace btf
