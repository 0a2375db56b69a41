#include "btf/material/albedo.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"

namespace btf {

namespace {

// Fixed work unit of estimateAlbedo: its size, not the thread count, decides the RNG streams.
constexpr std::uint32_t kAlbedoChunk = 4096;

struct ChannelSums {
  std::array<double, 3> sum{}, sum_sq{};
};

}  // namespace

AlbedoEstimate estimateAlbedo(const Material& m, const glm::vec3& wo, std::uint32_t sample_count,
                              std::uint64_t seed) {
  if (sample_count < 2) throw Error("estimateAlbedo: sample_count must be >= 2, got " + std::to_string(sample_count));
  const std::uint32_t chunks = (sample_count + kAlbedoChunk - 1) / kAlbedoChunk;
  std::vector<ChannelSums> partial(chunks);
  tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t chunk) {
    Rng rng(seed, chunk);
    const std::uint32_t begin = chunk * kAlbedoChunk;
    const std::uint32_t end = std::min(sample_count, begin + kAlbedoChunk);
    ChannelSums& sums = partial[chunk];
    for (std::uint32_t i = begin; i < end; ++i) {
      const auto s = m.sample(wo, {}, rng.uniform2D());
      if (!s) continue;
      for (int c = 0; c < 3; ++c) {
        const double w = s->weight[c];
        sums.sum[c] += w;
        sums.sum_sq[c] += w * w;
      }
    }
  });
  ChannelSums total;
  for (const ChannelSums& p : partial)
    for (int c = 0; c < 3; ++c) {
      total.sum[c] += p.sum[c];
      total.sum_sq[c] += p.sum_sq[c];
    }
  AlbedoEstimate result;
  const double n = sample_count;
  for (int c = 0; c < 3; ++c) {
    const double mean = total.sum[c] / n;
    const double variance = std::max(0.0, (total.sum_sq[c] / n - mean * mean) * n / (n - 1.0));
    result.value[c] = static_cast<float>(mean);
    result.standard_error[c] = static_cast<float>(std::sqrt(variance / n));
  }
  return result;
}

Rgb integrateAlbedoHalfVector(const Material& m, float theta_o, int theta_h_steps, int phi_h_steps) {
  if (m.isAnisotropic())
    throw Error("integrateAlbedoHalfVector: " + m.name() + " is anisotropic; the quadrature assumes phi_o = 0 "
                "represents every azimuth");
  if (!(theta_o >= 0.0f && theta_o < kHalfPi))
    throw Error("integrateAlbedoHalfVector: theta_o must be in [0, pi/2), got " + std::to_string(theta_o));
  if (theta_h_steps < 1 || phi_h_steps < 1)
    throw Error("integrateAlbedoHalfVector: step counts must be positive, got " + std::to_string(theta_h_steps) +
                " x " + std::to_string(phi_h_steps));

  const glm::vec3 wo = sphericalDirection(theta_o, 0.0f);
  const double dt = 1.0 / theta_h_steps;
  const double dphi = 2.0 * std::numbers::pi / phi_h_steps;
  std::vector<glm::vec2> azimuth(phi_h_steps);  // (cos, sin) of the midpoint of each phi step
  for (int j = 0; j < phi_h_steps; ++j) {
    const double phi = (j + 0.5) * dphi;
    azimuth[j] = {static_cast<float>(std::cos(phi)), static_cast<float>(std::sin(phi))};
  }
  std::array<double, 3> sum{};
  for (int i = 0; i < theta_h_steps; ++i) {
    // Midpoint in t; theta_h = pi/2 t^2, so dtheta_h = pi t dt.
    const double t = (i + 0.5) * dt;
    const double theta_h = 0.5 * std::numbers::pi * t * t;
    const double sin_h = std::sin(theta_h), cos_h = std::cos(theta_h);
    const double ring_weight = sin_h * std::numbers::pi * t * dt * dphi;
    for (const glm::vec2& cs : azimuth) {
      const glm::vec3 h{static_cast<float>(sin_h) * cs.x, static_cast<float>(sin_h) * cs.y, static_cast<float>(cos_h)};
      const float wo_dot_h = glm::dot(wo, h);
      if (wo_dot_h <= 0.0f) continue;
      const glm::vec3 wi = reflect(wo, h);
      if (wi.z <= 0.0f) continue;
      const Rgb f = m.eval(wi, wo);
      const double w = ring_weight * 4.0 * wo_dot_h * wi.z;
      for (int c = 0; c < 3; ++c) sum[c] += f[c] * w;
    }
  }
  return {static_cast<float>(sum[0]), static_cast<float>(sum[1]), static_cast<float>(sum[2])};
}

}  // namespace btf
