#include "btf/sampling/octree_bound_sampler.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <tbb/parallel_for.h>

#include "btf/core/error.h"
#include "btf/core/fast_trig.h"
#include "btf/core/math.h"
#include "merl_resolution.h"

namespace btf {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// Margins, in degrees, for the float rounding of the angles a query computes (about 1e-5 degree).
constexpr double kAngleMargin = 1e-3;
// Relative margin on a bound: luminance is a float blend of the channels and wo.h a float dot
// product, each a few ulps from the exact values the bound covers.
constexpr double kBoundMargin = 1e-5;

// theta_h (degrees) at the lower edge of slab i: u_h = sqrt(theta_h / 90) * 90.
double slabEdgeDegrees(int i) {
  const double x = double(i) / OctreeBoundSampler::kSlabs;
  return 90.0 * x * x;
}

// The f bound of a theta_h slab and a theta_d slab over all phi_d (one-cell margins).
double octreeMaxOverSlab(const OctreeTable& octree, int i, int j) {
  OctreeTable::Box box;
  box.lo = {std::max(i - 1, 0), std::max(j - 1, 0), 0};
  box.hi = {std::min(i + 3, OctreeBoundSampler::kSlabs), std::min(j + 3, kNd), kNp};
  return double(octree.maxOver(box));
}

struct Range {
  double lo, hi;  // degrees
};
struct PhiCells {
  int lo, hi;  // phi_d cells [lo, hi)
};

// The phi_d cells that a lookup can read for a pair with theta_o, theta_h and theta_d in the given
// ranges. In the half/diff frame, cos(theta_o) and cos(theta_i) are cos(theta_h) cos(theta_d) -+
// sin(theta_h) sin(theta_d) cos(phi_d), and the table folds phi_d onto [0, 180) (reciprocity), so
// the cell's phi_d satisfies cos(phi_d) = +-X with X = (cos(theta_o) - cos(theta_h) cos(theta_d)) /
// (sin(theta_h) sin(theta_d)). X's range follows by interval arithmetic (a guaranteed enclosure);
// each sign gives a range of phi_d, widened by the lookups' one-cell margins and cut where it wraps.
// Without a usable X (theta_h or theta_d at 0) every cell can be read.
std::vector<PhiCells> reachablePhiCells(Range theta_o, Range theta_h, Range theta_d) {
  const auto c = [](double deg) { return std::cos(std::clamp(deg, 0.0, 90.0) * kDegree); };
  const auto sn = [](double deg) { return std::sin(std::clamp(deg, 0.0, 90.0) * kDegree); };
  const double s0 = sn(theta_h.lo) * sn(theta_d.lo), s1 = sn(theta_h.hi) * sn(theta_d.hi);
  if (!(s0 > 1e-12)) return {{0, kNp}};
  const double n0 = c(theta_o.hi) - c(theta_h.lo) * c(theta_d.lo);
  const double n1 = c(theta_o.lo) - c(theta_h.hi) * c(theta_d.hi);
  const double x0 = n0 < 0 ? n0 / s0 : n0 / s1, x1 = n1 < 0 ? n1 / s1 : n1 / s0;
  if (x0 > 1.0 || x1 < -1.0) return {};  // no such pair
  const double a0 = std::acos(std::min(x1, 1.0)) / kDegree, a1 = std::acos(std::max(x0, -1.0)) / kDegree;
  std::vector<PhiCells> cells;
  // phi_d in [a0, a1] (sign +) and in [180 - a1, 180 - a0] (sign -), in cells with margins.
  for (const Range r : {Range{a0, a1}, Range{180.0 - a1, 180.0 - a0}}) {
    const int lo = int(std::floor(r.lo - kAngleMargin)) - 1, hi = int(std::floor(r.hi + kAngleMargin)) + 3;
    if (hi - lo >= kNp) return {{0, kNp}};
    if (lo < 0) cells.push_back({lo + kNp, kNp});
    if (hi > kNp) cells.push_back({0, hi - kNp});
    cells.push_back({std::max(lo, 0), std::min(hi, kNp)});
  }
  return cells;
}

// Half the range of azimuths of h about wo's azimuth, in radians, that can reflect some wo of the
// bin above the horizon, for h in a slab from theta_h_lo up. With wo = (sin o, 0, cos o) and h at
// (theta_h, delta phi), wi.z = 2 (wo.h) h.z - wo.z > 0 is cos(delta phi) > c = -cot(2 theta_h)
// cot(o). c grows with theta_h, so the slab's widest range is at theta_h_lo; there c is smallest at
// the bin's lower theta_o when cot(2 theta_h_lo) > 0 and at its upper one otherwise. The angles
// carry kAngleMargin outwards, and the range gets a margin of its own: wider only costs draws.
double validAzimuthRange(double theta_h_lo, double theta_o_lo, double theta_o_hi) {
  constexpr double kPiD = std::numbers::pi;
  const double th = std::max(theta_h_lo, 0.0) * kDegree;
  if (th <= 0.0) return kPiD;
  const double cot_2h = std::cos(2 * th) / std::sin(2 * th);
  const double theta_o = (cot_2h > 0 ? std::max(theta_o_lo, 0.0) : std::min(theta_o_hi, 90.0)) * kDegree;
  if (theta_o <= 0.0) return cot_2h > 0 ? kPiD : 0.0;
  const double c = -cot_2h * std::cos(theta_o) / std::sin(theta_o);
  if (c <= -1.0) return kPiD;
  if (c >= 1.0) return 0.0;
  return std::min(std::acos(c) + 1e-4, kPiD);
}

}  // namespace

