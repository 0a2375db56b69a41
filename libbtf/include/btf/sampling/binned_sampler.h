// Common ground of the tabulated importance samplers (reference tables, Douglas-Peucker CDFs,
// quadtree rejection): each wraps any Material, tabulates it through eval(), and is a Material
// itself (eval forwards to the wrapped one; sample and pdf come from the tables).
//
// Outgoing bins. theta_o is cut into theta_o_bins equal-angle bins; an anisotropic material
// (isAnisotropic()) also gets phi_o_bins equal bins of phi_o. Each bin holds a distribution of
// wi tabulated for the bin's central wo. A query wo uses its nearest bin; since sample() and
// pdf() use the same bin, the pdf is exact for any wo (only how well it follows f depends on the
// bin width). For an isotropic material only theta_o is binned: wi is rotated about the normal by
// -phi_o into the bin's frame (where wo lies in the xz-plane at phi = 0) and back.
//
// Incoming parameterization (parameterization.h): a 2D distribution over the unit square (s, t),
// mapped to wi in the bin's frame either directly (Incident: s = cos(theta_i), t = phi_i / (2 pi),
// d omega = 2 pi ds dt, uniform resolution over the hemisphere) or through the half vector (Half:
// the square is a map of h that crowds cells towards the normal, wi is wo reflected about h,
// d omega_i = 16 pi r^2 (wo.h) ds dt),
// which puts a glossy lobe at the square's centre whatever wo is and spreads it over many cells.
// Half maps use the query's own wo (rotated into the bin frame), not the bin's central one, so the
// lobe follows wo within a bin. makeSampler with Parameterization::Auto builds both and keeps the
// one whose estimates vary less (see makeSampler).
//
// What is tabulated: the luminance of f(wi, wo) * cos(theta_i) (as rendering weights it) times the
// map's Jacobian over the square (constant for Incident, 16 pi r^2 (wo.h) for Half), plus
// defensive_fraction times its mean over the bin, so that the density is > 0 wherever f may be
// (the estimator stays unbiased even where the tabulation missed a feature). Values that are NaN,
// infinite or negative count as 0; how many there were is in stats().invalid_evaluations and
// reported once per construction through btf::log (Warning). A bin where everything is 0 is
// empty: sample() returns nothing and pdf() is 0 there.
//
// Exactness: sample() returns pdf(wi, wo) computed from the final float direction by the same code
// as pdf(), so the two agree bit for bit; they differ from the density actually drawn only on cell
// boundaries of float-rounding width. Construction is parallel over bins (TBB); the tables do not
// depend on the thread count. All queries are const and thread-safe and allocate nothing.
//
// Speed: a query makes one virtual call (sampleQuery / pdfQuery), which the DP and tabulated
// samplers override with a path that has no further virtual calls, no trigonometric function on wo
// (the rotation by -phi_o is wo.xy / |wo.xy|) and a table-guided theta_o bin lookup. The generic
// path through sampleInBin / pdfInBin remains for the quadtree.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "btf/core/fast_atan.h"
#include "btf/core/fast_trig.h"
#include "btf/core/math.h"
#include "btf/material/material.h"
#include "btf/core/dp_cdf.h"
#include "btf/sampling/parameterization.h"

