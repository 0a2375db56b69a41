#include "btf/material/btf_material.h"

#include <array>
#include <atomic>
#include <cmath>

#include "btf/compress/compressed_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/cdf1d.h"
#include "btf/core/error.h"
#include "btf/core/fast_atan.h"
#include "btf/core/fast_trig.h"
#include "btf/core/math.h"
#include "btf/io/bonn_btf.h"
#include "btf/io/btf_images.h"
#include "btf/io/container.h"
#include "btf/material/registry.h"
#include "btf_scattered_directions.h"

namespace btf {

namespace {

// Cells of the light sphere (see the header): band of ring r in cos theta, and one cell's solid angle.
struct RingCells {
  std::array<float, kBtfRingCount> cos_top, cos_bottom, cell_solid_angle, cos_ring;
};
const RingCells& ringCells() {
  static const RingCells cells = [] {
    RingCells c{};
    for (int r = 0; r < kBtfRingCount; ++r) {
      const float deg = kPi / 180.0f;
      const float top = r == 0 ? 0.0f : (15.0f * float(r) - 7.5f) * deg;
      const float bottom = r == kBtfRingCount - 1 ? 0.5f * kPi : (15.0f * float(r) + 7.5f) * deg;
      c.cos_top[std::size_t(r)] = std::cos(top);
      c.cos_bottom[std::size_t(r)] = r == kBtfRingCount - 1 ? 0.0f : std::cos(bottom);
      c.cell_solid_angle[std::size_t(r)] =
          kTwoPi * (c.cos_top[std::size_t(r)] - c.cos_bottom[std::size_t(r)]) / float(btfRingSize(r));
      c.cos_ring[std::size_t(r)] = std::cos(btfRingThetaDeg(r) * deg);
    }
    return c;
  }();
  return cells;
}

// Polar angle in ring units (theta / 15 degrees) and azimuth in turns [0, 1).
inline float ringCoordinate(const glm::vec3& w) {
  return fastAtan2Turns(std::sqrt(w.x * w.x + w.y * w.y), w.z) * (360.0f / kBtfRingStepDeg);
}
inline float azimuthTurns(const glm::vec3& w) {
  float p = fastAtan2Turns(w.y, w.x);
  if (p < 0.0f) p += 1.0f;
  return p >= 1.0f ? 0.0f : p;
}

// Up to 4 measured directions and weights interpolating direction w (see the header).
struct DirectionStencil {
  int count = 0;
  std::array<int, 4> index{};
  std::array<float, 4> weight{};
  void add(int ring, float turns, float w) {
    const int n = btfRingSize(ring);
    if (n == 1) {
      index[std::size_t(count)] = btfRingStart(ring);
      weight[std::size_t(count++)] = w;
      return;
    }
    const float a = turns * float(n);
    int a0 = int(a);
    const float g = a - float(a0);
    if (a0 >= n) a0 -= n;
    const int a1 = a0 + 1 == n ? 0 : a0 + 1;
    index[std::size_t(count)] = btfRingStart(ring) + a0;
    weight[std::size_t(count++)] = w * (1.0f - g);
    index[std::size_t(count)] = btfRingStart(ring) + a1;
    weight[std::size_t(count++)] = w * g;
  }
};
// Over the first `rings` rings (views of a partial BTF: constant beyond its last ring).
DirectionStencil stencil(const glm::vec3& w, int rings = kBtfRingCount) {
  DirectionStencil s;
  const float t = ringCoordinate(w), turns = azimuthTurns(w);
  if (t >= float(rings - 1)) {
    s.add(rings - 1, turns, 1.0f);
    return s;
  }
  const int r0 = int(t);
  const float f = t - float(r0);
  s.add(r0, turns, 1.0f - f);
  if (f > 0.0f) s.add(r0 + 1, turns, f);
  return s;
}

inline int wrap(int i, int n) {
  i %= n;
  return i < 0 ? i + n : i;
}
inline int nearestTexel(float u, int n) { return wrap(int(std::floor(u * float(n))), n); }

// The light cell holding wi (ring band, azimuth cell centred on the measured azimuth).
inline void lightCell(const glm::vec3& wi, int& ring, int& azimuth) {
  const float t = ringCoordinate(wi);
  ring = std::min(int(t + 0.5f), kBtfRingCount - 1);
  const int n = btfRingSize(ring);
  azimuth = int(azimuthTurns(wi) * float(n) + 0.5f);
  if (azimuth >= n) azimuth -= n;
}

inline int nearestView(const glm::vec3& wo, int rings) {
  int ring, azimuth;
  lightCell(wo, ring, azimuth);
  if (ring >= rings) {
    ring = rings - 1;
    azimuth = int(azimuthTurns(wo) * float(btfRingSize(ring)) + 0.5f);
    if (azimuth >= btfRingSize(ring)) azimuth -= btfRingSize(ring);
  }
  return btfDirectionIndex(ring, azimuth);
}

}  // namespace

// Per-ring CDFs of one light slice and the ring marginal.
struct BtfMaterial::LightTables {
  std::array<const float*, kBtfRingCount> cdf;
  std::array<float, kBtfRingCount + 1> ring_cdf;
  double total = 0;
  // Storage for the generic path (the VQ path points into the codebook instead).
  std::array<float, kBtfDirectionCount + kBtfRingCount> cdf_storage;
  // On other sets (btf_scattered_directions.h): the view's light triangulation and sum_l f_l W_l
  // (hemisphere_triangulation.h); from the codebooks of a VqBtf whose views share their lights,
  // the slice's rings with the entries weighted by W (VqBtf::weightedRings) and their marginal,
  // else every light's f and the CDF of f_l W_l. The vectors live in the per-thread cache and keep
  // their memory.
  const HemisphereTriangulation* triangulation = nullptr;
  float weighted_total = 0;
  bool weighted = false;    // from the weighted codebook: slice and ring_marginal below
  VqBtf::SliceCode slice{};
  const float* ring_marginal = nullptr;  // ringCount() + 1 entries
  std::vector<VqBtf::LightRing> rings;
  std::vector<float> rings_cdf, light_luminance, light_cdf, light_mass;
};

namespace {
// The density of a draw in triangle t (hemisphere_triangulation.h): the one expression sample
// and pdf share, so that they agree bit for bit. `f(l)` is light l's luminance.
template <class Luminance>
float triangleDensity(const HemisphereTriangulation& lights, int t, float total, const Luminance& f) {
  const std::array<int, 3>& d = lights.triangleDirections(t);
  return lights.triangleDensityFactor(t) * (f(d[0]) + f(d[1]) + f(d[2])) / total;
}
}  // namespace

BtfMaterial::BtfMaterial(std::shared_ptr<const BtfLookup> btf, BtfTexelFilter filter, std::string name)
    : btf_(std::move(btf)), vq_(nullptr), filter_(filter), name_(std::move(name)) {
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id++;
  if (!btf_) throw Error("BtfMaterial needs a BTF");
  vq_ = dynamic_cast<const VqBtf*>(btf_.get());
  width_ = btf_->lookupWidth();
  height_ = btf_->lookupHeight();
  if (width_ < 1 || height_ < 1) throw Error("BtfMaterial: the BTF has no texels");
  const BtfViewSet& views = btf_->lookupViews();
  if (!views.directions().indexedAsUbo2003()) {
    view_rings_ = 0;
    scattered_ = std::make_shared<const BtfScatteredDirections>(views);
    // From the codebooks when all views share one light triangulation: the level-1 entries
    // weighted by the lights' triangle weights, once (the per-entry equivalent of the rings' sums).
    if (vq_ && scattered_->sharedLights()) {
      const HemisphereTriangulation& lights = *scattered_->sharedLights();
      std::vector<float> weight(std::size_t(lights.directionCount()));
      for (std::size_t l = 0; l < weight.size(); ++l) weight[l] = lights.directionWeight(int(l));
      weighted_rings_ = std::make_shared<const VqBtf::WeightedRings>(vq_->weightedRings(weight));
    }
    return;
  }
  // Interpolation over wo needs whole rings from the pole; a BTF of other views (a few scattered
  // ones) has no sensible value between them.
  view_rings_ = views.completeRingsFromPole();
  if (view_rings_ == 0 || views.count() != btfRingStart(view_rings_ - 1) + btfRingSize(view_rings_ - 1))
    throw Error("BtfMaterial needs the views of whole rings from the pole (e.g. all views up to theta 45); the BTF holds " +
                views.describe());
}

Rgb BtfMaterial::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return Rgb();
  // The (view, light, weight) triples with weight > 0, shared by the texels.
  std::array<int, 16> views, lights;
  std::array<float, 16> weights;
  int count = 0;
  if (scattered_) {
    count = scattered_->stencil(scattered_->viewStencil(wo), wi, -1, views.data(), lights.data(), weights.data());
  } else {
    const DirectionStencil light = stencil(wi), view = stencil(wo, view_rings_);
    for (int v = 0; v < view.count; ++v)
      for (int l = 0; l < light.count; ++l) {
        const float w = view.weight[std::size_t(v)] * light.weight[std::size_t(l)];
        if (w == 0.0f) continue;
        views[std::size_t(count)] = view.index[std::size_t(v)];
        lights[std::size_t(count)] = light.index[std::size_t(l)];
        weights[std::size_t(count++)] = w;
      }
  }
  return interpolate(views.data(), lights.data(), weights.data(), count, uv);
}

