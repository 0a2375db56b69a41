// The procedural samples of `btf-datagen btf`: each a height field with a material map built from
// the library's analytic materials, deterministic from a seed. Sizes (threads, stones, grain) are in
// texels and do not grow with the patch, as a real sample's features do not grow with the camera
// resolution: a larger BTF shows more of them, never the same cell twice except across the
// periodic border.
//   fabric  — plain or 2/2 twill weave of round threads (anisotropic Ward along each thread), with
//             per-thread colour and thickness jitter, fibre twist and slubs; dark gaps between.
//   stones  — Voronoi cobbles with rounded, tilted tops in three stone materials (rough and polished
//             GGX, Lafortune) set in grainy Lambertian mortar.
//   paint   — bumpy glossy coat (GGX) with brush streaks and sparse tilted metallic flakes.
//   leather — grain cells and larger creases with dark grooves; glossy Lafortune top, mottled dye.
//   print   — a printed paper: a two-ink motif repeating every 8-24 texels on matte, grainy paper
//             with a shallow emboss; low-rank like measured prints (the others are not).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "microgeometry.h"
#include "synthetic_btf.h"

namespace btf::synthetic {

enum class BtfPattern { Fabric, Stones, Paint, Leather, Print };

// "fabric", "stones", "paint", "leather", "print".
const std::vector<std::string>& btfPatternNames();
std::string btfPatternName(BtfPattern pattern);
// Throws btf::Error naming the valid patterns.
BtfPattern parseBtfPattern(std::string_view name);

inline constexpr int kDefaultSamplesPerTexel = 4;

Microgeometry makePatternMicrogeometry(BtfPattern pattern, int width, int height, std::uint64_t seed,
                                       int samples_per_texel = kDefaultSamplesPerTexel);

// The pattern's virtual measurement, named e.g. "fabric-64x64-seed1".
std::unique_ptr<SyntheticBtf> makeSyntheticBtf(BtfPattern pattern, int width, int height, std::uint64_t seed,
                                               SyntheticBtfOptions options = {});

}  // namespace btf::synthetic
