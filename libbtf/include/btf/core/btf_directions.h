// The 81-direction set of image-based measured BTFs (Bonn UBO2003 layout): six rings of constant
// elevation theta = 0, 15, 30, 45, 60, 75 degrees holding 1, 6, 12, 18, 20, 24 directions at
// equally spaced azimuths phi = j * 360 / count degrees (j = 0 .. count - 1). Views and lights use
// the same set. Index order: ring by ring from the pole, azimuth increasing within a ring.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include <glm/glm.hpp>

namespace btf {

struct BtfDirection {
  int ring;          // 0 .. 5
  int azimuth;       // 0 .. ringSize(ring) - 1
  float theta_deg;   // elevation from the normal
  float phi_deg;     // azimuth from +x
  glm::vec3 w;       // unit vector in the local frame
};

inline constexpr int kBtfDirectionCount = 81;
inline constexpr int kBtfRingCount = 6;
inline constexpr std::array<int, kBtfRingCount> kBtfRingSizes{1, 6, 12, 18, 20, 24};
inline constexpr std::array<int, kBtfRingCount> kBtfRingStarts{0, 1, 7, 19, 37, 57};
inline constexpr float kBtfRingStepDeg = 15.0f;

constexpr int btfRingSize(int ring) { return kBtfRingSizes[std::size_t(ring)]; }
constexpr int btfRingStart(int ring) { return kBtfRingStarts[std::size_t(ring)]; }
constexpr float btfRingThetaDeg(int ring) { return kBtfRingStepDeg * float(ring); }
constexpr int btfDirectionIndex(int ring, int azimuth) { return btfRingStart(ring) + azimuth; }

// All 81 directions in index order.
const std::array<BtfDirection, kBtfDirectionCount>& btfDirections();
// The index of the set direction with exactly these angles (degrees, within 0.5 degree; phi taken
// modulo 360, and any phi at theta = 0), or nothing.
std::optional<int> findBtfDirection(float theta_deg, float phi_deg);

}  // namespace btf
