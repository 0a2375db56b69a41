#include "btf/sampling/binned_sampler.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/sampling/quadtree_sampler.h"
#include "btf/sampling/tabulated_sampler.h"

namespace btf {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("sampler options: " + what);
}

void validate(const SamplerOptions& o) {
  require(o.theta_o_bins >= 1 && o.theta_o_bins <= 4096, "theta_o_bins must be in [1, 4096]");
  require(o.phi_o_bins >= 1 && o.phi_o_bins <= 4096, "phi_o_bins must be in [1, 4096]");
  require(o.cos_theta_bins >= 1 && o.cos_theta_bins <= 65536, "cos_theta_bins must be in [1, 65536]");
  require(o.phi_bins >= 1 && o.phi_bins <= 65536, "phi_bins must be in [1, 65536]");
  require(o.supersampling >= 1 && o.supersampling <= 64, "supersampling must be in [1, 64]");
  require(o.defensive_fraction >= 0.0f && std::isfinite(o.defensive_fraction), "defensive_fraction must be finite and >= 0");
  require(o.epsilon >= 0.0f && !std::isnan(o.epsilon), "epsilon must be >= 0");
  require(o.threshold >= 1.0f && std::isfinite(o.threshold), "threshold must be finite and >= 1");
  require(o.min_depth >= 0 && o.min_depth <= o.max_depth && o.max_depth <= 16,
          "depths must satisfy 0 <= min_depth <= max_depth <= 16");
  require(o.quadtree_probes >= 1 && o.quadtree_probes <= 64, "quadtree_probes must be in [1, 64]");
  require(o.max_tries >= 1 && o.max_tries <= 1 << 20, "max_tries must be in [1, 2^20]");
  require(o.half_vector_bins >= 2 && o.half_vector_bins <= 65536, "half_vector_bins must be in [2, 65536]");
}

float thetaOCentre(int i, int n) { return (float(i) + 0.5f) / float(n) * kHalfPi; }

}  // namespace

std::string_view toString(SamplerKind kind) {
  switch (kind) {
    case SamplerKind::Tabulated: return "tabulated";
    case SamplerKind::DpCdf: return "dp-cdf";
    case SamplerKind::Quadtree: return "quadtree";
  }
  return "unknown";
}

std::string_view toString(Parameterization p) {
  switch (p) {
    case Parameterization::Auto: return "auto";
    case Parameterization::Incident: return "incident";
    case Parameterization::Half: return "half";
  }
  return "unknown";
}

std::optional<Parameterization> parseParameterization(std::string_view name) {
  for (Parameterization p : {Parameterization::Auto, Parameterization::Incident, Parameterization::Half})
    if (toString(p) == name) return p;
  return std::nullopt;
}

std::optional<SamplerKind> parseSamplerKind(std::string_view name) {
  for (SamplerKind k : {SamplerKind::Tabulated, SamplerKind::DpCdf, SamplerKind::Quadtree})
    if (toString(k) == name) return k;
  return std::nullopt;
}

BinnedSampler::BinnedSampler(std::shared_ptr<const Material> material, const SamplerOptions& options)
    : material_(std::move(material)), options_(options) {
  if (!material_) throw Error("sampler: no material given");
  validate(options_);
  if (options_.parameterization == Parameterization::Auto) {
    const ParameterizationChoice choice = chooseParameterization(material_, options_);
    options_.parameterization = choice.chosen;
    auto_variance_incident_ = choice.incident_variance;
    auto_variance_half_ = choice.half_variance;
  }
  anisotropic_ = material_->isAnisotropic();
  theta_o_bins_ = options_.theta_o_bins;
  phi_o_bins_ = anisotropic_ ? options_.phi_o_bins : 1;
  for (int i = 1; i < theta_o_bins_; ++i)
    cos_theta_o_edges_.push_back(std::cos(float(i) / float(theta_o_bins_) * kHalfPi));
  // The narrowest bins in z are next to the normal (width ~ (pi / 2n)^2 / 2), so about n^2 / 2
  // cells leave ~1 edge per cell there; a power of two makes z * size exact in float. Capped at
  // 64 Ki cells (128 KiB): finer theta_o grids only scan a little further.
  const std::size_t cells = std::clamp<std::size_t>(
      std::bit_ceil(std::size_t(theta_o_bins_) * std::size_t(theta_o_bins_) / 2), 64, std::size_t(1) << 16);
  theta_guide_.resize(cells + 1);
  for (std::size_t g = 0; g <= cells; ++g) {
    const float upper = float(g + 1) / float(cells);  // exact: cells is a power of two
    theta_guide_[g] = static_cast<std::uint16_t>(
        std::count_if(cos_theta_o_edges_.begin(), cos_theta_o_edges_.end(), [&](float e) { return e >= upper; }));
  }
  // Sentinels for binOf's branch-free steps: no z (not even NaN) is <= -infinity... except
  // -infinity itself, which the bounded loop after the steps still handles.
  cos_theta_o_edges_.push_back(-std::numeric_limits<float>::infinity());
  cos_theta_o_edges_.push_back(-std::numeric_limits<float>::infinity());
}

