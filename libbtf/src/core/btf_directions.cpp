#include "btf/core/btf_directions.h"

#include <cmath>

#include "btf/core/math.h"

namespace btf {

const std::array<BtfDirection, kBtfDirectionCount>& btfDirections() {
  static const std::array<BtfDirection, kBtfDirectionCount> directions = [] {
    std::array<BtfDirection, kBtfDirectionCount> d{};
    for (int ring = 0; ring < kBtfRingCount; ++ring)
      for (int j = 0; j < btfRingSize(ring); ++j) {
        const float theta = btfRingThetaDeg(ring), phi = 360.0f * float(j) / float(btfRingSize(ring));
        d[std::size_t(btfDirectionIndex(ring, j))] =
            BtfDirection{ring, j, theta, phi, sphericalDirection(theta * kPi / 180.0f, phi * kPi / 180.0f)};
      }
    return d;
  }();
  return directions;
}

std::optional<int> findBtfDirection(float theta_deg, float phi_deg) {
  if (!std::isfinite(theta_deg) || !std::isfinite(phi_deg)) return std::nullopt;
  const float ring_f = theta_deg / kBtfRingStepDeg;
  const int ring = int(std::lround(ring_f));
  if (ring < 0 || ring >= kBtfRingCount || std::abs(theta_deg - btfRingThetaDeg(ring)) > 0.5f) return std::nullopt;
  if (ring == 0) return 0;
  float phi = std::fmod(phi_deg, 360.0f);
  if (phi < 0.0f) phi += 360.0f;
  const float step = 360.0f / float(btfRingSize(ring));
  int j = int(std::lround(phi / step));
  if (std::abs(phi - float(j) * step) > 0.5f) return std::nullopt;
  if (j == btfRingSize(ring)) j = 0;
  return btfDirectionIndex(ring, j);
}

}  // namespace btf
