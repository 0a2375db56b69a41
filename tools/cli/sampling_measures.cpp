#include "sampling_measures.h"

#include <chrono>
#include <cmath>

#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "sampler_choice.h"

namespace btf::cli {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

float environmentRadiance(const glm::vec3& w) {
  // The sun sits off the plane of the usual wo (phi = 0) so that no sampler is favoured by its lobe
  // and the sun lining up with the specular peak.
  static const glm::vec3 sun = sphericalDirection(40.0f * kPi / 180.0f, 200.0f * kPi / 180.0f);
  const float zenith = std::max(w.z, 0.0f);
  const float sun_lobe = std::pow(std::max(glm::dot(w, sun), 0.0f), 12.0f);
  return 0.3f + 0.7f * zenith + 3.0f * sun_lobe;
}

Estimate estimateReflectedRadiance(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed) {
  Rng rng(seed, 1);
  // Kahan-free running sums in double are enough: terms are O(1) and counts below 1e8.
  double sum = 0, sum_sq = 0;
  const auto start = Clock::now();
  for (std::uint64_t i = 0; i < count; ++i) {
    const auto s = sampled.sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    const double term = double(s->weight.luminance()) * double(environmentRadiance(s->wi));
    sum += term;
    sum_sq += term * term;
  }
  Estimate e;
  e.seconds = secondsSince(start);
  const double n = double(count);
  e.mean = sum / n;
  const double term_variance = std::max(0.0, (sum_sq - n * e.mean * e.mean) / std::max(1.0, n - 1.0));
  e.variance = term_variance / n;
  return e;
}

double samplesPerSecond(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed) {
  Rng rng(seed, 2);
  // The sink keeps the compiler from dropping draws whose results are unused.
  volatile float sink = 0;
  float acc = 0;
  const auto start = Clock::now();
  for (std::uint64_t i = 0; i < count; ++i) {
    float pdf = 0;
    if (const auto wi = drawDirection(sampled, wo, rng.uniform2D(), pdf)) acc += wi->x + pdf;
  }
  const double seconds = secondsSince(start);
  sink = acc;
  (void)sink;
  return double(count) / std::max(seconds, 1e-9);
}

}  // namespace btf::cli
