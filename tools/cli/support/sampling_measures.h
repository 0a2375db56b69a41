// The measures of `btf bench sampling` (names as in docs/design-notes.md#measures):
// - samples_per_s: single-thread draws per second of a direction with its pdf (drawDirection).
// - the fixed estimate: reflected radiance L(wo) = integral of f(wi, wo) cos(theta_i) E(wi) dwi,
//   of the material lit by the smooth sky-like environment E below, by N samples of sample()
//   (weight times E; a draw with no direction counts 0).
// - variance: of that N-sample mean (the sample variance of the terms over N); seconds: the time of
//   the N draws, single thread; efficiency = 1 / (variance * seconds), which does not depend on N.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "btf/material/material.h"
#include "btf/sampling/binned_sampler.h"

namespace btf::cli {

// Radiance arriving from direction w (local frame, +z the normal): a sky brighter towards the
// zenith plus a broad sun-like lobe, smooth so that every sampler's estimate has finite variance.
float environmentRadiance(const glm::vec3& w);

struct Estimate {
  double mean = 0;
  double variance = 0;  // of the mean
  double per_sample_variance = 0;  // of one term (variance times the draw count)
  double seconds = 0;   // wall time of the draws, one thread
  double efficiency() const { return 1.0 / (variance * seconds); }
};

// The fixed estimate with `count` draws of sampled.sample(wo, .) from stream `seed`.
Estimate estimateReflectedRadiance(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed);

// The exact value of the fixed estimate by deterministic quadrature: the midpoint rule over
// (theta_i, phi_i) with theta_steps x 2 theta_steps cells (material.eval, no sampler involved),
// computed at theta_steps and at twice that and extrapolated (Richardson: the rule's error falls by
// 4 per halving); `error` is the finer rule's estimated error, |fine - coarse| / 3. Parallel over rows, summed in row order,
// so the value does not depend on the thread count.
struct Quadrature {
  double value = 0;
  double error = 0;
  double seconds = 0;
};
Quadrature referenceRadiance(const Material& material, const glm::vec3& wo, int theta_steps);

// The sampler's quality alone, without the environment: the relative variance per sample of the
// luminance of f cos / pdf (the sample's weight; a draw with no direction counts 0), over `count`
// draws from stream `seed`. 0 for a sampler proportional to f cos; what lost draws cost shows too.
double fcosRelativeVariance(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed);

// drawDirection per second on one thread over `count` draws.
double samplesPerSecond(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed);
// The same draws through the stream call (BinnedSampler::sampleDirections, blocks of 256). With
// with_eval, each block's drawn directions are then evaluated (the wrapped material's evalMany, which
// a renderer needs for the weight f cos / pdf) inside the timed part.
double streamSamplesPerSecond(const BinnedSampler& sampler, const glm::vec3& wo, std::uint64_t count,
                              std::uint64_t seed, bool with_eval = false);
// The same for a sampler without a stream call (dj-warp): drawDirection one by one into blocks of
// 256, with_eval then evaluating each block with evalMany, as above.
double streamSamplesPerSecond(const Material& sampled, const glm::vec3& wo, std::uint64_t count, std::uint64_t seed,
                              bool with_eval = false);

// What a BSDF sampler of a material that samples f cos exactly would reach, relative to the
// material's own sampler, measured on `count` of the own sampler's draws (stream `seed`, as
// estimateReflectedRadiance). An unbiased estimate from a sampler that is not exactly proportional
// to f cos needs f at each drawn wi for the weight f cos / pdf, so each draw costs at least the
// material's eval (plus the environment in the single-query estimate; the stream measure leaves the
// environment out); and a sampler exactly proportional to lum(f) cos, whose term is the albedo A
// times E(wi), has constant weights: the best a sampler that ignores the environment can aim for.
// It is not a floor under one fixed environment: a sampler whose departures from f cos put more
// draws where that environment is bright has less variance (variance_ratio < 1 says the own
// sampler does). The proportional sampler's per-sample variance follows from the own draws by
// importance weighting with their weights w = lum(f) cos / pdf: E[(A E)^2] = A E_own[w E^2], so
// it is A mean(w E^2) - L^2.
// The ceilings multiply the two: a sampler with zero cost beyond the eval and the variance of an
// exactly proportional one would have these efficiencies relative to the own sampler.
struct EfficiencyCeiling {
  double own_seconds = 0;         // the own estimate, best of the repeats
  double eval_env_seconds = 0;    // eval, the weight and the environment at the own draws
  double eval_many_seconds = 0;   // evalMany alone at the own draws, in blocks of 256
  double variance_ratio = 0;      // own per-sample variance / an exactly proportional sampler's
  std::uint64_t draws = 0;        // of each timed pass
  double single() const { return own_seconds / eval_env_seconds * variance_ratio; }
  double stream() const { return own_seconds / eval_many_seconds * variance_ratio; }
  // Seconds per draw of eval, weight and environment: what any table sampler pays on top of its draw.
  double evalEnvPerDraw() const { return eval_env_seconds / double(draws); }
  // The most an exactly proportional sampler's draw (direction and pdf, beyond evalEnvPerDraw) may
  // cost for `target` times the own sampler's single-query efficiency: its efficiency over the
  // own's is variance_ratio * own time / (draw + eval), so the draw may take variance_ratio * own
  // time / target - eval per draw. Negative: no such sampler reaches the target, however fast.
  double drawBudget(double target) const { return (own_seconds * variance_ratio / target - eval_env_seconds) / double(draws); }
};
EfficiencyCeiling efficiencyCeiling(const Material& material, const glm::vec3& wo, std::uint64_t count,
                                    std::uint64_t seed, int timing_repeats);

}  // namespace btf::cli
