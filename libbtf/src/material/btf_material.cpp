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
  // On other sets (btf_scattered_directions.h): the view's light triangulation and the CDF of its
  // triangles.
  const HemisphereTriangulation* triangulation = nullptr;
  std::vector<float> triangle_cdf;
  std::vector<float> light_luminance, triangle_mass;  // work buffers, kept to reuse their memory
};

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
    count = scattered_->stencil(wi, wo, views.data(), lights.data(), weights.data());
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
  auto texelValue = [&](int x, int y) {
    if (vq_) return vq_->weightedSum(x, y, views.data(), lights.data(), weights.data(), count);
    Rgb sum;
    for (int k = 0; k < count; ++k)
      sum += weights[std::size_t(k)] * btf_->value(x, y, views[std::size_t(k)], lights[std::size_t(k)]);
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

const BtfMaterial::LightTables& BtfMaterial::lightTables(const glm::vec3& wo, glm::vec2 uv) const {
  const int x = nearestTexel(uv.x, width_), y = nearestTexel(uv.y, height_);
  const int view = scattered_ ? scattered_->nearestView(wo) : nearestView(wo, view_rings_);
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
    // Triangle masses: solid angle x cos theta at the centre x the mean luminance of the corners.
    const HemisphereTriangulation& lights = scattered_->lights(view);
    tables.triangulation = &lights;
    // The buffers live in the per-thread cache: a sampler rebuilds these tables for every new wo
    // or texel, and allocates nothing once they have grown.
    std::vector<float>& lum = tables.light_luminance;
    lum.resize(std::size_t(btf_->lookupViews().directions().lightCount(view)));
    for (std::size_t l = 0; l < lum.size(); ++l) lum[l] = std::max(btf_->value(x, y, view, int(l)).luminance(), 0.0f);
    std::vector<float>& mass = tables.triangle_mass;
    mass.resize(std::size_t(lights.triangleCount()));
    for (int t = 0; t < lights.triangleCount(); ++t) {
      const auto& d = lights.triangleDirections(t);
      const float mean = (lum[std::size_t(d[0])] + lum[std::size_t(d[1])] + lum[std::size_t(d[2])]) / 3.0f;
      mass[std::size_t(t)] = mean * std::max(lights.triangleCosTheta(t), 0.0f) * lights.triangleSolidAngle(t);
    }
    tables.triangle_cdf.resize(mass.size() + 1);
    tables.total = buildCdf1D(mass, tables.triangle_cdf);
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
  const std::optional<DirectionSample> d = sampleDirection(wo, uv, u);
  if (!d) return std::nullopt;
  const Rgb f = eval(d->wi, wo, uv);
  return BsdfSample{d->wi, f * (d->wi.z / d->pdf), d->pdf};
}

std::optional<BtfMaterial::DirectionSample> BtfMaterial::sampleDirection(const glm::vec3& wo, glm::vec2 uv,
                                                                         glm::vec2 u) const {
  if (!(wo.z > 0.0f)) return std::nullopt;
  const LightTables& tables = lightTables(wo, uv);
  if (!(tables.total > 0)) return std::nullopt;
  if (scattered_) {
    const DiscreteSample t = sampleDiscrete(tables.triangle_cdf, u.x);
    const HemisphereTriangulation& lights = *tables.triangulation;
    const float density = t.probability / lights.triangleSolidAngle(int(t.index));
    const glm::vec3 wi = lights.sampleTriangle(int(t.index), {t.remapped, u.y});
    // A direction on an edge, within float rounding, may be located in the neighbour triangle: it
    // is kept only where pdf() attributes it to the triangle it was drawn from, so that pdf is the
    // density of what is returned (the set dropped has measure zero).
    if (!(density > 0.0f) || !(wi.z > 0.0f) || lights.locate(wi) != int(t.index)) return std::nullopt;
    return DirectionSample{wi, density};
  }
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
  const LightTables& tables = lightTables(wo, uv);
  if (!(tables.total > 0)) return 0.0f;
  if (scattered_) {
    const int t = tables.triangulation->locate(wi);
    if (t < 0) return 0.0f;
    return (tables.triangle_cdf[std::size_t(t) + 1] - tables.triangle_cdf[std::size_t(t)]) /
           tables.triangulation->triangleSolidAngle(t);
  }
  int r, a;
  lightCell(wi, r, a);
  const float* cdf = tables.cdf[std::size_t(r)];
  const float p_ring = tables.ring_cdf[std::size_t(r) + 1] - tables.ring_cdf[std::size_t(r)];
  const float p_azimuth = cdf[a + 1] - cdf[a];
  return p_ring * p_azimuth / ringCells().cell_solid_angle[std::size_t(r)];
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
