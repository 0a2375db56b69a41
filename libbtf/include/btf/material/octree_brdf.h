// A Material over an octree table (compress/octree_table.h): the MERL-layout lookups of
// TabulatedBrdf, with each table cell found by point location in the tree instead of an array.
//
// The coordinates of a direction pair are TabulatedBrdf's, so at tolerance 0 the two agree wherever
// the cells they read are measured. Holes differ: TabulatedBrdf fills an unmeasured cell with the
// nearest measured one, which needs the whole table; here unmeasured cells never contribute
// (interpolation renormalizes over the measured corners) and a pair whose cells are all
// unmeasured evaluates to 0.
// sample()/pdf() draw cosine-weighted directions, as TabulatedBrdf's do.
#pragma once

#include <memory>

#include "btf/compress/octree_table.h"
#include "btf/material/material.h"
#include "btf/material/tabulated_brdf.h"

namespace btf {

class OctreeBrdf final : public Material {
 public:
  explicit OctreeBrdf(std::shared_ptr<const OctreeTable> octree, TableLookup lookup = TableLookup::Interpolated);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

  const OctreeTable& octree() const { return *octree_; }

 private:
  std::shared_ptr<const OctreeTable> octree_;
  TableLookup lookup_;
};

}  // namespace btf
