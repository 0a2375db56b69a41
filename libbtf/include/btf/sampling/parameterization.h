// How the tabulated samplers (binned_sampler.h) lay a material's incoming directions over the
// unit square (s, t) on which their 2D distributions live.
//
// Incident: s = cos(theta_i), t = phi_i / (2 pi), in the bin frame. d omega_i = 2 pi ds dt, a
// constant, so equal areas of the square are equal solid angles. Cells are spent evenly over the
// hemisphere, and a glossy lobe, which is narrow and moves with wo, covers few of them.
//
// Half: the square is mapped to the half vector h (Shirley and Chiu's concentric square-to-disk
// map, its radius r squared so that cells crowd towards the centre, then Lambert's azimuthal lift
// to the hemisphere: d omega_h = 4 pi r^2 ds dt), and wi is wo reflected about h (wi = 2 (wo.h) h
// - wo, d omega_i = 4 (wo.h) d omega_h). A microfacet-like lobe sits around h = n whatever wo is,
// at the square's centre, where the squared radius gives it the finest cells (about 0.25 degrees
// of theta_h at 128 cells per side, against 1.3 degrees for an equal-area map); the density over
// the square is f cos(theta_i) 16 pi r^2 (wo.h), and the solid-angle pdf divides it by that.
// The pdf grows without bound towards h = n (as the RGL files' own warp does), where f cos / pdf
// goes to 0; at h = n exactly it is not finite, and pdf() returns 0 there (a null set). Half
// vectors whose reflection falls below the horizon hold no mass but the defensive share, which
// sample() then loses.
//
// Both maps are hand-written here because they are the samplers' hot path (no library call; the
// trigonometry is core/fast_trig.h and core/fast_atan.h, accurate to float resolution).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "btf/core/fast_atan.h"
#include "btf/core/fast_trig.h"

namespace btf {

// Auto: the tabulated samplers' factory (makeSampler) builds both and keeps the one whose
// estimates vary less (binned_sampler.h); the sampler classes themselves take Incident or Half.
enum class Parameterization { Auto, Incident, Half };

std::string_view toString(Parameterization p);  // "auto", "incident", "half"
std::optional<Parameterization> parseParameterization(std::string_view name);

// The half-vector map of the unit square onto the upper hemisphere: the concentric map's signed
// radius r = max(|a|, |b|) (a, b = 2 (s, t) - 1) becomes the disk radius r |r|, then Lambert's lift
// z = 1 - rho^2, (x, y) scaled by sqrt(2 - rho^2). The square's centre is the pole.
// d omega_h / (ds dt) = 4 pi r^2.
inline glm::vec3 squareToHalfVector(glm::vec2 st) {
  const float a = 2.0f * st.x - 1.0f, b = 2.0f * st.y - 1.0f;
  float r, turns;
  if (std::abs(a) > std::abs(b)) {
    r = a, turns = b / (8.0f * a);  // phi = (pi / 4) (b / a), in (-1/8, 1/8) turns
  } else if (b != 0.0f) {
    r = b, turns = 0.25f - a / (8.0f * b);  // in [1/8, 3/8]
  } else {
    return {0.0f, 0.0f, 1.0f};
  }
  float c, s;
  cosSinTurns(turns, c, s);
  const float rho = r * std::abs(r);  // a negative radius turns the point by pi
  const float rho2 = rho * rho, k = rho * std::sqrt(std::max(2.0f - rho2, 0.0f));
  return {k * c, k * s, 1.0f - rho2};
}

// The inverse map for a unit h with h.z >= 0: (s, t) in [0, 1]^2 and the concentric radius r (for
// the Jacobian 4 pi r^2). The disk radius sqrt(1 - z) is computed as |h.xy| / sqrt(1 + z): 1 - z
// cancels near the pole, where glossy lobes put most draws, and would lose the digits that choose
// a cell.
struct HalfVectorSquare {
  glm::vec2 st;
  float r;
};
inline HalfVectorSquare halfVectorToSquare(const glm::vec3& h) {
  const float rho2 = h.x * h.x + h.y * h.y;
  const float r = std::sqrt(std::sqrt(rho2 / (1.0f + std::max(h.z, 0.0f))));
  const float turns = fastAtan2Turns(h.y, h.x);  // in (-1/2, 1/2]
  float a, b;
  if (turns >= -0.125f && turns <= 0.125f) {
    a = r, b = r * (8.0f * turns);
  } else if (turns > 0.125f && turns < 0.375f) {
    b = r, a = r * (2.0f - 8.0f * turns);
  } else if (turns >= 0.375f || turns <= -0.375f) {
    const float shifted = turns > 0.0f ? turns - 0.5f : turns + 0.5f;  // the opposite octant, in [-1/8, 1/8]
    a = -r, b = a * (8.0f * shifted);
  } else {
    const float shifted = turns + 0.5f;  // in (1/8, 3/8)
    b = -r, a = b * (2.0f - 8.0f * shifted);
  }
  return {{std::clamp(0.5f * (a + 1.0f), 0.0f, 1.0f), std::clamp(0.5f * (b + 1.0f), 0.0f, 1.0f)}, r};
}

}  // namespace btf
