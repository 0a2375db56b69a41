#include "sampling_measures.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>
#include <vector>

#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/sampling/sampler_choice.h"

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
  e.per_sample_variance = term_variance;
  return e;
}

namespace {

// Midpoint rule of f cos E over the hemisphere on nt x 2 nt cells of (theta, phi).
double midpointRadiance(const Material& material, const glm::vec3& wo, int nt) {
  const int np = 2 * nt;
  const double dtheta = 0.5 * double(kPi) / nt, dphi = 2.0 * double(kPi) / np;
  std::vector<double> rows(nt, 0.0);
  auto row_sum = [&](int i) {
    const double theta = (i + 0.5) * dtheta, st = std::sin(theta), ct = std::cos(theta);
    double row = 0.0;
    for (int j = 0; j < np; ++j) {
      const double phi = (j + 0.5) * dphi;
      const glm::vec3 wi{float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct)};
      row += double(material.eval(wi, wo).luminance()) * double(environmentRadiance(wi));
    }
    rows[i] = row * ct * st * dtheta * dphi;
  };
  // Plain threads over interleaved rows (the CLI does not link TBB); each row is summed alone and
  // the rows in order below, so the result does not depend on the thread count.
  const int threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  std::vector<std::thread> pool;
  for (int k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      for (int i = k; i < nt; i += threads) row_sum(i);
    });
  for (std::thread& t : pool) t.join();
  return std::accumulate(rows.begin(), rows.end(), 0.0);
}

}  // namespace

Quadrature referenceRadiance(const Material& material, const glm::vec3& wo, int theta_steps) {
  const auto start = Clock::now();
  Quadrature q;
  const double coarse = midpointRadiance(material, wo, theta_steps);
  const double fine = midpointRadiance(material, wo, 2 * theta_steps);
  // The midpoint rule's error falls by 4 when the step halves (smooth integrand): Richardson's
  // extrapolation removes that term; what is left is bounded by the fine rule's error estimate.
  q.value = fine + (fine - coarse) / 3.0;
  q.error = std::abs(fine - coarse) / 3.0;
  q.seconds = secondsSince(start);
  return q;
}

double fcosRelativeVariance(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed) {
  Rng rng(seed, 3);
  double sum = 0, sum_sq = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    const auto s = sampled.sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    const double w = double(s->weight.luminance());
    sum += w;
    sum_sq += w * w;
  }
  const double n = double(count), mean = sum / n;
  if (!(mean > 0)) return 0.0;
  return std::max(0.0, (sum_sq - n * mean * mean) / std::max(1.0, n - 1.0)) / (mean * mean);
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

namespace {

constexpr std::size_t kStreamBlock = 256;

// Draws per second of `draw_block(u, wi, pdf)` over blocks of kStreamBlock uniform pairs (drawn
// outside the timed part). With `evaluator`, each block's directions are then evaluated at wo
// inside the timed part, as a renderer's stream makes the weights' evals: one evalMany per block
// (a lost draw, wi = 0, evaluates to 0).
template <class DrawBlock>
double streamRate(const glm::vec3& wo, std::uint64_t count, std::uint64_t seed, const Material* evaluator,
                  DrawBlock draw_block) {
  Rng rng(seed, 2);
  std::vector<glm::vec2> u(kStreamBlock);
  std::vector<glm::vec3> wi(kStreamBlock);
  std::vector<float> pdf(kStreamBlock);
  std::vector<Rgb> f(kStreamBlock);
  volatile float sink = 0;
  float acc = 0;
  double seconds = 0;
  for (std::uint64_t done = 0; done < count; done += kStreamBlock) {
    for (glm::vec2& v : u) v = rng.uniform2D();
    const auto start = Clock::now();
    draw_block(u, wi, pdf);
    if (evaluator) {
      evaluator->evalMany(wo, wi, f);
      for (const Rgb& v : f) acc += v.luminance();
    }
    seconds += secondsSince(start);
    acc += pdf[done / kStreamBlock % kStreamBlock];
  }
  sink = acc;
  (void)sink;
  return double((count + kStreamBlock - 1) / kStreamBlock * kStreamBlock) / std::max(seconds, 1e-9);
}

}  // namespace