namespace btf {

enum class SamplerKind { Tabulated, DpCdf, Quadtree };
std::string_view toString(SamplerKind kind);  // "tabulated", "dp-cdf", "quadtree"
std::optional<SamplerKind> parseSamplerKind(std::string_view name);

struct SamplerOptions {
  // How the incoming directions are laid over the square (parameterization.h); Auto measures both
  // (chooseParameterization) when the sampler is built.
  Parameterization parameterization = Parameterization::Auto;
  // Outgoing bins.
  int theta_o_bins = 32;
  int phi_o_bins = 16;  // anisotropic materials only
  // Incoming grid of the tabulated and DP samplers: rows in s = cos(theta_i), columns in phi_i
  // (Incident), or cells per side of the half-vector square (Half).
  int cos_theta_bins = 64;
  int phi_bins = 128;
  int half_vector_bins = 128;
  int supersampling = 2;  // eval() at supersampling^2 stratified points per cell, averaged
  float defensive_fraction = 1e-3f;
  // DP-CDF: tolerance on every 1D CDF (0 keeps all but collinear nodes; >= 1 keeps endpoints only).
  float epsilon = 1e-3f;
  // Fewest by default: the same tolerance with fewer vertices than Douglas-Peucker's splitting
  // (`btf bench sampling` reports bytes / full CDF), for a construction cost that is small
  // beside the tabulation.
  CdfReduction reduction = CdfReduction::Fewest;
  // Quadtree: subdivide while max > threshold * mean over a cell's probes and depth < max_depth;
  // every bin is split to min_depth first; probes per cell = (quadtree_probes + 1)^2.
  float threshold = 4.0f;
  int min_depth = 3;
  int max_depth = 9;
  int quadtree_probes = 4;
  int max_tries = 16;  // rejections before the fallback draw (see quadtree_sampler.h)
};

struct SamplerStats {
  std::string kind;
  std::string parameterization;  // "incident" or "half"
  // When the parameterization was chosen (Auto): the relative variance per sample of f cos / pdf
  // measured for each (chooseParameterization); NaN otherwise.
  double auto_variance_incident = std::numeric_limits<double>::quiet_NaN();
  double auto_variance_half = std::numeric_limits<double>::quiet_NaN();
  std::size_t bytes = 0;           // the sampler's own tables (not the wrapped material)
  std::size_t full_cdf_bytes = 0;  // float CDFs of the full grid (cos_theta_bins x phi_bins), for ratios
  std::size_t bins = 0, empty_bins = 0;
  std::size_t elements = 0;        // tabulated: CDF entries; DP: kept vertices; quadtree: leaves
  double mean_elements_per_cdf = 0;  // DP only: kept vertices per 1D CDF
  double acceptance_rate = std::numeric_limits<double>::quiet_NaN();      // quadtree: mean over non-empty bins
  double min_acceptance_rate = std::numeric_limits<double>::quiet_NaN();  // quadtree: worst bin
  std::uint64_t evaluations = 0;          // eval() calls made while building
  std::uint64_t invalid_evaluations = 0;  // of which NaN, infinite or negative (counted as 0)
};


class BinnedSampler : public Material {
 public:
  // Throws btf::Error for a null material or invalid options (the message names the option).
  BinnedSampler(std::shared_ptr<const Material> material, const SamplerOptions& options);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  void evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out,
                glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  // final: callers holding a BinnedSampler& get a direct call.
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const final;
  std::string name() const override;
  bool isAnisotropic() const override { return anisotropic_; }

  // As sample(), also reporting how many proposals were drawn (1 except for rejection samplers).
  std::optional<BsdfSample> sampleCountingTries(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u, int& tries) const;
  // The direction and its pdf without evaluating the material for the weight (the sampler's own
  // cost, for benchmarks and for callers that evaluate f themselves). pdf == pdf(wi, wo).
  struct DirectionSample {
    glm::vec3 wi;
    float pdf;
  };
  std::optional<DirectionSample> sampleDirection(const glm::vec3& wo, glm::vec2 u, int& tries) const;

  // Streams of queries, after Embree's packet and stream calls: out[i] is sampleDirection(wo[i],
  // u[i]) and pdfs' out[i] is pdf(wi[i], wo[i]), bit for bit, whatever the machine; a query with
  // no sample gets {wi = 0, pdf = 0}. The spans must have equal sizes (btf::Error otherwise). The
  // defaults loop over the single queries; DpCdfSampler runs 32 queries per step in AVX2 lanes
  // when the CPU has AVX2 (dp_cdf_sampler.h), which is what renderers that trace wavefronts of
  // paths (and the benchmarks) call.
  virtual void sampleDirections(std::span<const glm::vec3> wo, std::span<const glm::vec2> u,
                                std::span<DirectionSample> out) const;
  virtual void pdfs(std::span<const glm::vec3> wi, std::span<const glm::vec3> wo, std::span<float> out) const;

