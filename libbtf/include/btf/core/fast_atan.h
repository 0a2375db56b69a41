// A fast atan2 for hot paths, accurate to about one float ulp (hand-written: the standard library
// call dominated table lookups and sampling, and no Debian library offers a vetted float version).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace btf {

// atan2(y, x) / (2 pi) in (-1/2, 1/2], without the library call: atan of the ratio min/max in
// [0, 1] as a * P(a^2), P interpolating atan(sqrt(z)) / (2 pi sqrt(z)) at the 9 Chebyshev nodes of
// z in [0, 1] (|error| < 1e-8 turns, about one float ulp of the result; evaluated by Estrin's
// scheme, half the dependent multiply-adds of Horner's), then the octant's symmetries. For hot
// paths where std::atan2 dominates: table lookups, an RGL file's eval, and the samplers' cell
// search (there sample()
// returns pdf's own value, so the two still agree exactly; the approximation moves cell
// boundaries by ~1 ulp, as float rounding does).
inline float fastAtan2Turns(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0.0f)) return 0.0f;  // atan2(+-0, +-0): phi = 0, as at the pole; NaN y too (NaN x, inf / inf give NaN)
  const float a = lo / hi, z = a * a, z2 = z * z, z4 = z2 * z2;
  const float p01 = 0.159154937f - 0.0530511774f * z, p23 = 0.0318180509f - 0.0225964971f * z;
  const float p45 = 0.0168996621f - 0.0118679535f * z, p67 = 0.00670641102f - 0.00250370614f * z;
  const float p = (p01 + p23 * z2) + z4 * ((p45 + p67 * z2) + 0.0004402677f * z4);
  float r = a * p;
  if (ay > ax) r = 0.25f - r;
  if (x < 0.0f) r = 0.5f - r;
  // The sign of y is random in a sampler's use: flip the sign bit without a branch (compilers
  // emit a conditional jump for the ternary, mispredicted half the time). Same value as y < 0 ? -r : r.
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(r) ^ (std::uint32_t(y < 0.0f) << 31));
}

}  // namespace btf
