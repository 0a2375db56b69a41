// A Material over a MERL-layout table of an isotropic BRDF.
//
// Policies (documented in the README as well):
// - Below the horizon (wi.z <= 0 or wo.z <= 0): eval returns 0.
// - Unmeasured samples (negative in any channel) never contribute. Nearest lookup returns the
//   nearest measured sample along phi_d, then theta_d (searching outwards); Interpolated lookup
//   blends only the measured corners of the cell and renormalizes their weights. A cell with no
//   measured corner falls back to the nearest-lookup rule. Only a table with no measured sample at
//   all evaluates to 0.
// - sample()/pdf() draw cosine-weighted directions (an exact density); the tabulated samplers of
//   the sampling module do better.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "btf/io/merl.h"
#include "btf/material/material.h"

namespace btf {

enum class TableLookup { Nearest, Interpolated };

class TabulatedBrdf final : public Material {
 public:
  explicit TabulatedBrdf(std::shared_ptr<const MerlTable> table, TableLookup lookup = TableLookup::Interpolated);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;

  const MerlTable& table() const { return *table_; }
  TableLookup lookup() const { return lookup_; }

 private:
  std::shared_ptr<const MerlTable> table_;
  TableLookup lookup_;
  // Filled at construction: for each cell, the index of the measured cell that nearest lookup
  // uses (itself when measured); -1 if the table has no measured cell.
  std::vector<std::int32_t> nearest_measured_;
};

// Tabulates any isotropic material into the MERL layout by evaluating it at each cell's angles
// (phi_h = 0). Parallel over theta_h rows; the result does not depend on the thread count.
MerlTable tabulate(const Material& material);

}  // namespace btf
