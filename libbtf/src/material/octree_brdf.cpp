#include "btf/material/octree_brdf.h"

#include <algorithm>
#include <cstdio>

#include "btf/core/error.h"
#include "btf/io/container.h"
#include "btf/material/registry.h"
#include "cosine_sampling.h"
#include "merl_resolution.h"
#include "table_coordinates.h"
#include "table_params.h"

namespace btf {
namespace {

// f of one cell (in double: blends of values near the float limit must not overflow) and whether
// it is measured.
struct CellValue {
  glm::dvec3 f;
  bool measured;
};

CellValue cellValue(const OctreeTable::Leaf& raw) {
  const bool measured = raw[0] >= 0 && raw[1] >= 0 && raw[2] >= 0;
  if (!measured) return {glm::dvec3(0.0), false};
  return {glm::dvec3(raw[0] * MerlTable::kChannelScale[0], raw[1] * MerlTable::kChannelScale[1],
                     raw[2] * MerlTable::kChannelScale[2]),
          true};
}

CellValue cellValue(const OctreeTable& octree, int i, int j, int k) { return cellValue(octree.raw(i, j, k)); }

Rgb toRgb(const glm::dvec3& f) { return Rgb(float(f.x), float(f.y), float(f.z)); }

}  // namespace

OctreeBrdf::OctreeBrdf(std::shared_ptr<const OctreeTable> octree, TableLookup lookup)
    : octree_(std::move(octree)), lookup_(lookup) {
  if (!octree_) throw Error("OctreeBrdf: no octree given");
}

Rgb OctreeBrdf::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (!(wi.z > 0 && wo.z > 0)) return Rgb(0.0f);
  const TableCoordinates u = tableCoordinates(wi, wo);
  if (lookup_ != TableLookup::Interpolated) {
    const bool nearest = lookup_ == TableLookup::Nearest;
    const float r = nearest ? 0.5f : 0.0f;
    int k = int(u.u_p + r);
    if (k >= kNp) k -= kNp;
    return toRgb(cellValue(*octree_, std::min(int(u.u_h + r), kNh - 1), std::min(int(u.u_d + r), kNd - 1), k).f);
  }
  // Trilinear over the measured corners, as TabulatedBrdf::evalInterpolated.
  const int i0 = std::min(int(u.u_h), kNh - 1), j0 = std::min(int(u.u_d), kNd - 1);
  const int i[2] = {i0, std::min(i0 + 1, kNh - 1)}, j[2] = {j0, std::min(j0 + 1, kNd - 1)};
  const float th = std::min(u.u_h - float(i0), 1.0f), td = std::min(u.u_d - float(j0), 1.0f);
  int k0 = int(u.u_p);
  const float tp = u.u_p - float(k0);
  if (k0 >= kNp) k0 -= kNp;
  const int k[2] = {k0, k0 + 1 == kNp ? 0 : k0 + 1};
  const OctreeTable::Block block = octree_->rawBlock({i[0], i[1]}, {j[0], j[1]}, {k[0], k[1]});
  glm::dvec3 sum(0.0);
  double weight_sum = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        const double w = double((a ? th : 1 - th) * (b ? td : 1 - td) * (c ? tp : 1 - tp));
        if (w == 0) continue;
        const CellValue v = cellValue(*block[std::size_t(4 * a + 2 * b + c)]);
        if (!v.measured) continue;
        sum += w * v.f;
        weight_sum += w;
      }
  if (weight_sum > 0) return toRgb(sum / weight_sum);
  int kn = int(u.u_p + 0.5f);
  if (kn >= kNp) kn -= kNp;
  return toRgb(cellValue(*octree_, std::min(int(u.u_h + 0.5f), kNh - 1), std::min(int(u.u_d + 0.5f), kNd - 1), kn).f);
}

std::optional<BsdfSample> OctreeBrdf::sample(const glm::vec3& wo, glm::vec2, glm::vec2 u) const {
  return sampleCosineWeighted(*this, wo, u);
}

float OctreeBrdf::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const { return cosineWeightedPdf(wi, wo); }

std::string OctreeBrdf::name() const {
  char text[96];
  std::snprintf(text, sizeof text, "octree(tolerance=%g, lookup=%s)", octree_->tolerance(), tableLookupName(lookup_));
  return text;
}

BTF_REGISTER_MATERIAL(octree, {.name = "octree",
                               .summary = "an adaptive octree table of a MERL-layout BRDF (btf convert --tolerance)",
                               .keys = {"file", "lookup"},
                               .formats = {{.description = "octree table (MERL layout, btf convert --tolerance)",
                                            .extensions = {".octree"},
                                            .sniff = [](std::span<const unsigned char> head, std::uintmax_t) {
                                              return containerFormatOf(head) == "libbtf-octree";
                                            }}},
                               .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                 const TableLookup lookup = tableLookupParam(p);
                                 auto table = std::make_shared<const OctreeTable>(readOctreeFile(p.existingPath("file")));
                                 return std::make_shared<OctreeBrdf>(std::move(table), lookup);
                               },
                               .table = [](const MaterialParams& p) { return readOctreeFile(p.existingPath("file")).expand(); }});

}  // namespace btf
