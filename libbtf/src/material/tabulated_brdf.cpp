#include "btf/material/tabulated_brdf.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "btf/core/error.h"
#include "btf/core/fast_atan.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/io/image.h"
#include "btf/io/merl_exr_stack.h"
#include "btf/material/registry.h"
#include "cosine_sampling.h"
#include "merl_resolution.h"
#include "table_coordinates.h"
#include "table_params.h"

namespace btf {
namespace {

constexpr std::size_t kCells = MerlTable::kEntriesPerChannel;

inline int nearestIndex(float u, int n) { return std::min(int(u + 0.5f), n - 1); }

// --- Nearest measured cell, for holes -------------------------------------------------------

// For one phi_d row with at least one measured cell: for every k, the nearest measured k'
// (circular distance, period kNp; ties go to k - d).
void nearestInRow(const std::uint8_t* measured, std::int16_t* nearest) {
  int first = 0;
  while (!measured[first]) ++first;
  std::int16_t prev[kNp], next[kNp];
  for (int step = 0, last = first; step < kNp; ++step) {
    const int k = (first + step) % kNp;
    if (measured[k]) last = k;
    prev[k] = std::int16_t(last);
  }
  for (int step = 0, last = first; step < kNp; ++step) {
    const int k = ((first - step) % kNp + kNp) % kNp;
    if (measured[k]) last = k;
    next[k] = std::int16_t(last);
  }
  for (int k = 0; k < kNp; ++k) {
    const int d_prev = (k - prev[k] + kNp) % kNp, d_next = (next[k] - k + kNp) % kNp;
    nearest[k] = d_prev <= d_next ? prev[k] : next[k];
  }
}

// The index nearest to `at` among 0..n-1 with has[index] (searching outwards, ties to the lower),
// or -1.
int nearestWith(const std::vector<std::uint8_t>& has, int offset, int n, int at) {
  for (int d = 0; d < n; ++d) {
    if (at - d >= 0 && has[offset + at - d]) return at - d;
    if (at + d < n && has[offset + at + d]) return at + d;
  }
  return -1;
}

}  // namespace

TabulatedBrdf::TabulatedBrdf(std::shared_ptr<const MerlTable> table, TableLookup lookup)
    : table_(std::move(table)), lookup_(lookup), cells_(kCells, Cell{Rgb(0.0f), 0.0f}) {
  if (!table_) throw Error("TabulatedBrdf: no table given");
  if (table_->values.size() != 3 * kCells)
    throw Error("TabulatedBrdf: the table holds " + std::to_string(table_->values.size()) + " values, expected " +
                std::to_string(3 * kCells));

  std::vector<std::uint8_t> measured(kCells), row_has(kNh * kNd, 0), slab_has(kNh, 0);
  for (std::size_t c = 0; c < kCells; ++c) {
    measured[c] = table_->isMeasured(c);
    if (measured[c]) row_has[c / kNp] = slab_has[c / (kNp * kNd)] = 1;
  }
  if (std::none_of(slab_has.begin(), slab_has.end(), [](std::uint8_t b) { return b != 0; })) return;

  std::vector<std::int16_t> nearest_k(kCells, 0);
  for (int row = 0; row < kNh * kNd; ++row)
    if (row_has[row]) nearestInRow(&measured[std::size_t(row) * kNp], &nearest_k[std::size_t(row) * kNp]);

  for (int i = 0; i < kNh; ++i) {
    const int src_i = nearestWith(slab_has, 0, kNh, i);
    for (int j = 0; j < kNd; ++j) {
      // The row to take values from: this one if it has any measurement, else the nearest in theta_d
      // (within the nearest theta_h slab that has one).
      const int src_j = nearestWith(row_has, src_i * kNd, kNd, j);
      const std::size_t src_row = std::size_t(src_i) * kNd + src_j;
      for (int k = 0; k < kNp; ++k) {
        const std::size_t c = MerlTable::index(i, j, k);
        const std::size_t src = src_row * kNp + nearest_k[src_row * kNp + k];
        cells_[c] = {table_->reflectance(measured[c] ? c : src), measured[c] ? 1.0f : 0.0f};
      }
    }
  }
}

Rgb TabulatedBrdf::evalNearest(float u_h, float u_d, float u_p) const {
  int k = int(u_p + 0.5f);
  if (k >= kNp) k -= kNp;
  return cells_[MerlTable::index(nearestIndex(u_h, kNh), nearestIndex(u_d, kNd), k)].f;
}

Rgb TabulatedBrdf::evalTruncated(float u_h, float u_d, float u_p) const {
  int k = int(u_p);
  if (k >= kNp) k -= kNp;
  return cells_[MerlTable::index(std::min(int(u_h), kNh - 1), std::min(int(u_d), kNd - 1), k)].f;
}

Rgb TabulatedBrdf::evalInterpolated(float u_h, float u_d, float u_p) const {
  const int i0 = std::min(int(u_h), kNh - 1), j0 = std::min(int(u_d), kNd - 1);
  const int i1 = std::min(i0 + 1, kNh - 1), j1 = std::min(j0 + 1, kNd - 1);
  const float th = std::min(u_h - float(i0), 1.0f), td = std::min(u_d - float(j0), 1.0f);
  int k0 = int(u_p);
  const float tp = u_p - float(k0);
  if (k0 >= kNp) k0 -= kNp;
  const int k1 = k0 + 1 == kNp ? 0 : k0 + 1;

  const std::size_t rows[4] = {MerlTable::index(i0, j0, 0), MerlTable::index(i0, j1, 0), MerlTable::index(i1, j0, 0),
                               MerlTable::index(i1, j1, 0)};
  const float row_weights[4] = {(1 - th) * (1 - td), (1 - th) * td, th * (1 - td), th * td};
  Rgb sum(0.0f);
  float weight_sum = 0;
  for (int r = 0; r < 4; ++r) {
    const Cell& a = cells_[rows[r] + k0];
    const Cell& b = cells_[rows[r] + k1];
    const float wa = row_weights[r] * (1 - tp) * a.measured, wb = row_weights[r] * tp * b.measured;
    sum += wa * a.f + wb * b.f;
    weight_sum += wa + wb;
  }
  if (weight_sum > 0) return sum / weight_sum;
  return evalNearest(u_h, u_d, u_p);
}

Rgb TabulatedBrdf::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (!(wi.z > 0 && wo.z > 0)) return Rgb(0.0f);  // below the horizon (or NaN input)
  const TableCoordinates u = tableCoordinates(wi, wo);
  switch (lookup_) {
    case TableLookup::Nearest: return evalNearest(u.u_h, u.u_d, u.u_p);
    case TableLookup::Truncated: return evalTruncated(u.u_h, u.u_d, u.u_p);
    case TableLookup::Interpolated: break;
  }
  return evalInterpolated(u.u_h, u.u_d, u.u_p);
}

