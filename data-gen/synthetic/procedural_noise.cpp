#include "procedural_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace btf::synthetic {
namespace {

int wrap(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

// Quintic fade (Perlin 2002): continuous second derivative, so normals have no creases at cells.
float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

}  // namespace

int latticeCells(float period, float feature_size) {
  return std::max(1, int(std::lround(period / std::max(feature_size, 1e-3f))));
}

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

float periodicValueNoise(glm::vec2 p, glm::vec2 period, int cells_x, int cells_y, std::uint64_t key) {
  const float x = p.x / period.x * float(cells_x), y = p.y / period.y * float(cells_y);
  const float fx = std::floor(x), fy = std::floor(y);
  const int ix = int(fx), iy = int(fy);
  const float tx = fade(x - fx), ty = fade(y - fy);
  auto corner = [&](int i, int j) {
    return 2.0f * hash01(key, wrap(ix + i, cells_x), wrap(iy + j, cells_y)) - 1.0f;
  };
  const float a = corner(0, 0) + (corner(1, 0) - corner(0, 0)) * tx;
  const float b = corner(0, 1) + (corner(1, 1) - corner(0, 1)) * tx;
  return a + (b - a) * ty;
}

float periodicFbm(glm::vec2 p, glm::vec2 period, float feature_size, int octaves, std::uint64_t key) {
  float sum = 0.0f, amplitude = 1.0f, norm = 0.0f, size = feature_size;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * periodicValueNoise(p, period, latticeCells(period.x, size), latticeCells(period.y, size),
                                          mix64(key + std::uint64_t(o)));
    norm += amplitude;
    amplitude *= 0.5f;
    size *= 0.5f;
  }
  return sum / norm;
}

VoronoiSample periodicVoronoi(glm::vec2 p, glm::vec2 period, float cell_size, float jitter, std::uint64_t key) {
  const int nx = latticeCells(period.x, cell_size), ny = latticeCells(period.y, cell_size);
  const glm::vec2 cell(period.x / float(nx), period.y / float(ny));
  const int cx = int(std::floor(p.x / cell.x)), cy = int(std::floor(p.y / cell.y));
  VoronoiSample s;
  s.f1 = s.f2 = std::numeric_limits<float>::max();
  // With jitter <= 1 the two nearest points lie within two cells of p's cell.
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      const int wx = wrap(cx + i, nx), wy = wrap(cy + j, ny);
      const glm::vec2 offset(0.5f + jitter * (hash01(key, wx, wy, 1) - 0.5f),
                             0.5f + jitter * (hash01(key, wx, wy, 2) - 0.5f));
      const glm::vec2 point = (glm::vec2(float(cx + i), float(cy + j)) + offset) * cell;
      const glm::vec2 d = point - p;
      const float dist = glm::length(d);
      if (dist < s.f1) {
        s.f2 = s.f1;
        s.f1 = dist;
        s.cell = std::uint64_t(wy) * std::uint64_t(nx) + std::uint64_t(wx);
        s.to_nearest = d;
      } else if (dist < s.f2) {
        s.f2 = dist;
      }
    }
  return s;
}

}  // namespace btf::synthetic
