// The random part of a measurement, applied to a finished table: multiplicative noise and
// unmeasured samples (negative values, as in MERL files). Each cell draws from its own counter-based
// random stream keyed by (seed, cell index), so the result is independent of how work is split.
#pragma once

#include <cstddef>
#include <cstdint>

#include "btf/io/merl.h"

namespace btf::datagen {

struct TableArtifacts {
  // Per-channel multiplicative noise exp(sigma * z - sigma^2 / 2), z standard normal: lognormal
  // with mean 1, so the expected albedo is unchanged.
  float noise_sigma = 0.0f;
  // Fraction of cells dropped at random (a failed exposure, a saturated pixel).
  float hole_fraction = 0.0f;
  // Cells with a light or view direction within this many degrees of the horizon are unmeasured:
  // real gonioreflectometers cannot reach grazing angles.
  float grazing_gap_degrees = 0.0f;
};

// Adds noise and holes; returns the number of cells this call marked unmeasured.
std::size_t applyArtifacts(MerlTable& table, const TableArtifacts& artifacts, std::uint64_t seed);

}  // namespace btf::datagen
