// Linear RGB triple. A type of its own so that colours and directions cannot be mixed up.
#pragma once

#include <algorithm>
#include <cmath>

namespace btf {

struct Rgb {
  float r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr explicit Rgb(float v) : r(v), g(v), b(v) {}
  constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}

  constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }

  constexpr Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Rgb& operator-=(const Rgb& o) { r -= o.r; g -= o.g; b -= o.b; return *this; }
  constexpr Rgb& operator*=(const Rgb& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
  constexpr Rgb& operator*=(float s) { r *= s; g *= s; b *= s; return *this; }
  constexpr Rgb& operator/=(float s) { return *this *= 1.0f / s; }

  // Rec. 709 / sRGB primaries.
  constexpr float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
  constexpr float maxComponent() const { return std::max(r, std::max(g, b)); }
  constexpr float minComponent() const { return std::min(r, std::min(g, b)); }
  constexpr float average() const { return (r + g + b) / 3.0f; }
  constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }

  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

constexpr Rgb operator+(Rgb a, const Rgb& b) { return a += b; }
constexpr Rgb operator-(Rgb a, const Rgb& b) { return a -= b; }
constexpr Rgb operator*(Rgb a, const Rgb& b) { return a *= b; }
constexpr Rgb operator*(Rgb a, float s) { return a *= s; }
constexpr Rgb operator*(float s, Rgb a) { return a *= s; }
constexpr Rgb operator/(Rgb a, float s) { return a /= s; }

}  // namespace btf
