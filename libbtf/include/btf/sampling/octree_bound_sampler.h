// Importance sampling of an octree table (compress/octree_table.h) from the bounds its nodes store,
// and the rejection sampler those bounds make possible: no tabulation per wo, a few float tables
// per theta_o bin and theta_h slab (bytes()).
//
// Domain. The sampler draws the half vector h and reflects wo about it (wi = 2 (wo.h) h - wo,
// d omega_i = 4 (wo.h) d omega_h), because the table's own coordinates are theta_h, theta_d and
// phi_d: for a fixed wo, theta_d is the angle between wo and h, so a slab of theta_h and a range
// of theta_o bound the theta_d a draw can have. The target is luminance(f) cos(theta_i) over wi,
// i.e. 4 luminance(f) cos(theta_i) cos(theta_d) over h.
//
// Bound. theta_o is cut into theta_o_bins equal-angle bins, theta_h into the table's 90 slabs
// (slab i holds u_h in [i, i + 1), u_h = sqrt(theta_h / (pi/2)) * 90 as in MerlTable). For a bin
// and a slab, B = max over the theta_d (1-degree slabs j) that an h of the slab can make with a wo
// of the bin (between |theta_o - theta_h| and theta_o + theta_h) of
//   maxOver(theta_h cells [i-1, i+3), theta_d cells [j-1, j+3), all phi_d) * cos(j degrees),
// the node ranges of the tree read over whole nodes (an upper bound of every channel of f, hence
// of its luminance; the one-cell margins cover every lookup, nearest or interpolated, and float
// rounding of the coordinates). So luminance(f) cos(theta_d) <= B on the slab for every wo of the
// bin, a guarantee, not an estimate from probes: the sampler cannot miss a feature of the table.
//
// Proposal (exact mode, what sample() and pdf() do): h with density q(h) = B(bin, slab of h) / Z
// over the part of each slab whose azimuth about wo's lies within the range that can reflect a wo
// of the bin above the horizon (a closed form per bin and slab, widened a little), Z = sum over
// slabs of B * (solid angle of that part): a slab by a 91-entry CDF, cos(theta_h) uniform within
// it, the azimuth uniform within the range. pdf(wi) = q(h) / (4 wo.h), exact and computed by one
// code path for sample() and pdf(). A reflection below the horizon is no
// sample (its mass is where f cos is 0). The weight f cos / pdf = 4 f cos(theta_i) cos(theta_d) Z
// / B is at most 4 Z in every channel (B bounds every channel): no fireflies, whatever the table.
//
// Rejection mode (sampleByRejection): accept a proposal with probability
// luminance(f) cos(theta_i) cos(theta_d) / B <= 1. Accepted draws follow luminance(f) cos(theta_i)
// exactly (Montes et al. 2008 with the octree's maxima as the bound, after Knoll et al. 2006),
// but their normalization is the albedo, which no finite computation gives exactly; so this mode
// returns directions without a pdf, for photon tracing and for measuring acceptance. Used as a
// roulette on exact-mode draws (survive with that probability, weight divided by it) it is
// unbiased with the exact pdf q. Each try costs one eval of the octree.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "btf/core/rng.h"
#include "btf/material/octree_brdf.h"

namespace btf {

class OctreeBoundSampler final : public Material {
 public:
  // Throws btf::Error for a null material, theta_o_bins outside [1, 900], or a table without a
  // measured cell (nothing to sample).
  explicit OctreeBoundSampler(std::shared_ptr<const OctreeBrdf> material, int theta_o_bins = 90);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  void evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out,
                glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

  // A proposal (exact mode) without the eval for the weight: wi and pdf(wi, wo), bit for bit.
  struct DirectionSample {
    glm::vec3 wi;
    float pdf;
  };
  std::optional<DirectionSample> sampleDirection(const glm::vec3& wo, glm::vec2 u) const;

  // Rejection mode: up to max_tries proposals from rng, each accepted with the probability above;
  // the accepted wi, or nothing when all were rejected or fell below the horizon. tries counts
  // the proposals drawn.
  std::optional<glm::vec3> sampleByRejection(const glm::vec3& wo, Rng& rng, int max_tries, int& tries) const;

  int thetaOBins() const { return theta_o_bins_; }
  // The theta_o bin of a wo (wo.z in [0, 1]) and the bin's normalization Z of q (0: nothing to sample).
  int thetaOBin(const glm::vec3& wo) const { return thetaOBin(wo.z); }
  double normalization(int theta_o_bin) const {
    const float inv = norm_[std::size_t(theta_o_bin)];
    return inv > 0 ? 1.0 / double(inv) : 0.0;
  }
  // Bytes of the bounds and CDFs (the octree itself belongs to the material).
  std::size_t bytes() const {
    return (bound_.size() + phi_range_.size() + cos_phi_range_.size() + cdf_.size() + norm_.size()) * sizeof(float);
  }
  // The bound B of a theta_o bin and theta_h slab (for tests).
  float bound(int theta_o_bin, int slab) const { return bound_[std::size_t(theta_o_bin) * kSlabs + std::size_t(slab)]; }
  static constexpr int kSlabs = MerlTable::kThetaHalfRes;

 private:
  int thetaOBin(float cos_theta_o) const;
  int slabOf(float cos_theta_h) const;
  void buildBin(const OctreeTable& octree, const std::vector<double>& slab_max, int theta_o_bin);

  std::shared_ptr<const OctreeBrdf> material_;
  int theta_o_bins_;
  std::vector<float> bound_;  // theta_o_bins x kSlabs
  // Per bin and slab: half the range of h's azimuth about wo's that can reflect above the horizon
  // (radians, pi = all) and its cosine (-2 when all azimuths are in range).
  std::vector<float> phi_range_, cos_phi_range_;
  std::vector<float> cdf_;    // theta_o_bins x (kSlabs + 1), over B * slab solid angle
  std::vector<float> norm_;   // per bin: 1 / Z (0 for a bin with nothing to sample)
  std::array<float, kSlabs + 1> cos_edge_{};  // cos(theta_h) at the slab edges, decreasing
};

}  // namespace btf
