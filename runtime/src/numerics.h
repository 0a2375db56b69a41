// The arithmetic the runtime shares with the full library, written op for op as the library's
// (core/fast_atan.h, core/fast_trig.h, core/cdf1d.cpp, material/btf_material.cpp's ring cells),
// in C++17 (memcpy for std::bit_cast). Change both together: tests/unit/test_runtime.cpp compares
// the runtime's eval, sample and pdf with the library's, bit for bit, on every codec path.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "btf_runtime/material.h"

namespace btfrt::detail {

inline constexpr int kRingCount = 6;
inline constexpr int kDirectionCount = 81;
inline constexpr std::array<int, kRingCount> kRingSizes{1, 6, 12, 18, 20, 24};
inline constexpr std::array<int, kRingCount> kRingStarts{0, 1, 7, 19, 37, 57};
inline constexpr float kRingStepDeg = 15.0f;
inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kTwoPi = 2.0f * 3.14159265358979323846f;

inline std::uint32_t floatBits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline float bitsFloat(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

inline Rgb operator*(const Rgb& a, float s) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb operator*(float s, const Rgb& a) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb& operator+=(Rgb& a, const Rgb& b) {
  a.r += b.r;
  a.g += b.g;
  a.b += b.b;
  return a;
}

// atan2(y, x) / (2 pi), as core/fast_atan.h.
inline float fastAtan2Turns(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0.0f)) return 0.0f;
  const float a = lo / hi, z = a * a, z2 = z * z, z4 = z2 * z2;
  const float p01 = 0.159154937f - 0.0530511774f * z, p23 = 0.0318180509f - 0.0225964971f * z;
  const float p45 = 0.0168996621f - 0.0118679535f * z, p67 = 0.00670641102f - 0.00250370614f * z;
  const float p = (p01 + p23 * z2) + z4 * ((p45 + p67 * z2) + 0.0004402677f * z4);
  float r = a * p;
  if (ay > ax) r = 0.25f - r;
  if (x < 0.0f) r = 0.5f - r;
  return bitsFloat(floatBits(r) ^ (std::uint32_t(y < 0.0f) << 31));
}

// cos and sin of 2 pi t, as core/fast_trig.h.
inline void cosSinTurns(float t, float& c, float& s) {
  const int quarter = static_cast<int>(4.0f * t + 0.5f);
  const float a = 6.28318531f * (t - 0.25f * float(quarter)), a2 = a * a;
  const float sin_a = a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
  const float cos_a = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 + a2 * (1.0f / 40320))));
  const std::uint32_t swap = 0u - std::uint32_t(quarter & 1), negate = std::uint32_t(quarter & 2) << 30;
  const std::uint32_t cb = floatBits(cos_a), sb = floatBits(sin_a);
  c = bitsFloat(((cb & ~swap) | ((sb ^ 0x80000000u) & swap)) ^ negate);
  s = bitsFloat(((sb & ~swap) | (cb & swap)) ^ negate);
}

inline float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }

// The CDF of f (n values) into cdf (n + 1), returning the mean of f: core/cdf1d.cpp's buildCdf1D.
inline double buildCdf1D(const float* f, std::size_t n, float* cdf) {
  double sum = 0.0;
  cdf[0] = 0.0f;
  for (std::size_t k = 0; k < n; ++k) {
    const float v = f[k];
    if (std::isfinite(v) && v > 0.0f) sum += v;
    cdf[k + 1] = static_cast<float>(sum);
  }
  if (!(sum > 0.0)) {
    for (std::size_t k = 0; k <= n; ++k) cdf[k] = static_cast<float>(double(k) / double(n));
    return 0.0;
  }
  const double inv = 1.0 / sum;
  double running = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const float v = f[k];
    if (std::isfinite(v) && v > 0.0f) running += v;
    cdf[k + 1] = static_cast<float>(running * inv);
  }
  cdf[n] = 1.0f;
  return sum / double(n);
}

struct DiscreteSample {
  std::size_t index;
  float probability;
  float remapped;
};
// core/cdf1d.cpp's sampleDiscrete on a CDF of n + 1 entries (n <= 32 here: the linear count; the
// library bisects beyond 32 cells, with the same result).
inline DiscreteSample sampleDiscrete(const float* cdf, std::size_t n, float u) {
  std::size_t count = 1;
  for (std::size_t i = 1; i < n; ++i) count += !(u < cdf[i]);
  const std::size_t k = count - 1;
  const float lo = cdf[k], width = cdf[k + 1] - lo;
  const float r = width > 0.0f ? (u - lo) / width : 0.0f;
  return {std::min(k, n - 1), width, r >= 0.0f ? std::min(r, 0x1.fffffep-1f) : 0.0f};
}

// The light cells of the 81-direction set (material/btf_material.cpp's RingCells).
struct RingCells {
  std::array<float, kRingCount> cos_top, cos_bottom, cell_solid_angle, cos_ring;
};
inline const RingCells& ringCells() {
  static const RingCells cells = [] {
    RingCells c{};
    for (int r = 0; r < kRingCount; ++r) {
      const std::size_t i = std::size_t(r);
      const float deg = kPi / 180.0f;
      const float top = r == 0 ? 0.0f : (15.0f * float(r) - 7.5f) * deg;
      const float bottom = r == kRingCount - 1 ? 0.5f * kPi : (15.0f * float(r) + 7.5f) * deg;
      c.cos_top[i] = std::cos(top);
      c.cos_bottom[i] = r == kRingCount - 1 ? 0.0f : std::cos(bottom);
      c.cell_solid_angle[i] = kTwoPi * (c.cos_top[i] - c.cos_bottom[i]) / float(kRingSizes[i]);
      c.cos_ring[i] = std::cos(kRingStepDeg * float(r) * deg);
    }
    return c;
  }();
  return cells;
}

}  // namespace btfrt::detail