Rgb BtfMaterial::interpolate(const int* views, const int* lights, const float* weights, int count, glm::vec2 uv) const {
  auto texelValue = [&](int x, int y) {
    if (vq_) return vq_->weightedSum(x, y, views, lights, weights, count);
    Rgb sum;
    for (int k = 0; k < count; ++k) sum += weights[k] * btf_->value(x, y, views[k], lights[k]);
    return sum;
  };
  if (filter_ == BtfTexelFilter::Nearest || (width_ == 1 && height_ == 1))
    return texelValue(nearestTexel(uv.x, width_), nearestTexel(uv.y, height_));
  const float x = uv.x * float(width_) - 0.5f, y = uv.y * float(height_) - 0.5f;
  const float fx0 = std::floor(x), fy0 = std::floor(y);
  const float fx = x - fx0, fy = y - fy0;
  const int x0 = wrap(int(fx0), width_), y0 = wrap(int(fy0), height_);
  const int x1 = x0 + 1 == width_ ? 0 : x0 + 1, y1 = y0 + 1 == height_ ? 0 : y0 + 1;
  Rgb sum;
  if ((1.0f - fx) * (1.0f - fy) != 0.0f) sum += (1.0f - fx) * (1.0f - fy) * texelValue(x0, y0);
  if (fx * (1.0f - fy) != 0.0f) sum += fx * (1.0f - fy) * texelValue(x1, y0);
  if ((1.0f - fx) * fy != 0.0f) sum += (1.0f - fx) * fy * texelValue(x0, y1);
  if (fx * fy != 0.0f) sum += fx * fy * texelValue(x1, y1);
  return sum;
}