OctreeBoundSampler::OctreeBoundSampler(std::shared_ptr<const OctreeBrdf> material, int theta_o_bins)
    : material_(std::move(material)), theta_o_bins_(theta_o_bins) {
  if (!material_) throw Error("OctreeBoundSampler: no material given");
  if (theta_o_bins < 1 || theta_o_bins > 900)
    throw Error("OctreeBoundSampler: theta_o_bins must be in [1, 900], not " + std::to_string(theta_o_bins));
  const OctreeTable& octree = material_->octree();

  for (int i = 0; i <= kSlabs; ++i) cos_edge_[std::size_t(i)] = float(std::cos(slabEdgeDegrees(i) * kDegree));
  cos_edge_[0] = 1.0f;
  cos_edge_[kSlabs] = 0.0f;

  bound_.assign(std::size_t(theta_o_bins_) * kSlabs, 0.0f);
  phi_range_.assign(std::size_t(theta_o_bins_) * kSlabs, 0.0f);
  cos_phi_range_.assign(std::size_t(theta_o_bins_) * kSlabs, 0.0f);
  cdf_.assign(std::size_t(theta_o_bins_) * (kSlabs + 1), 0.0f);
  norm_.assign(std::size_t(theta_o_bins_), 0.0f);
  // The f bound of each (theta_h slab, theta_d slab) over all phi_d: a quick test that skips the
  // phi_d-restricted queries of buildBin when they could not raise a bound.
  std::vector<double> slab_max(std::size_t(kSlabs) * kNd);
  tbb::parallel_for(0, kSlabs, [&](int i) {
    for (int j = 0; j < kNd; ++j) slab_max[std::size_t(i) * kNd + std::size_t(j)] = octreeMaxOverSlab(octree, i, j);
  });
  // Bins are independent and each writes only its own rows: the tables do not depend on the
  // thread count.
  tbb::parallel_for(0, theta_o_bins_, [&](int b) { buildBin(octree, slab_max, b); });
  if (std::all_of(norm_.begin(), norm_.end(), [](float n) { return n == 0.0f; }))
    throw Error("OctreeBoundSampler: the table has no measured cell with f > 0 (" + material_->name() + ")");
}

