// Private helpers shared by the analytic models: argument validation with one message style,
// parameter formatting for name(), and picking a mixture component from one uniform number.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

#include "btf/core/error.h"
#include "btf/core/frame.h"
#include "btf/core/math.h"
#include "btf/core/rgb.h"
#include "btf/core/value_limits.h"
#include "btf/core/warp.h"

namespace btf::detail {

inline std::string formatRgb(const Rgb& c) {
  std::ostringstream out;
  out << '(' << c.r << ',' << c.g << ',' << c.b << ')';
  return out.str();
}

inline std::string formatFloat(float v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// Albedos are reflectances: finite and non-negative in every channel, and at most `max`: 1 for a
// diffuse albedo (a surface reflects no more than it receives), kMaxReflectance for the weights of
// lobes whose normalization is the model's own.
inline void requireAlbedo(const char* model, const char* parameter, const Rgb& value, float max = kMaxReflectance) {
  if (!value.isFinite() || value.minComponent() < 0.0f || value.maxComponent() > max)
    throw Error(std::string(model) + ": " + parameter + " must be finite and in [0, " + formatFloat(max) +
                "] in every channel, got " + formatRgb(value));
}
inline void requireDiffuseAlbedo(const char* model, const char* parameter, const Rgb& value) {
  requireAlbedo(model, parameter, value, 1.0f);
}

inline void requirePositive(const char* model, const char* parameter, float value) {
  if (!std::isfinite(value) || !(value > 0.0f))
    throw Error(std::string(model) + ": " + parameter + " must be finite and > 0, got " + formatFloat(value));
}

inline void requireNonNegative(const char* model, const char* parameter, float value) {
  if (!std::isfinite(value) || !(value >= 0.0f))
    throw Error(std::string(model) + ": " + parameter + " must be finite and >= 0, got " + formatFloat(value));
}

// Mixture selection: returns true with probability p and rescales u to a fresh uniform number in
// [0, 1), so one dimension of the sample serves both the choice and the chosen warp.
inline bool chooseFirst(float p, float& u) {
  if (u < p) {
    u = std::min(u / p, 0x1.fffffep-1f);
    return true;
  }
  u = std::min((u - p) / (1.0f - p), 0x1.fffffep-1f);
  return false;
}

// A cos^exponent lobe around an arbitrary unit axis (Phong and Lafortune lobes). The density
// depends only on the angle to the axis, so the frame chosen around it does not matter.
inline glm::vec3 sampleLobeAround(const glm::vec3& axis, float exponent, glm::vec2 u) {
  return Frame::fromNormal(axis).toWorld(squareToCosinePowerHemisphere(u, exponent));
}
inline float lobePdf(float cos_to_axis, float exponent) {
  return cos_to_axis > 0.0f ? (exponent + 1.0f) * kInv2Pi * std::pow(cos_to_axis, exponent) : 0.0f;
}

}  // namespace btf::detail