const BtfMaterial::LightTables& BtfMaterial::lightTables(int view, glm::vec2 uv) const {
  const int x = nearestTexel(uv.x, width_), y = nearestTexel(uv.y, height_);
  // One slice's tables per thread are kept: pdf is mostly called for the same wo and uv as the
  // sample before it (MIS, chi-square quadrature), so the slice is decoded once. Keyed by a
  // per-material id, not the address, which a later material may reuse.
  thread_local struct {
    std::uint64_t id = 0;
    int x = -1, y = -1, view = -1;
    LightTables tables;
  } cache;
  if (cache.id == id_ && cache.x == x && cache.y == y && cache.view == view) return cache.tables;
  cache.id = id_;
  cache.x = x;
  cache.y = y;
  cache.view = view;
  LightTables& tables = cache.tables;
  if (scattered_) {
    const HemisphereTriangulation& lights = scattered_->lights(view);
    tables.triangulation = &lights;
    if (weighted_rings_) {
      // The rings' marginal: the level-2 entry's, precomputed (VqBtf::weightedRings); with one
      // level, from the rings' masses scale x (sum over the entry of value x W).
      tables.weighted = true;
      tables.slice = vq_->sliceCode(x, y, view);
      if (vq_->options().levels >= 2) {
        const VqBtf::RingMarginal marginal = vq_->ringMarginal(tables.slice, *weighted_rings_);
        tables.ring_marginal = marginal.cdf;
        tables.weighted_total = marginal.total;
        tables.total = double(marginal.total);
        return tables;
      }
      const int R = vq_->ringLayout().ringCount();
      tables.rings.resize(std::size_t(R));
      vq_->lightRings(x, y, view, tables.rings, weighted_rings_.get());
      tables.light_mass.resize(std::size_t(R));
      for (int r = 0; r < R; ++r)
        tables.light_mass[std::size_t(r)] = std::max(tables.rings[std::size_t(r)].scale * tables.rings[std::size_t(r)].sum, 0.0f);
      tables.rings_cdf.resize(std::size_t(R) + 1);
      tables.weighted_total = float(buildCdf1D(tables.light_mass, tables.rings_cdf) * double(R));
      tables.total = double(tables.weighted_total);
      tables.ring_marginal = tables.rings_cdf.data();
      return tables;
    }
    tables.weighted = false;
    // Every light's luminance, and the CDF of f_l W_l.
    const std::size_t n = std::size_t(btf_->lookupViews().directions().lightCount(view));
    tables.light_luminance.resize(n);
    tables.light_mass.resize(n);
    for (std::size_t l = 0; l < n; ++l) {
      tables.light_luminance[l] = std::max(btf_->value(x, y, view, int(l)).luminance(), 0.0f);
      tables.light_mass[l] = tables.light_luminance[l] * lights.directionWeight(int(l));
    }
    tables.light_cdf.resize(n + 1);
    tables.weighted_total = float(buildCdf1D(tables.light_mass, tables.light_cdf) * double(n));
    tables.total = double(tables.weighted_total);
    return tables;
  }
  const RingCells& cells = ringCells();
  std::array<float, kBtfRingCount> mass;
  if (vq_) {
    std::array<VqBtf::LightRing, kBtfRingCount> rings;
    vq_->lightRings(x, y, view, rings);
    for (int r = 0; r < kBtfRingCount; ++r) {
      tables.cdf[std::size_t(r)] = rings[std::size_t(r)].cdf;
      mass[std::size_t(r)] = std::max(rings[std::size_t(r)].scale * rings[std::size_t(r)].sum, 0.0f) *
                             cells.cos_ring[std::size_t(r)] * cells.cell_solid_angle[std::size_t(r)];
    }
  } else {
    std::array<float, kBtfDirectionCount> lum;
    for (int l = 0; l < kBtfDirectionCount; ++l) lum[std::size_t(l)] = std::max(btf_->value(x, y, view, l).luminance(), 0.0f);
    for (int r = 0; r < kBtfRingCount; ++r) {
      const std::size_t n = std::size_t(btfRingSize(r)), start = std::size_t(btfRingStart(r));
      float* cdf = &tables.cdf_storage[start + std::size_t(r)];
      const double mean = buildCdf1D(std::span<const float>(&lum[start], n), std::span<float>(cdf, n + 1));
      tables.cdf[std::size_t(r)] = cdf;
      mass[std::size_t(r)] = float(mean * double(n)) * cells.cos_ring[std::size_t(r)] * cells.cell_solid_angle[std::size_t(r)];
    }
  }
  tables.total = buildCdf1D(mass, tables.ring_cdf);
  return tables;
}