glm::vec3 BinnedSampler::binEdgeDirection(std::size_t bin, bool upper) const {
  const int theta_bin = int(bin / phi_o_bins_), phi_bin = int(bin % phi_o_bins_);
  const float phi = anisotropic_ ? (float(phi_bin) + 0.5f) / float(phi_o_bins_) * kTwoPi : 0.0f;
  // The upper edge of the last bin is the horizon itself, where f is not defined.
  const float theta = std::min(float(theta_bin + int(upper)) / float(theta_o_bins_) * kHalfPi, kHalfPi - 1e-3f);
  return sphericalDirection(theta, phi);
}

glm::vec3 BinnedSampler::binDirection(std::size_t bin) const {
  const int theta_bin = int(bin / phi_o_bins_), phi_bin = int(bin % phi_o_bins_);
  const float phi = anisotropic_ ? (float(phi_bin) + 0.5f) / float(phi_o_bins_) * kTwoPi : 0.0f;
  return sphericalDirection(thetaOCentre(theta_bin, theta_o_bins_), phi);
}

float BinnedSampler::pdfQuery(const BinQuery& q, const glm::vec3& wi) const {
  if (!(wi.z > 0.0f)) return 0.0f;
  const std::optional<SquarePoint> p = incomingToSquare(q.toBinFrame(wi), q.wo);
  if (!p) return 0.0f;
  return pdfInBin(q.bin, p->st) * p->to_solid_angle;
}

std::optional<BinnedSampler::DirectionSample> BinnedSampler::sampleQuery(const BinQuery& q, glm::vec2 u,
                                                                         int& tries) const {
  const std::optional<glm::vec2> st = sampleInBin(q.bin, u, tries);
  if (!st) return std::nullopt;
  const std::optional<glm::vec3> wi_bin = squareToIncoming(*st, q.wo);
  if (!wi_bin) return std::nullopt;  // a half vector whose reflection is below the horizon
  const glm::vec3 wi = glm::normalize(q.fromBinFrame(*wi_bin));
  const float p = pdfQuery(q, wi);
  if (!(p > 0.0f)) return std::nullopt;  // only on a boundary of a zero-density cell
  return DirectionSample{wi, p};
}

Rgb BinnedSampler::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return material_->eval(wi, wo, uv);
}

void BinnedSampler::evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out, glm::vec2 uv) const {
  material_->evalMany(wo, wi, out, uv);
}

float BinnedSampler::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (!(wo.z > 0.0f)) return 0.0f;
  return pdfQuery(query(wo), wi);
}

std::optional<BsdfSample> BinnedSampler::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  int tries = 0;
  return sampleCountingTries(wo, uv, u, tries);
}

std::optional<BinnedSampler::DirectionSample> BinnedSampler::sampleDirection(const glm::vec3& wo, glm::vec2 u,
                                                                             int& tries) const {
  tries = 0;
  if (!(wo.z > 0.0f)) return std::nullopt;
  // u outside [0, 1)^2 (or NaN) would send the searches outside the tables: clamp it there
  // (NaN -> 0) rather than trust every caller.
  constexpr float kBelowOne = 0x1.fffffep-1f;
  const glm::vec2 safe_u(u.x > 0.0f ? std::min(u.x, kBelowOne) : 0.0f, u.y > 0.0f ? std::min(u.y, kBelowOne) : 0.0f);
  return sampleQuery(query(wo), safe_u, tries);
}