void OctreeBoundSampler::buildBin(const OctreeTable& octree, const std::vector<double>& slab_max, int b) {
  const double theta_o_lo = std::max(90.0 * b / theta_o_bins_ - kAngleMargin, 0.0);
  const double theta_o_hi = std::min(90.0 * (b + 1) / theta_o_bins_ + kAngleMargin, 90.0);
  float* bound = &bound_[std::size_t(b) * kSlabs];
  float* phi_range = &phi_range_[std::size_t(b) * kSlabs];
  float* cos_phi_range = &cos_phi_range_[std::size_t(b) * kSlabs];
  std::vector<double> mass(kSlabs);
  double total = 0;
  for (int i = 0; i < kSlabs; ++i) {
    const double theta_h_lo = std::max(slabEdgeDegrees(i) - kAngleMargin, 0.0);
    const double theta_h_hi = slabEdgeDegrees(i + 1) + kAngleMargin;
    // The angle between wo and h lies between |theta_o - theta_h| and theta_o + theta_h.
    const double d_lo = std::max({0.0, theta_h_lo - theta_o_hi, theta_o_lo - theta_h_hi});
    const double d_hi = std::min(theta_o_hi + theta_h_hi, 90.0);
    double b_max = 0;
    // h beyond (90 + theta_o) / 2 reflects every wo of the bin below the horizon (the reflection
    // is highest when h leans towards wo, at theta_i = 2 theta_h - theta_o): such slabs get no mass.
    const bool reflects_above = theta_h_lo < 0.5 * (90.0 + theta_o_hi);
    for (int j = int(d_lo); reflects_above && j <= std::min(int(d_hi), kNd - 1); ++j) {
      const double cos_d = std::cos(j * kDegree);
      if (cos_d * slab_max[std::size_t(i) * kNd + std::size_t(j)] <= b_max) continue;  // cannot raise it
      for (const PhiCells& cells : reachablePhiCells({theta_o_lo, theta_o_hi}, {theta_h_lo, theta_h_hi},
                                                    {double(j) - kAngleMargin, double(j + 1) + kAngleMargin})) {
        OctreeTable::Box box;
        box.lo = {std::max(i - 1, 0), std::max(j - 1, 0), cells.lo};
        box.hi = {std::min(i + 3, kSlabs), std::min(j + 3, kNd), cells.hi};
        b_max = std::max(b_max, cos_d * double(octree.maxOver(box)));
      }
    }
    // Rounded up to float so that the stored bound still bounds.
    float stored = float(b_max * (1.0 + kBoundMargin));
    if (double(stored) < b_max) stored = std::nextafter(stored, INFINITY);
    bound[i] = stored;
    const double half_range = validAzimuthRange(theta_h_lo, theta_o_lo, theta_o_hi);
    phi_range[i] = float(half_range);
    cos_phi_range[i] = half_range >= std::numbers::pi ? -2.0f : float(std::cos(half_range));
    mass[std::size_t(i)] = double(stored) * 2.0 * double(phi_range[i]) *
                           (double(cos_edge_[std::size_t(i)]) - cos_edge_[std::size_t(i) + 1]);
    total += mass[std::size_t(i)];
  }
  if (!(total > 0)) return;
  float* cdf = &cdf_[std::size_t(b) * (kSlabs + 1)];
  double sum = 0;
  for (int i = 0; i < kSlabs; ++i) {
    sum += mass[std::size_t(i)];
    cdf[i + 1] = float(sum / total);
  }
  cdf[kSlabs] = 1.0f;
  norm_[std::size_t(b)] = float(1.0 / total);
}

int OctreeBoundSampler::thetaOBin(float cos_theta_o) const {
  const float theta = std::acos(std::clamp(cos_theta_o, 0.0f, 1.0f));
  const int b = int(theta * float(2.0 * std::numbers::inv_pi) * float(theta_o_bins_));
  return std::clamp(b, 0, theta_o_bins_ - 1);
}

int OctreeBoundSampler::slabOf(float cos_theta_h) const {
  // The number of inner edges at or above cos_theta_h (the edges decrease).
  const auto first = cos_edge_.begin() + 1, last = cos_edge_.begin() + kSlabs;
  return int(std::partition_point(first, last, [&](float e) { return e >= cos_theta_h; }) - first);
}

Rgb OctreeBoundSampler::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return material_->eval(wi, wo, uv);
}

void OctreeBoundSampler::evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out, glm::vec2 uv) const {
  material_->evalMany(wo, wi, out, uv);
}