std::optional<BsdfSample> BtfMaterial::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (scattered_) {
    // The draw's view stencil and light triangle serve the weight's interpolation too (what
    // eval(wi, wo, uv) would locate again): the same triples, so the same f.
    if (!(wo.z > 0.0f)) return std::nullopt;
    const HemisphereTriangulation::Stencil view = scattered_->viewStencil(wo);
    // The weight's interpolation reads these views' slices after the draw: their codes are
    // fetched now, while the draw computes (nearest texel; the bilinear filter's other texels
    // are left to the cache).
    if (vq_)
      for (int k = 0; k < view.count; ++k)
        vq_->prefetch(vq_->sliceCode(nearestTexel(uv.x, width_), nearestTexel(uv.y, height_), view.index[std::size_t(k)]));
    const std::optional<ScatteredDraw> d = drawScattered(view, uv, u);
    if (!d) return std::nullopt;
    std::array<int, 16> views, lights;
    std::array<float, 16> weights;
    const int count = scattered_->stencil(view, d->wi, scattered_->sharedLights() ? d->triangle : -1, views.data(),
                                          lights.data(), weights.data());
    const Rgb f = interpolate(views.data(), lights.data(), weights.data(), count, uv);
    return BsdfSample{d->wi, f * (d->wi.z / d->pdf), d->pdf};
  }
  const std::optional<DirectionSample> d = sampleDirection(wo, uv, u);
  if (!d) return std::nullopt;
  const Rgb f = eval(d->wi, wo, uv);
  return BsdfSample{d->wi, f * (d->wi.z / d->pdf), d->pdf};
}