void BinnedSampler::sampleDirections(std::span<const glm::vec3> wo, std::span<const glm::vec2> u,
                                     std::span<DirectionSample> out) const {
  if (u.size() != wo.size() || out.size() != wo.size()) throw Error("sampleDirections: spans of different sizes");
  int tries = 0;
  for (std::size_t i = 0; i < wo.size(); ++i)
    out[i] = sampleDirection(wo[i], u[i], tries).value_or(DirectionSample{glm::vec3(0.0f), 0.0f});
}

void BinnedSampler::pdfs(std::span<const glm::vec3> wi, std::span<const glm::vec3> wo, std::span<float> out) const {
  if (wo.size() != wi.size() || out.size() != wi.size()) throw Error("pdfs: spans of different sizes");
  for (std::size_t i = 0; i < wi.size(); ++i) out[i] = pdf(wi[i], wo[i]);
}

std::optional<BsdfSample> BinnedSampler::sampleCountingTries(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u,
                                                             int& tries) const {
  const std::optional<DirectionSample> d = sampleDirection(wo, u, tries);
  if (!d) return std::nullopt;
  return BsdfSample{d->wi, material_->eval(d->wi, wo, uv) * (d->wi.z / d->pdf), d->pdf};
}

std::string BinnedSampler::name() const { return std::string(toString(kind())) + "(" + material_->name() + ")"; }

float BinnedSampler::target(std::size_t bin, glm::vec2 st) const {
  glm::vec3 wo = binDirection(bin);
  glm::vec3 wi;
  float jacobian = 1.0f;
  if (options_.parameterization == Parameterization::Half) {
    // Directions whose reflection is below the horizon for the bin's central wo may be above it
    // for other wo of the bin, and cells on the horizon are partly above it: without mass there,
    // a query would draw such directions only by the defensive share, with weights hundreds of
    // times the mean (at several theta_o on RGL files). So a point below the
    // horizon takes f at whichever of the bin's theta_o edges reflects it highest (the lower edge
    // for half vectors near the plane of wo, the upper one for many far out of it; wi.z is close
    // to linear in theta_o across a bin, so the edges bound it), and a point still just below it
    // there takes f at its mirror image above the horizon (within kHorizonBand of wi.z, about one
    // cell): cells on the edge keep their neighbours' mass. Lifting the points just above the
    // horizon too (wi.z < kHorizonBand) made the variance worse at theta_o = 0 on paper_white.
    constexpr float kHorizonBand = 0.02f;
    const glm::vec3 h = squareToHalfVector(st);
    Reflection reflected = reflectAbout(wo, h);
    if (!(reflected.wi.z > 0.0f))
      for (const bool upper : {false, true}) {
        const glm::vec3 edge = binEdgeDirection(bin, upper);
        const Reflection at_edge = reflectAbout(edge, h);
        if (at_edge.wi.z > reflected.wi.z) wo = edge, reflected = at_edge;
      }
    wi = reflected.wi;
    const float d = reflected.wo_dot_h;
    if (!(d > 0.0f) || !(wi.z > -kHorizonBand)) return 0.0f;
    wi.z = std::max(std::abs(wi.z), 1e-6f);
    wi = glm::normalize(wi);
    const float r = std::max(std::abs(2.0f * st.x - 1.0f), std::abs(2.0f * st.y - 1.0f));
    jacobian = 16.0f * kPi * r * r * d;
  } else {
    wi = squareToDirection(st);
  }
  // The density over the square is f cos times the map's Jacobian.
  const float v = material_->eval(wi, wo).luminance() * wi.z * jacobian;
  std::atomic_ref<std::uint64_t>(evaluations_).fetch_add(1, std::memory_order_relaxed);
  if (std::isfinite(v) && v >= 0.0f) return v;
  std::atomic_ref<std::uint64_t>(invalid_evaluations_).fetch_add(1, std::memory_order_relaxed);
  return 0.0f;
}