float OctreeBoundSampler::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (!(wi.z > 0.0f && wo.z > 0.0f)) return 0.0f;
  const glm::vec3 s = wi + wo;
  const float len = glm::length(s);
  if (!(len > 0.0f)) return 0.0f;
  const glm::vec3 h = s / len;
  const float d = glm::dot(wo, h);
  if (!(d > 0.0f)) return 0.0f;
  const int b = thetaOBin(wo.z);
  const std::size_t cell = std::size_t(b) * kSlabs + std::size_t(slabOf(h.z));
  const float cos_range = cos_phi_range_[cell];
  if (cos_range > -1.0f) {
    // Outside the slab's azimuth range about wo: q is 0 there. At the pole (no azimuth) h counts
    // as lying towards wo.
    const float ho = h.x * wo.x + h.y * wo.y, hh = h.x * h.x + h.y * h.y, oo = wo.x * wo.x + wo.y * wo.y;
    if (hh > 0.0f && oo > 0.0f && ho < cos_range * std::sqrt(hh * oo)) return 0.0f;
  }
  return bound_[cell] * norm_[std::size_t(b)] / (4.0f * d);
}

std::optional<OctreeBoundSampler::DirectionSample> OctreeBoundSampler::sampleDirection(const glm::vec3& wo,
                                                                                     glm::vec2 u) const {
  if (!(wo.z > 0.0f)) return std::nullopt;
  const int b = thetaOBin(wo.z);
  if (norm_[std::size_t(b)] == 0.0f) return std::nullopt;
  const float* cdf = &cdf_[std::size_t(b) * (kSlabs + 1)];
  const float x = std::clamp(u.x, 0.0f, std::nextafter(1.0f, 0.0f));
  // The slab whose CDF interval holds x; zero-width slabs are never chosen.
  const int i = std::min(int(std::upper_bound(cdf + 1, cdf + kSlabs + 1, x) - (cdf + 1)), kSlabs - 1);
  const float t = (x - cdf[i]) / (cdf[i + 1] - cdf[i]);
  const float c0 = cos_edge_[std::size_t(i)], c1 = cos_edge_[std::size_t(i) + 1];
  const float cos_h = std::clamp(c0 - t * (c0 - c1), c1, c0);
  const float sin_h = std::sqrt(std::max(1.0f - cos_h * cos_h, 0.0f));
  // Azimuth of h: uniform within the slab's range about wo's azimuth.
  const float range = phi_range_[std::size_t(b) * kSlabs + std::size_t(i)];
  float c, s;
  cosSinTurns((2.0f * u.y - 1.0f) * range * float(0.5 * std::numbers::inv_pi), c, s);
  const float oo = wo.x * wo.x + wo.y * wo.y;
  float co = 1.0f, so = 0.0f;
  if (oo > 0.0f) {
    const float inv = 1.0f / std::sqrt(oo);
    co = wo.x * inv, so = wo.y * inv;
  }
  const glm::vec3 h(sin_h * (co * c - so * s), sin_h * (so * c + co * s), cos_h);
  const float d = glm::dot(wo, h);
  if (!(d > 0.0f)) return std::nullopt;
  const glm::vec3 r = (2.0f * d) * h - wo;
  if (!(r.z > 0.0f)) return std::nullopt;
  const glm::vec3 wi = glm::normalize(r);
  const float p = pdf(wi, wo);
  if (!(p > 0.0f) || !(wi.z > 0.0f)) return std::nullopt;
  return DirectionSample{wi, p};
}

std::optional<BsdfSample> OctreeBoundSampler::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  const auto d = sampleDirection(wo, u);
  if (!d) return std::nullopt;
  const Rgb f = material_->eval(d->wi, wo, uv);
  return BsdfSample{d->wi, f * (d->wi.z / d->pdf), d->pdf};
}

std::optional<glm::vec3> OctreeBoundSampler::sampleByRejection(const glm::vec3& wo, Rng& rng, int max_tries,
                                                               int& tries) const {
  tries = 0;
  if (!(wo.z > 0.0f)) return std::nullopt;
  const int b = thetaOBin(wo.z);
  while (tries < max_tries) {
    ++tries;
    const glm::vec2 u = rng.uniform2D();
    const float accept = rng.uniform();
    const auto d = sampleDirection(wo, u);
    if (!d) continue;
    const glm::vec3 h = glm::normalize(d->wi + wo);
    const float bound_here = bound(b, slabOf(h.z));
    const float target = material_->eval(d->wi, wo).luminance() * d->wi.z * glm::dot(wo, h);
    if (accept * bound_here < target) return d->wi;
  }
  return std::nullopt;
}

std::string OctreeBoundSampler::name() const {
  return "octree-bound(" + material_->name() + ", theta_o_bins=" + std::to_string(theta_o_bins_) + ")";
}

}  // namespace btf