std::optional<BtfMaterial::ScatteredDraw> BtfMaterial::drawScattered(const HemisphereTriangulation::Stencil& view,
                                                                     glm::vec2 uv, glm::vec2 u) const {
  const LightTables& tables = lightTables(BtfScatteredDirections::samplingView(view), uv);
  if (!(tables.total > 0)) return std::nullopt;
  // A light with probability f_l W_l / total (its ring, then its place in the ring's weighted
  // entry), one of its triangles by its share, a point uniform in that triangle.
  const HemisphereTriangulation& lights = *tables.triangulation;
  int light;
  float u_point;
  if (tables.weighted) {
    const BtfRingLayout& layout = vq_->ringLayout();
    const DiscreteSample ring =
        sampleDiscrete(std::span<const float>(tables.ring_marginal, std::size_t(layout.ringCount()) + 1), u.x);
    const int r = int(ring.index);
    const VqBtf::LightRing entry = vq_->lightRing(tables.slice, r, *weighted_rings_);
    const DiscreteSample place = sampleDiscrete(std::span<const float>(entry.cdf, std::size_t(layout.size(r)) + 1), ring.remapped);
    light = layout.light(r, int(place.index));
    u_point = place.remapped;
  } else {
    const DiscreteSample l = sampleDiscrete(tables.light_cdf, u.x);
    light = int(l.index);
    u_point = l.remapped;
  }
  const DiscreteSample share = sampleDiscrete(lights.incidentCdf(light), u.y);
  const int t = lights.incidentTriangles(light)[share.index];
  const glm::vec3 wi = lights.sampleTriangle(t, {u_point, share.remapped});
  // A direction on an edge, within float rounding, may be located in the neighbour triangle: it
  // is kept only where pdf() attributes it to the triangle it was drawn from, so that pdf is the
  // density of what is returned (the set dropped has measure zero).
  if (!(wi.z > 0.0f) || !lights.locatesIn(t, wi)) return std::nullopt;
  const float density = scatteredDensity(tables, t);
  if (!(density > 0.0f)) return std::nullopt;
  return ScatteredDraw{wi, density, t};
}

std::optional<BtfMaterial::DirectionSample> BtfMaterial::sampleDirection(const glm::vec3& wo, glm::vec2 uv,
                                                                         glm::vec2 u) const {
  if (!(wo.z > 0.0f)) return std::nullopt;
  if (scattered_) {
    const std::optional<ScatteredDraw> d = drawScattered(scattered_->viewStencil(wo), uv, u);
    if (!d) return std::nullopt;
    return DirectionSample{d->wi, d->pdf};
  }
  const LightTables& tables = lightTables(nearestView(wo, view_rings_), uv);
  if (!(tables.total > 0)) return std::nullopt;
  const DiscreteSample ring_choice = sampleDiscrete(tables.ring_cdf, u.x);
  const int r = int(ring_choice.index), n = btfRingSize(r);
  const std::span<const float> cdf(tables.cdf[std::size_t(r)], std::size_t(n) + 1);
  const DiscreteSample azimuth_choice = sampleDiscrete(cdf, u.y);
  const RingCells& cells = ringCells();
  const float density = ring_choice.probability * azimuth_choice.probability / cells.cell_solid_angle[std::size_t(r)];
  if (!(density > 0.0f)) return std::nullopt;
  // Uniform in solid angle inside the cell: cos theta uniform over the band, phi over the cell.
  const float cos_theta = cells.cos_top[std::size_t(r)] +
                          (cells.cos_bottom[std::size_t(r)] - cells.cos_top[std::size_t(r)]) * ring_choice.remapped;
  const float turns = n == 1 ? azimuth_choice.remapped
                             : (float(azimuth_choice.index) - 0.5f + azimuth_choice.remapped) / float(n);
  const float sin_theta = safeSqrt(1.0f - cos_theta * cos_theta);
  float cos_phi, sin_phi;
  cosSinTurns(turns, cos_phi, sin_phi);  // turns > -1/12 (half of ring 1's cell)
  const glm::vec3 wi(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
  if (!(wi.z > 0.0f)) return std::nullopt;
  return DirectionSample{wi, density};
}

float BtfMaterial::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  if (scattered_) {
    const LightTables& tables = lightTables(BtfScatteredDirections::samplingView(scattered_->viewStencil(wo)), uv);
    if (!(tables.total > 0)) return 0.0f;
    const int t = tables.triangulation->locate(wi);
    return t < 0 ? 0.0f : scatteredDensity(tables, t);
  }
  const LightTables& tables = lightTables(nearestView(wo, view_rings_), uv);
  if (!(tables.total > 0)) return 0.0f;
  int r, a;
  lightCell(wi, r, a);
  const float* cdf = tables.cdf[std::size_t(r)];
  const float p_ring = tables.ring_cdf[std::size_t(r) + 1] - tables.ring_cdf[std::size_t(r)];
  const float p_azimuth = cdf[a + 1] - cdf[a];
  return p_ring * p_azimuth / ringCells().cell_solid_angle[std::size_t(r)];
}

