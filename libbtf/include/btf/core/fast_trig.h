// cos and sin of an angle given in turns, for hot paths (hand-written: the library's sin/cos do a
// general range reduction that dominated the samplers' direction mapping, and no Debian library
// offers a vetted float version; see also fast_atan.h).
#pragma once

#include <bit>
#include <cstdint>

namespace btf {

// cos and sin of 2 pi t for t in (-1/8, 1], without the library's general range reduction: t is in
// turns, so the nearest quarter turn is subtracted exactly (Sterbenz) and Taylor polynomials of
// degree 8 / 9 on [-pi/4, pi/4] give |error| < 3e-8, below float resolution of the unit vector.
inline void cosSinTurns(float t, float& c, float& s) {
  const int quarter = static_cast<int>(4.0f * t + 0.5f);  // 4 t + 0.5 > 0: truncation rounds to nearest
  const float a = 6.28318531f * (t - 0.25f * float(quarter)), a2 = a * a;
  const float sin_a = a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
  const float cos_a = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 + a2 * (1.0f / 40320))));
  // Quarter 0: (cos, sin); 1: (-sin, cos); 2: (-cos, -sin); 3: (sin, -cos). That is a swap for
  // odd quarters and a negation of both for quarters 2 and 3, done on the bits: the quarter is
  // random for sampled directions and a switch was a mispredicted jump.
  const std::uint32_t swap = 0u - std::uint32_t(quarter & 1), negate = std::uint32_t(quarter & 2) << 30;
  const std::uint32_t cb = std::bit_cast<std::uint32_t>(cos_a), sb = std::bit_cast<std::uint32_t>(sin_a);
  c = std::bit_cast<float>(((cb & ~swap) | ((sb ^ 0x80000000u) & swap)) ^ negate);
  s = std::bit_cast<float>(((sb & ~swap) | (cb & swap)) ^ negate);
}

}  // namespace btf