  virtual SamplerKind kind() const = 0;
  virtual SamplerStats stats() const = 0;
  // The options as built: parameterization() is Incident or Half (Auto resolved).
  const SamplerOptions& options() const { return options_; }
  Parameterization parameterization() const { return options_.parameterization; }
  // The grid of the tabulated and DP samplers for the parameterization: rows x columns.
  int gridRows() const { return half() ? options_.half_vector_bins : options_.cos_theta_bins; }
  int gridColumns() const { return half() ? options_.half_vector_bins : options_.phi_bins; }
  const Material& material() const { return *material_; }
  std::size_t binCount() const { return std::size_t(theta_o_bins_) * phi_o_bins_; }
  // The bin a wo falls in (wo.z > 0), and the central wo the bin was tabulated for (bin frame).
  std::size_t binOf(const glm::vec3& wo) const;
  glm::vec3 binDirection(std::size_t bin) const;
  // The bin's wo at its lower or upper theta_o edge (and central phi_o).
  glm::vec3 binEdgeDirection(std::size_t bin, bool upper) const;

 protected:
  // The bin of a wo and the rotation from the bin frame to the local frame (identity when
  // anisotropic: the bins then cover phi_o themselves).
  struct BinQuery {
    std::size_t bin;
    float cos_phi, sin_phi;
    glm::vec3 wo;  // the query's wo in the bin frame (Half maps reflect about it)
    glm::vec3 toBinFrame(const glm::vec3& w) const {
      return {cos_phi * w.x + sin_phi * w.y, -sin_phi * w.x + cos_phi * w.y, w.z};
    }
    glm::vec3 fromBinFrame(const glm::vec3& w) const {
      return {cos_phi * w.x - sin_phi * w.y, sin_phi * w.x + cos_phi * w.y, w.z};
    }
  };
  BinQuery query(const glm::vec3& wo) const;
  // binOf's theta_o tables, for vectorized lookups that must give its bins exactly.
  struct ThetaBinTable {
    const float* edges;           // cos of the inner edges, then two -infinity sentinels
    const std::uint16_t* guide;   // last_cell + 1 entries
    int last_cell;
    int edge_count;               // inner edges (theta_o_bins - 1)
  };
  ThetaBinTable thetaBinTable() const {
    return {cos_theta_o_edges_.data(), theta_guide_.data(), int(theta_guide_.size() - 1), theta_o_bins_ - 1};
  }
  // sampleDirection and pdf for wo.z > 0, after the bin lookup. The defaults go through
  // sampleInBin / pdfInBin; overrides must keep sampleQuery's pdf == pdfQuery(q, its wi).
  virtual std::optional<DirectionSample> sampleQuery(const BinQuery& q, glm::vec2 u, int& tries) const;
  virtual float pdfQuery(const BinQuery& q, const glm::vec3& wi) const;

  // A point (s, t) of the square for the bin, or nothing for an empty bin.
  virtual std::optional<glm::vec2> sampleInBin(std::size_t bin, glm::vec2 u, int& tries) const = 0;
  // Density over the square at (s, t) in [0,1)^2 for the bin.
  virtual float pdfInBin(std::size_t bin, glm::vec2 st) const = 0;

  // Luminance of f * cos(theta_i) at (s, t) for the bin's central wo (invalid values -> 0, counted).
  float target(std::size_t bin, glm::vec2 st) const;
  // For every bin, the cell means of the target on an nu x nv grid (supersampled, plus the
  // defensive share), bin-major then row (s) then column (t). Parallel over bins.
  std::vector<float> tabulateGrid(int nu, int nv) const;
  // Counters of target() calls since construction; derived classes copy them into stats().
  void fillCommonStats(SamplerStats& stats) const;
  // Logs a warning if any evaluation was invalid; derived constructors call it last.
  void reportInvalidEvaluations() const;