float BtfMaterial::scatteredDensity(const LightTables& tables, int t) const {
  if (tables.weighted)
    return triangleDensity(*tables.triangulation, t, tables.weighted_total,
                           [&](int l) { return vq_->luminance(tables.slice, l); });
  return triangleDensity(*tables.triangulation, t, tables.weighted_total,
                         [&](int l) { return tables.light_luminance[std::size_t(l)]; });
}

namespace {

// The BTF of a "btf" parameter set: an image folder, or a .btfz file (one material of a database
// by "material").
std::shared_ptr<const BtfSource> btfSourceParam(const MaterialParams& p) {
  const std::filesystem::path file = p.existingPath("file");
  const std::string material = p.has("material") ? p.string("material") : std::string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    if (!material.empty()) p.fail("material", "names a material of a .btfz database only");
    return std::make_shared<BtfImageFolder>(BtfImageFolder::open(file));
  }
  if (isBonnBtfFile(file)) {
    if (!material.empty()) p.fail("material", "names a material of a .btfz database only");
    return std::make_shared<BonnBtf>(BonnBtf::open(file));
  }
  return readCompressedBtf(file, material);
}

}  // namespace

// "mapping", "uv_scale" and "axis" place the texture on a shape; the scene loader reads them.
BTF_REGISTER_MATERIAL(btf, {.name = "btf",
                            .summary = "a BTF: an image folder, a Bonn .btf file or a compressed .btfz (VQ or "
                                       "factor form; one material of a database)",
                            .keys = {"file", "material", "filter", "mapping", "uv_scale", "axis"},
                            .formats = {{.description = "image-folder BTF", .folder = true},
                                        {.description = "Bonn BTF file (.btf: DFMF, FMF or PVF)",
                                         .extensions = {".btf"},
                                         .sniff = [](std::span<const unsigned char> head, std::uintmax_t) {
                                           return isBonnBtfSignature(head.data(), head.size());
                                         }},
                                        {.description = "compressed BTF (.btfz: VQ or factor form)",
                                         .extensions = {".btfz"},
                                         .sniff = [](std::span<const unsigned char> head, std::uintmax_t) {
                                           return isCompressedBtfFormat(containerFormatOf(head));
                                         }}},
                            .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                              BtfTexelFilter filter = BtfTexelFilter::Bilinear;
                              if (p.has("filter")) {
                                const std::string f = p.string("filter");
                                if (f == "nearest") filter = BtfTexelFilter::Nearest;
                                else if (f != "bilinear") p.fail("filter", "expected bilinear or nearest");
                              }
                              std::shared_ptr<const BtfSource> source = btfSourceParam(p);
                              std::shared_ptr<const BtfLookup> lookup = std::dynamic_pointer_cast<const BtfLookup>(source);
                              if (!lookup) lookup = std::make_shared<BtfData>(BtfData::copyOf(*source));
                              const std::filesystem::path file = p.path("file");
                              const std::string label = file.filename().string() +
                                                        (p.has("material") ? ":" + p.string("material") : std::string());
                              return std::make_shared<BtfMaterial>(std::move(lookup), filter, "btf(" + label + ")");
                            },
                            .btf = btfSourceParam});

}  // namespace btf