std::vector<float> BinnedSampler::tabulateGrid(int nu, int nv) const {
  const std::size_t cells = std::size_t(nu) * nv;
  std::vector<float> grid(binCount() * cells);
  const int ss = options_.supersampling;
  Progress progress("tabulating " + material_->name(), binCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, binCount()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t bin = r.begin(); bin < r.end(); ++bin) {
      float* values = grid.data() + bin * cells;
      double total = 0.0;
      for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
          double sum = 0.0;
          for (int a = 0; a < ss; ++a)
            for (int b = 0; b < ss; ++b)
              sum += target(bin, {(float(i) + (float(a) + 0.5f) / float(ss)) / float(nu),
                                  (float(j) + (float(b) + 0.5f) / float(ss)) / float(nv)});
          values[std::size_t(i) * nv + j] = float(sum / double(ss * ss));
          total += sum / double(ss * ss);
        }
      const float floor = float(options_.defensive_fraction * total / double(cells));
      for (std::size_t c = 0; c < cells; ++c) values[c] += floor;
      progress.advance();
    }
  });
  return grid;
}

void BinnedSampler::fillCommonStats(SamplerStats& stats) const {
  stats.kind = std::string(toString(kind()));
  stats.parameterization = std::string(toString(options_.parameterization));
  stats.auto_variance_incident = auto_variance_incident_;
  stats.auto_variance_half = auto_variance_half_;
  stats.bins = binCount();
  stats.full_cdf_bytes =
      binCount() * (std::size_t(gridRows() + 1) + std::size_t(gridRows()) * (gridColumns() + 1)) * sizeof(float);
  stats.evaluations = evaluations_;
  stats.invalid_evaluations = invalid_evaluations_;
}

void BinnedSampler::reportInvalidEvaluations() const {
  if (invalid_evaluations_ == 0) return;
  log(LogLevel::Warning, name() + ": " + std::to_string(invalid_evaluations_) + " of " + std::to_string(evaluations_) +
                             " evaluations were NaN, infinite or negative and were counted as 0");
}

std::unique_ptr<BinnedSampler> makeSampler(SamplerKind kind, std::shared_ptr<const Material> material,
                                           const SamplerOptions& options) {
  switch (kind) {
    case SamplerKind::Tabulated: return std::make_unique<TabulatedSampler>(std::move(material), options);
    case SamplerKind::DpCdf: return std::make_unique<DpCdfSampler>(std::move(material), options);
    case SamplerKind::Quadtree: return std::make_unique<QuadtreeSampler>(std::move(material), options);
  }
  throw Error("makeSampler: unknown sampler kind");
}

ParameterizationChoice chooseParameterization(std::shared_ptr<const Material> material, const SamplerOptions& options) {
  if (!material) throw Error("sampler: no material given");
  // Probes: tabulated samplers of each parameterization on the full grid but at most 9 theta_o
  // (and 4 phi_o) bins, so that both cost about half of one full build.
  SamplerOptions probe = options;
  probe.theta_o_bins = std::min(options.theta_o_bins, 9);
  probe.phi_o_bins = std::min(options.phi_o_bins, 4);
  // Measured a quarter of a full-size bin off each probe bin's centre: the mean distance of a
  // query from its bin's centre in the sampler being built, where the incident tables lose most.
  const float offset = 0.25f * kHalfPi / float(options.theta_o_bins);
  ParameterizationChoice choice;
  for (const Parameterization p : {Parameterization::Incident, Parameterization::Half}) {
    probe.parameterization = p;
    const TabulatedSampler sampler(material, probe);
    constexpr int kDraws = 4096;
    double sum = 0;
    for (int k = 0; k < probe.theta_o_bins; ++k) {
      const float theta = std::min(thetaOCentre(k, probe.theta_o_bins) + offset, kHalfPi - 1e-3f);
      const glm::vec3 wo = sphericalDirection(theta, 0.7f);
      Rng rng(0x5eed, std::uint64_t(k));
      double m1 = 0, m2 = 0;
      for (int i = 0; i < kDraws; ++i) {
        const auto d = sampler.sample(wo, {}, rng.uniform2D());
        const double w = d ? double(d->weight.luminance()) : 0.0;
        if (std::isfinite(w)) m1 += w, m2 += w * w;
      }
      m1 /= kDraws, m2 /= kDraws;
      if (m1 > 0) sum += std::max(m2 - m1 * m1, 0.0) / (m1 * m1);
    }
    (p == Parameterization::Incident ? choice.incident_variance : choice.half_variance) = sum / probe.theta_o_bins;
  }
  choice.chosen = choice.half_variance < choice.incident_variance ? Parameterization::Half : Parameterization::Incident;
  return choice;
}

}  // namespace btf