  bool half() const { return options_.parameterization == Parameterization::Half; }
  // The parameterization's map from a square point to wi in the bin frame (unit length), or
  // nothing where a half vector's reflection leaves the upper hemisphere.
  std::optional<glm::vec3> squareToIncoming(glm::vec2 st, const glm::vec3& wo_bin) const {
    if (!half()) return squareToDirection(st);
    const Reflection r = reflectAbout(wo_bin, squareToHalfVector(st));
    if (!(r.wo_dot_h > 0.0f) || !(r.wi.z > 0.0f)) return std::nullopt;
    return glm::normalize(r.wi);
  }
  // wo mirrored about the half vector h (unit length): wi = 2 (wo.h) h - wo, with wo.h, which
  // decides whether the reflection is valid and enters the half map's Jacobian.
  struct Reflection {
    glm::vec3 wi;
    float wo_dot_h;
  };
  static Reflection reflectAbout(const glm::vec3& wo, const glm::vec3& h) {
    const float d = glm::dot(wo, h);
    return {(2.0f * d) * h - wo, d};
  }
  // The square point of wi (bin frame, wi.z > 0) and the factor that turns a density over the
  // square into the solid-angle pdf of wi: 1 / (2 pi) for Incident, 1 / (16 pi r^2 wo.h) for Half
  // (parameterization.h). Nothing outside the square (wi.z == 1 exactly for Incident, h == n
  // exactly for Half: null sets) or for NaN.
  struct SquarePoint {
    glm::vec2 st;
    float to_solid_angle;
  };
  std::optional<SquarePoint> incomingToSquare(const glm::vec3& wi_bin, const glm::vec3& wo_bin) const {
    if (!half()) {
      const glm::vec2 st = directionToSquare(wi_bin);
      if (!(st.x < 1.0f)) return std::nullopt;
      return SquarePoint{st, kInv2Pi};
    }
    const glm::vec3 h = glm::normalize(wi_bin + wo_bin);
    const float d = glm::dot(wo_bin, h);
    const HalfVectorSquare m = halfVectorToSquare(h);
    const float jacobian = (16.0f * kPi) * (m.r * m.r) * d;
    if (!(jacobian > 0.0f) || !(m.st.x >= 0.0f && m.st.y >= 0.0f)) return std::nullopt;  // NaN fails the tests
    return SquarePoint{m.st, 1.0f / jacobian};
  }

  // Inline (and free of library trigonometry, see core/fast_trig.h) because they are on every query.
  static glm::vec3 squareToDirection(glm::vec2 st) {
    const float z = st.x, r = std::sqrt(std::max(1.0f - z * z, 0.0f));
    float c, s;
    cosSinTurns(st.y, c, s);
    return {r * c, r * s, z};
  }
  static glm::vec2 directionToSquare(const glm::vec3& w) {
    const float t = fastAtan2Turns(w.y, w.x);
    // Wrap into [0,1); t + 1 can round to exactly 1 for tiny negative t. The sign of t is random
    // for a sampler's directions: select by a mask (a ternary compiles to a mispredicted branch).
    const std::uint32_t negative = 0u - std::uint32_t(t < 0.0f);
    const float sum = t + 1.0f;  // for t < 0 in (0, 1]: exactly 1 becomes the float below it
    const float wrapped = std::bit_cast<float>(std::bit_cast<std::uint32_t>(sum) - std::uint32_t(sum >= 1.0f));
    return {w.z, std::bit_cast<float>((std::bit_cast<std::uint32_t>(wrapped) & negative) |
                                      (std::bit_cast<std::uint32_t>(t) & ~negative))};
  }

 private:

  std::shared_ptr<const Material> material_;
  SamplerOptions options_;
  bool anisotropic_;
  int theta_o_bins_, phi_o_bins_;
  std::vector<float> cos_theta_o_edges_;  // cos of the inner theta_o bin edges, decreasing; 2 sentinels
  // Guide table over wo.z (cutpoint method, Chen & Asau 1974): entry g is the number of edges
  // >= (g + 1) / size, a lower bound of binOf's theta bin for every z in [g / size, (g + 1) / size),
  // so the lookup scans forward over the few edges left instead of bisecting all of them.
  std::vector<std::uint16_t> theta_guide_;
  mutable std::uint64_t evaluations_ = 0, invalid_evaluations_ = 0;  // build-time only (atomically)
  // What chooseParameterization measured (NaN when the parameterization was given).
  double auto_variance_incident_ = std::numeric_limits<double>::quiet_NaN();
  double auto_variance_half_ = std::numeric_limits<double>::quiet_NaN();
};

// Inline (with query): on every sample and pdf, and a call from the library's own code would go
// through its PLT.
inline std::size_t BinnedSampler::binOf(const glm::vec3& wo) const {
  // Nearest bin in theta_o = the bin whose edges enclose it; cos decreases with theta, so the bin
  // is the number of inner edges e >= wo.z (no acos needed). The guide gives a lower bound (all
  // edges before it are >= the top of wo.z's guide cell); the scan counts the rest exactly as a
  // bisection would: two branch-free steps (the edges end with two -infinity sentinels; a guide
  // cell rarely holds more than two edges), then a loop that rarely runs. 32-bit conversions:
  // float -> size_t is a branchy two-conversion sequence on x86-64. NaN or z outside [0, 1] only
  // costs a longer scan or the first cell.
  const int last_cell = int(theta_guide_.size() - 1);
  const float scaled = wo.z * float(last_cell);
  const int g = scaled > 0.0f ? (scaled < float(last_cell) ? int(scaled) : last_cell) : 0;
  const std::size_t edges = std::size_t(theta_o_bins_ - 1);
  const float* e = cos_theta_o_edges_.data();
  std::size_t theta_bin = theta_guide_[std::size_t(g)];
  theta_bin += std::size_t(e[theta_bin] >= wo.z);
  theta_bin += std::size_t(e[theta_bin] >= wo.z);
  while (theta_bin < edges && e[theta_bin] >= wo.z) ++theta_bin;
  theta_bin = std::min(theta_bin, edges);
  if (!anisotropic_) return theta_bin;
  const float t = sphericalPhi(wo) * (0.5f * std::numbers::inv_pi_v<float>) * float(phi_o_bins_);
  const int phi_bin = t > 0.0f ? std::min(int(t), phi_o_bins_ - 1) : 0;  // NaN (a NaN wo.x or wo.y): bin 0
  return theta_bin * phi_o_bins_ + std::size_t(phi_bin);
}

inline BinnedSampler::BinQuery BinnedSampler::query(const glm::vec3& wo) const {
  BinQuery q{binOf(wo), 1.0f, 0.0f, wo};
  if (!anisotropic_) {
    // wo is a unit vector, so x^2 + y^2 cannot overflow: no need for hypot's care (and cost).
    // Below ~1e-19 the square underflows to 0 and the identity is used, as at the pole itself.
    const float r2 = wo.x * wo.x + wo.y * wo.y;
    if (r2 > 0.0f) {
      const float inv = 1.0f / std::sqrt(r2);
      q.cos_phi = wo.x * inv, q.sin_phi = wo.y * inv;
    }
    if (half()) q.wo = q.toBinFrame(wo);
  }
  return q;
}

// Builds the sampler of the given kind (throws btf::Error as the constructors do).
std::unique_ptr<BinnedSampler> makeSampler(SamplerKind kind, std::shared_ptr<const Material> material,
                                           const SamplerOptions& options = {});

// Parameterization::Auto: builds a tabulated sampler of each parameterization with the options'
// grids but at most 9 theta_o (and 4 phi_o) bins, and keeps the one whose estimate of f cos varies
// less: the mean over the probe bins of the relative variance per sample of f cos / pdf
// (luminance; a missing draw counts 0), 4,096 draws per bin from fixed streams at a quarter of a
// full-size bin off each probe bin's centre. Deterministic; costs about one full build.
struct ParameterizationChoice {
  Parameterization chosen = Parameterization::Incident;
  double incident_variance = 0, half_variance = 0;
};
ParameterizationChoice chooseParameterization(std::shared_ptr<const Material> material, const SamplerOptions& options);

}  // namespace btf