std::optional<BsdfSample> TabulatedBrdf::sample(const glm::vec3& wo, glm::vec2, glm::vec2 u) const {
  return sampleCosineWeighted(*this, wo, u);
}

float TabulatedBrdf::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const { return cosineWeightedPdf(wi, wo); }

const char* tableLookupName(TableLookup lookup) {
  switch (lookup) {
    case TableLookup::Nearest: return "nearest";
    case TableLookup::Truncated: return "truncated";
    case TableLookup::Interpolated: break;
  }
  return "interpolated";
}

std::optional<TableLookup> parseTableLookup(std::string_view name) {
  for (const TableLookup lookup : {TableLookup::Nearest, TableLookup::Interpolated, TableLookup::Truncated})
    if (name == tableLookupName(lookup)) return lookup;
  return std::nullopt;
}

std::string TabulatedBrdf::name() const {
  return std::string("tabulated(lookup=") + tableLookupName(lookup_) + ")";
}

MerlTable tabulate(const Material& material) {
  MerlTable table;
  Progress progress("tabulate " + material.name(), kNh);
  const bool reciprocal = material.isReciprocal();
  // Each cell depends only on its own angles, so any split over threads gives the same table.
  tbb::parallel_for(tbb::blocked_range<int>(0, kNh), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i != range.end(); ++i) {
      for (int j = 0; j < kNd; ++j) {
        for (int k = 0; k < kNp; ++k) {
          const DirectionPair pair = MerlTable::directionsOf(i, j, k);
          const std::size_t c = MerlTable::index(i, j, k);
          if (!(pair.wi.z > 0 && pair.wo.z > 0)) {
            table.setUnmeasured(c);
            continue;
          }
          // A cell stands for both (wi, wo) and the swapped pair (phi_d + pi): store their mean,
          // the reciprocal part. For measured data that is not exactly reciprocal this avoids a
          // seam where the lookup folds phi_d onto [0, pi); reciprocal models need one eval.
          const Rgb f = reciprocal ? material.eval(pair.wi, pair.wo)
                                   : 0.5f * (material.eval(pair.wi, pair.wo) + material.eval(pair.wo, pair.wi));
          if (!f.isFinite())
            throw Error("tabulate: " + material.name() + " returned a non-finite value at theta_h index " +
                        std::to_string(i) + ", theta_d index " + std::to_string(j) + ", phi_d index " +
                        std::to_string(k));
          table.setReflectance(c, f);
        }
      }
      progress.advance();
    }
  });
  return table;
}

namespace {

// A MERL-layout table in either file form: the .binary MERL writes, or `btf convert`'s EXR stack.
MerlTable readMerlLayoutTable(const std::filesystem::path& path) {
  if (path.extension() == ".exr") return exrStackToMerl(path, readImageStack(path));
  return readMerl(path);
}

// The .binary header: int32 dims 90, 90, 180 (theta_h, theta_d, phi_d).
bool isMerlBinary(std::span<const unsigned char> head, std::uintmax_t) {
  const std::int32_t dims[3] = {MerlTable::kThetaHalfRes, MerlTable::kThetaDiffRes, MerlTable::kPhiDiffRes};
  return head.size() >= sizeof dims && std::memcmp(head.data(), dims, sizeof dims) == 0;
}

// OpenEXR's magic number, 20000630 little-endian.
bool isExr(std::span<const unsigned char> head, std::uintmax_t) {
  return head.size() >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01;
}

}  // namespace

BTF_REGISTER_MATERIAL(merl, {.name = "merl",
                             .summary = "a measured isotropic BRDF table in MERL's layout",
                             .keys = {"file", "lookup"},
                             .formats = {{.description = "MERL binary (isotropic BRDF table)",
                                          .extensions = {".binary"},
                                          .sniff = isMerlBinary},
                                         {.description = "EXR stack of MERL half/diff slices (btf convert)",
                                          .extensions = {".exr"},
                                          .sniff = isExr}},
                             .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                               const TableLookup lookup = tableLookupParam(p);
                               auto table = std::make_shared<const MerlTable>(readMerlLayoutTable(p.existingPath("file")));
                               return std::make_shared<TabulatedBrdf>(std::move(table), lookup);
                             },
                             .table = [](const MaterialParams& p) { return readMerlLayoutTable(p.existingPath("file")); }});

}  // namespace btf
