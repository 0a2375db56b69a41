#include "btf_patterns.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/ward.h"
#include "procedural_noise.h"

namespace btf::synthetic {
namespace {

// What a pattern says about one point of the sample.
struct SurfacePoint {
  float height = 0;
  std::uint8_t material = 0;
  Rgb tint{1.0f};
  float tangent_angle = 0;
};

using PatternFunction = std::function<SurfacePoint(glm::vec2 p)>;

// Colour varied per channel by up to +-amount (relative), from a key; kept within (0, 0.95].
Rgb jitterColour(Rgb base, std::uint64_t key, float amount) {
  Rgb c;
  for (int i = 0; i < 3; ++i) c[i] = std::clamp(base[i] * (1.0f + amount * (2.0f * hash01(key, i) - 1.0f)), 0.005f, 0.95f);
  return c;
}

Rgb pick(std::uint64_t key, std::initializer_list<Rgb> palette) {
  const std::size_t i = std::min(palette.size() - 1, std::size_t(hash01(key, 0) * float(palette.size())));
  return *(palette.begin() + i);
}

// Fills the grid from a pattern (rows in parallel; every sample a pure function of its position).
void fill(Microgeometry& g, const PatternFunction& pattern) {
  tbb::parallel_for(tbb::blocked_range<int>(0, g.gridHeight()), [&](const tbb::blocked_range<int>& rows) {
    for (int gy = rows.begin(); gy != rows.end(); ++gy)
      for (int gx = 0; gx < g.gridWidth(); ++gx) {
        const SurfacePoint s = pattern(glm::vec2(g.sampleX(gx), g.sampleY(gy)));
        const std::size_t i = g.gridIndex(gx, gy);
        g.heights[i] = s.height;
        g.material_ids[i] = s.material;
        g.tints[i] = s.tint;
        g.tangent_angles[i] = s.tangent_angle;
      }
  });
}

// ---- fabric ----------------------------------------------------------------------------------

void makeFabric(Microgeometry& g, std::uint64_t seed) {
  const glm::vec2 period(float(g.width), float(g.height));
  const std::uint64_t key = subKey(seed, 1);
  const float thread_period = 4.0f + 2.0f * hash01(key, 1);  // texels
  // Thread counts are multiples of 4 so that both weaves close over the periodic border.
  const int nx = 4 * std::max(1, int(std::lround(period.x / (4.0f * thread_period))));
  const int ny = 4 * std::max(1, int(std::lround(period.y / (4.0f * thread_period))));
  const glm::vec2 pitch(period.x / float(nx), period.y / float(ny));
  const bool twill = hash01(key, 2) < 0.5f;
  const float radius = 0.2f * thread_period, undulation = 0.15f * thread_period;
  const Rgb warp_colour = jitterColour(pick(subKey(seed, 2), {{0.55f, 0.12f, 0.10f}, {0.15f, 0.22f, 0.50f},
                                                              {0.60f, 0.55f, 0.40f}, {0.20f, 0.35f, 0.18f}}),
                                       subKey(seed, 3), 0.15f);
  const Rgb weft_colour = jitterColour(pick(subKey(seed, 4), {{0.75f, 0.70f, 0.60f}, {0.35f, 0.10f, 0.30f},
                                                              {0.12f, 0.12f, 0.14f}, {0.70f, 0.45f, 0.15f}}),
                                       subKey(seed, 5), 0.15f);
  g.materials = {std::make_shared<Ward>(warp_colour, Rgb(0.05f), 0.12f, 0.45f),
                 std::make_shared<Ward>(weft_colour, Rgb(0.05f), 0.12f, 0.45f),
                 std::make_shared<Lambert>(Rgb(0.03f, 0.03f, 0.035f))};
  auto over = [&](int i, int j) {  // warp thread i above weft thread j
    const int k = ((i % nx) + nx + (j % ny) + ny) % 4;
    return twill ? k < 2 : k % 2 == 0;
  };
  // One family of threads: `across` runs across the threads, `along` along them.
  struct Thread {
    float height;
    Rgb tint;
  };
  auto thread = [&](float across, float along, float across_pitch, float along_pitch, int count, bool is_warp,
                    std::uint64_t family) -> Thread {
    const float t = across / across_pitch;
    const int i = int(std::floor(t));
    const int wrapped = ((i % count) + count) % count;
    // The centreline wobbles a little along the thread, the thickness varies per thread (slubs).
    const glm::vec2 along_pos = is_warp ? glm::vec2(across, along) : glm::vec2(along, across);
    const float wobble = 0.05f * periodicFbm(along_pos, period, 6.0f, 2, mix64(family + std::uint64_t(wrapped)));
    const float half_width = 0.42f * (1.0f + 0.12f * (hash01(family, wrapped, 7) - 0.5f)) *
                             (1.0f + 0.06f * periodicFbm(along_pos, period, 3.0f, 2, mix64(family ^ 0xabcULL)));
    const float d = (t - float(i) - 0.5f - wobble) / half_width;
    if (std::abs(d) >= 1.0f) return {-1e9f, Rgb(1.0f)};
    // Height of the thread's centre along it: up over the crossing threads, down under them.
    const float s = along / along_pitch - 0.5f;
    const int j0 = int(std::floor(s));
    const float f = s - float(j0);
    auto level = [&](int j) {
      const bool up = is_warp ? over(wrapped, j) : !over(j, wrapped);
      return up ? undulation : -undulation;
    };
    const float centre = level(j0) + (level(j0 + 1) - level(j0)) * 0.5f * (1.0f - std::cos(kPi * f));
    // Fibre twist: ridges slanting across the thread, 1.5 turns per crossing (thread counts are
    // multiples of 4, so a whole number of turns fits the period).
    const float twist = 0.08f * radius * std::sin(kTwoPi * (1.5f * d + 1.5f * along / along_pitch));
    const float height = centre + radius * std::sqrt(1.0f - d * d) + twist;
    const float slub = 1.0f + 0.12f * periodicFbm(along_pos, period, 2.0f, 3, mix64(family ^ 0x5ULL));
    const Rgb tint = Rgb(1.0f + 0.16f * (hash01(family, wrapped, 9) - 0.5f)) * slub;
    return {height, tint};
  };
  const float base = -undulation - 0.3f * radius;
  fill(g, [&](glm::vec2 p) {
    const Thread warp = thread(p.x, p.y, pitch.x, pitch.y, nx, true, subKey(seed, 10));
    const Thread weft = thread(p.y, p.x, pitch.y, pitch.x, ny, false, subKey(seed, 11));
    if (warp.height <= base && weft.height <= base) return SurfacePoint{base, 2, Rgb(1.0f), 0.0f};
    if (warp.height >= weft.height) return SurfacePoint{warp.height, 0, warp.tint, kHalfPi};  // runs along y
    return SurfacePoint{weft.height, 1, weft.tint, 0.0f};                                   // runs along x
  });
}

// ---- stones ----------------------------------------------------------------------------------

void makeStones(Microgeometry& g, std::uint64_t seed) {
  const glm::vec2 period(float(g.width), float(g.height));
  const std::uint64_t cells = subKey(seed, 20), grain = subKey(seed, 21), shape = subKey(seed, 22);
  const float cell_size = 5.0f + 2.5f * hash01(subKey(seed, 23), 0);
  g.materials = {std::make_shared<Lambert>(jitterColour(Rgb(0.50f, 0.48f, 0.44f), subKey(seed, 24), 0.1f)),
                 std::make_shared<Ggx>(Rgb(0.42f, 0.40f, 0.37f), Rgb(0.03f), 0.65f, 0.65f),
                 std::make_shared<Ggx>(Rgb(0.35f, 0.20f, 0.15f), Rgb(0.04f), 0.12f, 0.12f),
                 std::make_shared<Lafortune>(Rgb(0.45f, 0.36f, 0.22f),
                                             std::vector<LafortuneLobe>{{Rgb(0.10f), {-1.0f, -1.0f, 1.0f}, 20.0f}})};
  fill(g, [&](glm::vec2 p) {
    const VoronoiSample v = periodicVoronoi(p, period, cell_size, 0.9f, cells);
    const float edge = 0.5f * (v.f2 - v.f1);
    const float mortar_half_width = 0.3f;
    const float mortar = 0.12f * periodicFbm(p, period, 1.5f, 3, grain);
    if (edge < mortar_half_width) {
      const float speckle = 1.0f + 0.25f * periodicFbm(p, period, 0.5f, 2, grain ^ 1);
      return SurfacePoint{mortar, 0, Rgb(speckle), 0.0f};
    }
    const float stone_height = 0.8f + 0.8f * hash01(shape, std::int64_t(v.cell), 0);
    const float bevel = 1.2f + 0.8f * hash01(shape, std::int64_t(v.cell), 1);
    const float s = std::min(1.0f, (edge - mortar_half_width) / bevel);
    const float tilt_angle = kTwoPi * hash01(shape, std::int64_t(v.cell), 2);
    const glm::vec2 tilt = 0.12f * hash01(shape, std::int64_t(v.cell), 3) * glm::vec2(std::cos(tilt_angle), std::sin(tilt_angle));
    const float rough = 0.10f * periodicFbm(p, period, 1.2f, 3, grain ^ 2);
    const float height = std::max(mortar, stone_height * (1.0f - (1.0f - s) * (1.0f - s)) +
                                              s * (glm::dot(tilt, -v.to_nearest) + rough));
    const auto material = std::uint8_t(1 + std::min(2, int(3.0f * hash01(shape, std::int64_t(v.cell), 4))));
    const Rgb cell_tint = jitterColour(Rgb(0.8f), mix64(shape + v.cell), 0.25f) / 0.8f;
    const float speckle = 1.0f + 0.2f * periodicFbm(p, period, 0.6f, 2, grain ^ 3);
    return SurfacePoint{height, material, cell_tint * speckle, 0.0f};
  });
}

// ---- paint -----------------------------------------------------------------------------------

void makePaint(Microgeometry& g, std::uint64_t seed) {
  const glm::vec2 period(float(g.width), float(g.height));
  const std::uint64_t bumps = subKey(seed, 30), streaks = subKey(seed, 31), flakes = subKey(seed, 32);
  const Rgb colour = jitterColour(pick(subKey(seed, 33), {{0.60f, 0.06f, 0.05f}, {0.05f, 0.15f, 0.50f},
                                                          {0.08f, 0.35f, 0.12f}, {0.70f, 0.55f, 0.08f}}),
                                  subKey(seed, 34), 0.1f);
  g.materials = {std::make_shared<Ggx>(colour, Rgb(0.04f), 0.10f, 0.10f),
                 std::make_shared<Ggx>(Rgb(0.0f), jitterColour(Rgb(0.85f, 0.82f, 0.75f), subKey(seed, 35), 0.1f), 0.06f,
                                       0.06f)};
  const int streak_cells_x = latticeCells(period.x, 12.0f), streak_cells_y = latticeCells(period.y, 1.2f);
  fill(g, [&](glm::vec2 p) {
    float height = 1.6f * periodicFbm(p, period, 4.0f, 4, bumps) +
                   0.12f * periodicValueNoise(p, period, streak_cells_x, streak_cells_y, streaks);
    const Rgb tint(1.0f + 0.06f * periodicFbm(p, period, 10.0f, 2, bumps ^ 7));
    const VoronoiSample v = periodicVoronoi(p, period, 1.2f, 0.8f, flakes);
    if (hash01(flakes, std::int64_t(v.cell), 0) < 0.12f && v.f1 < 0.35f) {
      // A metallic platelet slightly proud of the coat and tilted at random: it glints at its own angles.
      const float a = kTwoPi * hash01(flakes, std::int64_t(v.cell), 1);
      const float slope = 0.25f * hash01(flakes, std::int64_t(v.cell), 2);
      height += 0.03f + slope * glm::dot(glm::vec2(std::cos(a), std::sin(a)), -v.to_nearest);
      return SurfacePoint{height, 1, Rgb(1.0f), 0.0f};
    }
    return SurfacePoint{height, 0, tint, 0.0f};
  });
}

// ---- leather ---------------------------------------------------------------------------------

void makeLeather(Microgeometry& g, std::uint64_t seed) {
  const glm::vec2 period(float(g.width), float(g.height));
  const std::uint64_t grain = subKey(seed, 40), creases = subKey(seed, 41), pores = subKey(seed, 42), dye = subKey(seed, 43);
  const Rgb colour = jitterColour(pick(subKey(seed, 44), {{0.28f, 0.14f, 0.07f}, {0.08f, 0.07f, 0.06f},
                                                          {0.45f, 0.30f, 0.16f}, {0.30f, 0.05f, 0.05f}}),
                                  subKey(seed, 45), 0.1f);
  g.materials = {std::make_shared<Lafortune>(colour, std::vector<LafortuneLobe>{{Rgb(0.07f), {-1.0f, -1.0f, 1.0f}, 12.0f}}),
                 std::make_shared<Lambert>(colour * 0.45f)};
  fill(g, [&](glm::vec2 p) {
    const VoronoiSample fine = periodicVoronoi(p, period, 3.5f, 0.9f, grain);
    const VoronoiSample coarse = periodicVoronoi(p, period, 14.0f, 0.9f, creases);
    const float e1 = 0.5f * (fine.f2 - fine.f1), e2 = 0.5f * (coarse.f2 - coarse.f1);
    const float groove = 0.35f * std::exp(-(e1 / 0.3f) * (e1 / 0.3f)) + 0.6f * std::exp(-(e2 / 0.5f) * (e2 / 0.5f));
    const float height = 0.2f * smoothstep(0.0f, 1.5f, e1) - groove + 0.05f * periodicFbm(p, period, 0.6f, 2, pores) +
                         0.2f * periodicFbm(p, period, 10.0f, 2, grain ^ 3);
    const Rgb tint(1.0f + 0.12f * periodicFbm(p, period, 6.0f, 3, dye));
    return SurfacePoint{height, std::uint8_t(groove > 0.25f ? 1 : 0), tint, 0.0f};
  });
}

// ---- print -----------------------------------------------------------------------------------

// A printed paper, as wallpapers are made: a motif of two inks repeating every 8 to 24 texels,
// printed on a matte paper with fine fibre grain and a shallow emboss under the inks. Unlike the
// other samples it is low-rank on purpose: three materials and one motif make texels repeat up to
// the grain, registration and sub-texel phase (the motif's pitch is not a whole number of texels),
// as the texels of measured prints do.
void makePrint(Microgeometry& g, std::uint64_t seed) {
  const glm::vec2 period(float(g.width), float(g.height));
  const std::uint64_t key = subKey(seed, 50), grain = subKey(seed, 51), mottle = subKey(seed, 52);
  const float motif = 8.0f + 16.0f * hash01(key, 1);  // texels
  const int nx = std::max(1, int(std::lround(period.x / motif))), ny = std::max(1, int(std::lround(period.y / motif)));
  const glm::vec2 pitch(period.x / float(nx), period.y / float(ny));
  const Rgb paper = jitterColour(Rgb(0.78f, 0.74f, 0.64f), subKey(seed, 53), 0.05f);
  const Rgb ink1 = jitterColour(pick(subKey(seed, 54), {{0.45f, 0.12f, 0.10f}, {0.12f, 0.20f, 0.42f},
                                                        {0.20f, 0.32f, 0.16f}, {0.50f, 0.38f, 0.12f}}),
                                subKey(seed, 55), 0.1f);
  const Rgb ink2 = jitterColour(pick(subKey(seed, 56), {{0.62f, 0.55f, 0.30f}, {0.30f, 0.30f, 0.32f},
                                                        {0.55f, 0.30f, 0.25f}}),
                                subKey(seed, 57), 0.1f);
  g.materials = {std::make_shared<Lambert>(paper), std::make_shared<Ggx>(ink1, Rgb(0.04f), 0.35f, 0.35f),
                 std::make_shared<Lambert>(ink2)};
  const float phase = hash01(key, 2);
  fill(g, [&](glm::vec2 p) {
    const glm::vec2 q = p / pitch;  // motif cells
    const glm::vec2 f = q - glm::floor(q);
    // Ink 1: four-petal rosettes; ink 2: a ring around them and a thin diagonal trellis.
    const float petals = 0.5f + 0.5f * std::sin(kTwoPi * (f.x + phase)) * std::sin(kTwoPi * (f.y + phase));
    const float ring = std::abs(glm::length(f - glm::vec2(0.5f)) - 0.32f);
    const float trellis = std::abs(std::sin(kPi * (f.x + f.y)));
    const float fibres = periodicFbm(p, period, 1.5f, 3, grain);
    // Ink density varies from print to print of the motif, and the paper's colour is mottled.
    const glm::ivec2 cell(int(std::floor(q.x)), int(std::floor(q.y)));
    const float density = 1.0f + 0.12f * (hash01(key, cell.x, cell.y) - 0.5f);
    const Rgb tint = Rgb(1.0f + 0.08f * periodicFbm(p, period, 5.0f, 3, mottle)) * density;
    std::uint8_t material = 0;
    float emboss = 0.0f;
    if (petals > 0.78f) {
      material = 1;
      emboss = 0.5f * smoothstep(0.78f, 0.9f, petals);
    } else if (ring < 0.05f || trellis < 0.08f) {
      material = 2;
      emboss = 0.25f;
    }
    return SurfacePoint{emboss + 0.1f * fibres, material, material == 0 ? Rgb(tint.r / density) : tint, 0.0f};
  });
}

}  // namespace

const std::vector<std::string>& btfPatternNames() {
  static const std::vector<std::string> names{"fabric", "stones", "paint", "leather", "print"};
  return names;
}

std::string btfPatternName(BtfPattern pattern) { return btfPatternNames()[std::size_t(pattern)]; }

BtfPattern parseBtfPattern(std::string_view name) {
  const auto& names = btfPatternNames();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return BtfPattern(i);
  throw Error("unknown BTF pattern '" + std::string(name) + "' (choose fabric, stones, paint, leather or print)");
}

Microgeometry makePatternMicrogeometry(BtfPattern pattern, int width, int height, std::uint64_t seed,
                                       int samples_per_texel) {
  Microgeometry g(width, height, samples_per_texel, std::make_shared<Lambert>(Rgb(0.5f)));
  switch (pattern) {
    case BtfPattern::Fabric: makeFabric(g, seed); break;
    case BtfPattern::Stones: makeStones(g, seed); break;
    case BtfPattern::Paint: makePaint(g, seed); break;
    case BtfPattern::Leather: makeLeather(g, seed); break;
    case BtfPattern::Print: makePrint(g, seed); break;
  }
  g.validate();
  return g;
}

std::unique_ptr<SyntheticBtf> makeSyntheticBtf(BtfPattern pattern, int width, int height, std::uint64_t seed,
                                               SyntheticBtfOptions options) {
  std::string name = btfPatternName(pattern) + "-" + std::to_string(width) + "x" + std::to_string(height) + "-seed" +
                     std::to_string(seed);
  return std::make_unique<SyntheticBtf>(makePatternMicrogeometry(pattern, width, height, seed), std::move(name), options);
}

}  // namespace btf::synthetic
