// A Material over a MERL-layout table of an isotropic BRDF.
//
// Policies (documented in docs/formats.md as well):
// - Below the horizon (wi.z <= 0 or wo.z <= 0): eval returns 0.
// - Table samples sit at integer table coordinates (MerlTable::thetaHalfOf etc.). Nearest lookup
//   rounds the continuous coordinates to the closest sample; Truncated lookup is MERL's own reader
//   (the coordinates rounded down, so each sample stands for the cell above it: half a cell off for
//   samples placed at cell edges, and on a falling near-mirror peak it reads every cell at its
//   higher end, which is why MERL's published albedos of mirror-like tables are higher than the
//   interpolated ones); Interpolated lookup is trilinear in the coordinates
//   (theta_h through its sqrt mapping; phi_d periodic with period pi by reciprocity; theta
//   coordinates beyond the last sample take its value).
// - Unmeasured samples (negative in any channel) never contribute. Nearest lookup returns the
//   nearest measured sample along phi_d, then theta_d, then theta_h (searching outwards, ties to
//   the lower index); Interpolated lookup blends only the measured corners of the cell and
//   renormalizes their weights. A cell with no measured corner (of nonzero weight) falls back to
//   the nearest-lookup rule. Only a table with no measured sample at all evaluates to 0.
// - sample()/pdf() draw cosine-weighted directions (an exact density); the tabulated samplers of
//   the sampling module do better.
#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "btf/io/merl.h"
#include "btf/material/material.h"

namespace btf {

enum class TableLookup { Nearest, Interpolated, Truncated };

// Lookups by the names options and scene files give them: "nearest", "interpolated", "truncated".
const char* tableLookupName(TableLookup lookup);
// The lookup of that name; std::nullopt for any other.
std::optional<TableLookup> parseTableLookup(std::string_view name);
inline constexpr const char* kTableLookupNames = "interpolated, nearest or truncated";  // for messages

class TabulatedBrdf final : public Material {
 public:
  explicit TabulatedBrdf(std::shared_ptr<const MerlTable> table, TableLookup lookup = TableLookup::Interpolated);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  // One cell stands for both orders of a pair (the phi_d fold), so lookups are reciprocal.
  bool isReciprocal() const override { return true; }

  const MerlTable& table() const { return *table_; }
  TableLookup lookup() const { return lookup_; }

 private:
  // One table cell as eval reads it: 16 bytes, RGB interleaved, so an interpolated lookup touches
  // a few cache lines instead of 3 channel planes of doubles.
  struct Cell {
    Rgb f;           // f (1/sr) of the cell if measured, else of the measured cell nearest lookup uses
    float measured;  // 1 if the cell itself is measured, else 0 (its weight in interpolation)
  };

  Rgb evalNearest(float u_h, float u_d, float u_p) const;
  Rgb evalTruncated(float u_h, float u_d, float u_p) const;
  Rgb evalInterpolated(float u_h, float u_d, float u_p) const;

  std::shared_ptr<const MerlTable> table_;
  TableLookup lookup_;
  // Filled at construction from table_ (zero everywhere if the table has no measured cell).
  std::vector<Cell> cells_;
};

// Tabulates any isotropic material into the MERL layout by evaluating it at each cell's angles
// (phi_h = 0), storing the mean of f(wi, wo) and f(wo, wi): a MERL cell stands for both, so a
// material that is not exactly reciprocal (measured data) is stored by its reciprocal part. Cells whose sample directions lie below the horizon (wi.z <= 0 or wo.z <= 0) hold
// nothing measurable and are marked unmeasured, so interpolation near grazing angles blends only
// valid samples instead of zeros. Parallel over theta_h rows; the result does not depend on the
// thread count.
MerlTable tabulate(const Material& material);

}  // namespace btf
