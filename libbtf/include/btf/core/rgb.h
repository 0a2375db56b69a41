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

// CIE XYZ (D65 white, Y of the white 1) <-> linear Rec.709 / sRGB primaries, by IEC 61966-2-1's
// matrices. Colours outside the Rec.709 gamut come out with negative components.
constexpr Rgb xyzToLinearRec709(const Rgb& xyz) {
  return Rgb(3.2404542f * xyz.r - 1.5371385f * xyz.g - 0.4985314f * xyz.b,
             -0.9692660f * xyz.r + 1.8760108f * xyz.g + 0.0415560f * xyz.b,
             0.0556434f * xyz.r - 0.2040259f * xyz.g + 1.0572252f * xyz.b);
}
constexpr Rgb linearRec709ToXyz(const Rgb& rgb) {
  return Rgb(0.4124564f * rgb.r + 0.3575761f * rgb.g + 0.1804375f * rgb.b,
             0.2126729f * rgb.r + 0.7151522f * rgb.g + 0.0721750f * rgb.b,
             0.0193339f * rgb.r + 0.1191920f * rgb.g + 0.9503041f * rgb.b);
}

}  // namespace btf