double streamSamplesPerSecond(const BinnedSampler& sampler, const glm::vec3& wo, std::uint64_t count,
                              std::uint64_t seed, bool with_eval) {
  const std::vector<glm::vec3> wos(kStreamBlock, wo);
  std::vector<BinnedSampler::DirectionSample> out(kStreamBlock);
  return streamRate(wo, count, seed, with_eval ? &sampler.material() : nullptr,
                    [&](const std::vector<glm::vec2>& u, std::vector<glm::vec3>& wi, std::vector<float>& pdf) {
                      sampler.sampleDirections(wos, u, out);
                      for (std::size_t k = 0; k < kStreamBlock; ++k) wi[k] = out[k].wi, pdf[k] = out[k].pdf;
                    });
}

double streamSamplesPerSecond(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed,
                              bool with_eval) {
  return streamRate(wo, count, seed, with_eval ? &sampled : nullptr,
                    [&](const std::vector<glm::vec2>& u, std::vector<glm::vec3>& wi, std::vector<float>& pdf) {
                      for (std::size_t k = 0; k < kStreamBlock; ++k) {
                        const auto d = drawDirection(sampled, wo, u[k], pdf[k]);
                        wi[k] = d ? *d : glm::vec3(0.0f);
                      }
                    });
}

EfficiencyCeiling efficiencyCeiling(const Material& material, const glm::vec3& wo, std::uint64_t count,
                                    std::uint64_t seed, int timing_repeats) {
  // The own draws, and the moments both variances need.
  Rng rng(seed, 1);
  std::vector<glm::vec3> wi(count, glm::vec3(0.0f));
  std::vector<float> pdf(count, 0.0f);
  double sum_w = 0, sum_we = 0, sum_we2 = 0, sum_term_sq = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    const auto s = material.sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    wi[i] = s->wi;
    pdf[i] = s->pdf;
    const double w = s->weight.luminance(), e = environmentRadiance(s->wi);
    sum_w += w;
    sum_we += w * e;
    sum_we2 += w * e * e;
    sum_term_sq += (w * e) * (w * e);
  }
  const double n = double(count), albedo = sum_w / n, mean = sum_we / n;
  const double own_variance = sum_term_sq / n - mean * mean;
  const double proportional_variance = albedo * sum_we2 / n - mean * mean;

  EfficiencyCeiling c;
  // 0 (no ratio) when either variance vanishes (to rounding): an own sampler without variance
  // leaves nothing to compare with, and a ceiling from a zero proportional variance is no figure.
  c.variance_ratio = proportional_variance > 0 && own_variance > 0 ? own_variance / proportional_variance : 0.0;
  c.draws = count;
  c.own_seconds = c.eval_env_seconds = c.eval_many_seconds = 1e300;
  volatile double sink = 0;
  constexpr std::size_t kBlock = 256;
  std::vector<Rgb> f(kBlock);
  for (int r = 0; r < timing_repeats; ++r) {
    c.own_seconds = std::min(c.own_seconds, estimateReflectedRadiance(material, wo, count, seed).seconds);
    double acc = 0;
    auto start = Clock::now();
    for (std::uint64_t i = 0; i < count; ++i) {
      if (!(pdf[i] > 0.0f)) continue;
      acc += double(material.eval(wi[i], wo).luminance() * wi[i].z / pdf[i]) * double(environmentRadiance(wi[i]));
    }
    c.eval_env_seconds = std::min(c.eval_env_seconds, secondsSince(start));
    start = Clock::now();
    for (std::uint64_t i = 0; i < count; i += kBlock) {
      const std::size_t m = std::min<std::uint64_t>(kBlock, count - i);
      material.evalMany(wo, std::span<const glm::vec3>(wi.data() + i, m), std::span<Rgb>(f.data(), m));
      acc += f[0].g;
    }
    c.eval_many_seconds = std::min(c.eval_many_seconds, secondsSince(start));
    sink = acc;
  }
  (void)sink;
  return c;
}

}  // namespace btf::cli
