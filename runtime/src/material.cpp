// Material: the 81-direction set's interpolation and sampler of material/btf_material.cpp, op for
// op, over a Codec (see that file's header comment for what eval and sample compute and why).
#include "btf_runtime/material.h"

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "codec.h"
#include "btf_runtime/file_layout.h"

namespace btfrt {

using namespace detail;

namespace {

inline float ringCoordinate(const Vec3& w) {
  return fastAtan2Turns(std::sqrt(w.x * w.x + w.y * w.y), w.z) * (360.0f / kRingStepDeg);
}
inline float azimuthTurns(const Vec3& w) {
  float p = fastAtan2Turns(w.y, w.x);
  if (p < 0.0f) p += 1.0f;
  return p >= 1.0f ? 0.0f : p;
}

// Up to 4 measured directions and weights interpolating a direction.
struct DirectionStencil {
  int count = 0;
  std::array<int, 4> index{};
  std::array<float, 4> weight{};
  void add(int ring, float turns, float w) {
    const int n = kRingSizes[std::size_t(ring)];
    if (n == 1) {
      index[std::size_t(count)] = kRingStarts[std::size_t(ring)];
      weight[std::size_t(count++)] = w;
      return;
    }
    const float a = turns * float(n);
    int a0 = int(a);
    const float g = a - float(a0);
    if (a0 >= n) a0 -= n;
    const int a1 = a0 + 1 == n ? 0 : a0 + 1;
    index[std::size_t(count)] = kRingStarts[std::size_t(ring)] + a0;
    weight[std::size_t(count++)] = w * (1.0f - g);
    index[std::size_t(count)] = kRingStarts[std::size_t(ring)] + a1;
    weight[std::size_t(count++)] = w * g;
  }
};
DirectionStencil stencil(const Vec3& w, int rings = kRingCount) {
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

inline void lightCell(const Vec3& wi, int& ring, int& azimuth) {
  const float t = ringCoordinate(wi);
  ring = std::min(int(t + 0.5f), kRingCount - 1);
  const int n = kRingSizes[std::size_t(ring)];
  azimuth = int(azimuthTurns(wi) * float(n) + 0.5f);
  if (azimuth >= n) azimuth -= n;
}

inline int nearestView(const Vec3& wo, int rings) {
  int ring, azimuth;
  lightCell(wo, ring, azimuth);
  if (ring >= rings) {
    ring = rings - 1;
    azimuth = int(azimuthTurns(wo) * float(kRingSizes[std::size_t(ring)]) + 0.5f);
    if (azimuth >= kRingSizes[std::size_t(ring)]) azimuth -= kRingSizes[std::size_t(ring)];
  }
  return kRingStarts[std::size_t(ring)] + azimuth;
}

// The light slice's sampling tables (BtfMaterial::LightTables on the 81-direction set), on the
// caller's stack.
struct LightTables {
  Codec::Rings rings;
  std::array<float, kRingCount + 1> ring_cdf;
  double total = 0;
  std::array<float, kDirectionCount + kRingCount> storage;
};
void lightTables(const Codec& codec, int view, float u, float v, LightTables& tables) {
  const int x = nearestTexel(u, codec.width), y = nearestTexel(v, codec.height);
  codec.lightRings(x, y, view, tables.rings, tables.storage.data());
  const RingCells& cells = ringCells();
  std::array<float, kRingCount> mass;
  for (int r = 0; r < kRingCount; ++r)
    mass[std::size_t(r)] =
        tables.rings.luminance[std::size_t(r)] * cells.cos_ring[std::size_t(r)] * cells.cell_solid_angle[std::size_t(r)];
  tables.total = buildCdf1D(mass.data(), mass.size(), tables.ring_cdf.data());
}

}  // namespace

Material::Material(std::shared_ptr<const Codec> codec, TexelFilter filter)
    : codec_(std::move(codec)), filter_(filter), width_(codec_->width), height_(codec_->height),
      view_rings_(codec_->view_rings) {}

Material Material::fromBytes(const unsigned char* data, std::size_t size, const std::string& what, TexelFilter filter) {
  const std::uint32_t one = 1;
  unsigned char first_byte;
  std::memcpy(&first_byte, &one, 1);
  if (first_byte != 1) throw std::runtime_error(what + ": the runtime file is little-endian; this host is not");
  if (size < file::kHeaderBytes || std::memcmp(data, file::kMagic, sizeof file::kMagic) != 0)
    throw std::runtime_error(what + ": not a libbtf runtime file (btf export --runtime writes them)");
  file::Header h;
  std::memcpy(&h, data, sizeof h);
  if (h.version != file::kVersion)
    throw std::runtime_error(what + ": runtime file version " + std::to_string(h.version) + ", this runtime reads " +
                             std::to_string(file::kVersion));
  if (h.file_bytes != size)
    throw std::runtime_error(what + ": " + std::to_string(size) + " bytes, the header says " + std::to_string(h.file_bytes) +
                             " (truncated?)");
  if (h.codec == file::kCodecVq) return Material(readVqCodec(data, size, what), filter);
  throw std::runtime_error(what + ": unknown codec " + std::to_string(h.codec));
}

Material Material::open(const std::string& path, TexelFilter filter) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(path + ": cannot be opened for reading");
  const std::streamoff size = in.tellg();
  if (size < 0) throw std::runtime_error(path + ": cannot be read");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (!bytes.empty() && !in.read(reinterpret_cast<char*>(bytes.data()), size)) throw std::runtime_error(path + ": read failed");
  return fromBytes(bytes.data(), bytes.size(), path, filter);
}

Rgb Material::value(int x, int y, int view, int light) const { return codec_->value(x, y, view, light); }

Rgb Material::eval(const Vec3& wi, const Vec3& wo, float u, float v) const {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return Rgb();
  std::array<int, 16> views, lights;
  std::array<float, 16> weights;
  int count = 0;
  const DirectionStencil light = stencil(wi), view = stencil(wo, view_rings_);
  for (int i = 0; i < view.count; ++i)
    for (int l = 0; l < light.count; ++l) {
      const float w = view.weight[std::size_t(i)] * light.weight[std::size_t(l)];
      if (w == 0.0f) continue;
      views[std::size_t(count)] = view.index[std::size_t(i)];
      lights[std::size_t(count)] = light.index[std::size_t(l)];
      weights[std::size_t(count++)] = w;
    }
  return interpolate(views.data(), lights.data(), weights.data(), count, u, v);
}

Rgb Material::interpolate(const int* views, const int* lights, const float* weights, int count, float u, float v) const {
  const Codec& c = *codec_;
  auto texelValue = [&](int x, int y) { return c.weightedSum(x, y, views, lights, weights, count); };
  if (filter_ == TexelFilter::Nearest || (width_ == 1 && height_ == 1))
    return texelValue(nearestTexel(u, width_), nearestTexel(v, height_));
  const float x = u * float(width_) - 0.5f, y = v * float(height_) - 0.5f;
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

bool Material::sampleDirection(const Vec3& wo, float u, float v, float u1, float u2, Vec3& wi, float& pdf) const {
  if (!(wo.z > 0.0f)) return false;
  LightTables tables;
  lightTables(*codec_, nearestView(wo, view_rings_), u, v, tables);
  if (!(tables.total > 0)) return false;
  const DiscreteSample ring_choice = sampleDiscrete(tables.ring_cdf.data(), kRingCount, u1);
  const int r = int(ring_choice.index), n = kRingSizes[std::size_t(r)];
  const DiscreteSample azimuth_choice = sampleDiscrete(tables.rings.cdf[std::size_t(r)], std::size_t(n), u2);
  const RingCells& cells = ringCells();
  const float density = ring_choice.probability * azimuth_choice.probability / cells.cell_solid_angle[std::size_t(r)];
  if (!(density > 0.0f)) return false;
  const float cos_theta = cells.cos_top[std::size_t(r)] +
                          (cells.cos_bottom[std::size_t(r)] - cells.cos_top[std::size_t(r)]) * ring_choice.remapped;
  const float turns = n == 1 ? azimuth_choice.remapped
                             : (float(azimuth_choice.index) - 0.5f + azimuth_choice.remapped) / float(n);
  const float sin_theta = safeSqrt(1.0f - cos_theta * cos_theta);
  float cos_phi, sin_phi;
  cosSinTurns(turns, cos_phi, sin_phi);
  const Vec3 w{sin_theta * cos_phi, sin_theta * sin_phi, cos_theta};
  if (!(w.z > 0.0f)) return false;
  wi = w;
  pdf = density;
  return true;
}

bool Material::sample(const Vec3& wo, float u, float v, float u1, float u2, Sample& out) const {
  Vec3 wi;
  float pdf;
  if (!sampleDirection(wo, u, v, u1, u2, wi, pdf)) return false;
  const Rgb f = eval(wi, wo, u, v);
  out = {wi, f * (wi.z / pdf), pdf};
  return true;
}

float Material::pdf(const Vec3& wi, const Vec3& wo, float u, float v) const {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  LightTables tables;
  lightTables(*codec_, nearestView(wo, view_rings_), u, v, tables);
  if (!(tables.total > 0)) return 0.0f;
  int r, a;
  lightCell(wi, r, a);
  const float* cdf = tables.rings.cdf[std::size_t(r)];
  const float p_ring = tables.ring_cdf[std::size_t(r) + 1] - tables.ring_cdf[std::size_t(r)];
  const float p_azimuth = cdf[a + 1] - cdf[a];
  return p_ring * p_azimuth / ringCells().cell_solid_angle[std::size_t(r)];
}

}  // namespace btfrt
