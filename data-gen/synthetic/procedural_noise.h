// Procedural noise for the synthetic microgeometries: pure functions of (key, position), periodic
// over the patch so that the height field tiles (rays that leave one side enter the other) while
// the content inside the patch never repeats. Positions and lengths are in texels.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "btf/core/rng.h"

namespace btf::synthetic {

// A uniform number in [0, 1) from a key and up to three integers (no state: any evaluation order).
inline float hash01(std::uint64_t key, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0) {
  std::uint64_t h = mix64(key ^ 0x6a09e667f3bcc909ULL);
  h = mix64(h ^ std::uint64_t(a));
  h = mix64(h ^ (std::uint64_t(b) * 0x9e3779b97f4a7c15ULL));
  h = mix64(h ^ (std::uint64_t(c) * 0xc2b2ae3d27d4eb4fULL));
  return float(h >> 40) * 0x1p-24f;
}

// A key for one named ingredient of a pattern, derived from the seed.
inline std::uint64_t subKey(std::uint64_t seed, std::uint64_t ingredient) { return mix64(seed * 0x100000001b3ULL + ingredient); }

// Lattice cells that fit a period when features are about `feature_size` texels apart (>= 1).
int latticeCells(float period, float feature_size);

// Smooth value noise in [-1, 1] on a lattice of cells_x x cells_y cells over a patch of
// period.x x period.y texels (periodic).
float periodicValueNoise(glm::vec2 p, glm::vec2 period, int cells_x, int cells_y, std::uint64_t key);

// Fractal sum of `octaves` value noises, the first with features about `feature_size` texels apart,
// each next one twice as fine and half as strong; normalized to about [-1, 1].
float periodicFbm(glm::vec2 p, glm::vec2 period, float feature_size, int octaves, std::uint64_t key);

// Cellular (Voronoi) noise over jittered lattice points, periodic over the patch.
struct VoronoiSample {
  float f1 = 0;         // distance to the nearest point (texels)
  float f2 = 0;         // distance to the second nearest point
  std::uint64_t cell = 0;  // identifies the nearest point's cell (wrapped), for per-cell choices
  glm::vec2 to_nearest{0};  // vector from p to the nearest point (texels)
};
VoronoiSample periodicVoronoi(glm::vec2 p, glm::vec2 period, float cell_size, float jitter, std::uint64_t key);

float smoothstep(float edge0, float edge1, float x);

}  // namespace btf::synthetic
