#include "synthetic_btf.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "btf/core/error.h"
#include "btf/core/frame.h"

namespace btf::synthetic {
namespace {

int wrapIndex(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

// Bisection steps that refine a view-ray crossing: the interval shrinks below 1e-5 texel.
constexpr int kBisectionSteps = 18;
// Shadow rays must rise this far (texels) below the surface before they count as blocked, so the
// bilinear surface does not shadow the very point it starts from.
constexpr float kShadowBias = 1e-3f;

}  // namespace

namespace {

// n points of a spherical Fibonacci spiral over the cap theta <= 80 degrees (equal solid angle per
// point), turned by `turn` degrees.
std::vector<BtfAngles> fibonacciCap(int n, float turn) {
  constexpr double kGolden = 137.50776405003785;  // degrees
  const double cos_max = std::cos(80.0 * 3.14159265358979323846 / 180.0);
  std::vector<BtfAngles> out;
  for (int i = 0; i < n; ++i) {
    const double cos_theta = 1.0 - (double(i) + 0.5) / double(n) * (1.0 - cos_max);
    const double theta = std::acos(cos_theta) * 180.0 / 3.14159265358979323846;
    const double phi = std::fmod(double(i) * kGolden + double(turn), 360.0);
    out.push_back({float(theta), float(phi)});
  }
  return out;
}

}  // namespace

BtfDirectionSetPtr scatteredDirectionSet(int views, int lights) {
  if (views < 1 || lights < 1) throw Error("a scattered direction set needs at least one view and one light");
  std::vector<std::vector<BtfAngles>> light_lists;
  for (int v = 0; v < views; ++v) light_lists.push_back(fibonacciCap(lights, 7.0f * float(v)));
  return std::make_shared<const BtfDirectionSet>("scattered", fibonacciCap(views, 0.0f), std::move(light_lists));
}

SyntheticBtf::SyntheticBtf(Microgeometry geometry, std::string name, SyntheticBtfOptions options)
    : geometry_(std::move(geometry)), name_(std::move(name)), options_(options) {
  if (!options_.directions) throw Error(name_ + ": a synthetic BTF needs a direction set");
  views_ = BtfViewSet::all(options_.directions);
  geometry_.validate();
  const int gw = geometry_.gridWidth(), gh = geometry_.gridHeight();
  const float spacing = 1.0f / float(geometry_.samples_per_texel);
  gradients_.resize(geometry_.gridSize());
  min_height_ = max_height_ = geometry_.heights[0];
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx) {
      auto h = [&](int x, int y) { return geometry_.heights[geometry_.gridIndex(wrapIndex(x, gw), wrapIndex(y, gh))]; };
      gradients_[geometry_.gridIndex(gx, gy)] =
          glm::vec2(h(gx + 1, gy) - h(gx - 1, gy), h(gx, gy + 1) - h(gx, gy - 1)) / (2.0f * spacing);
      min_height_ = std::min(min_height_, h(gx, gy));
      max_height_ = std::max(max_height_, h(gx, gy));
    }
  step_ = 0.5f * spacing;
}

// The grid samples around a texel-space point (periodic) and its bilinear weights.
SyntheticBtf::GridCell SyntheticBtf::cellAt(float x, float y) const {
  const int gw = geometry_.gridWidth(), gh = geometry_.gridHeight();
  const float u = x * float(geometry_.samples_per_texel) - 0.5f, v = y * float(geometry_.samples_per_texel) - 0.5f;
  const float fu = std::floor(u), fv = std::floor(v);
  GridCell c;
  c.tu = u - fu, c.tv = v - fv;
  c.x0 = wrapIndex(int(fu), gw), c.y0 = wrapIndex(int(fv), gh);
  c.x1 = c.x0 + 1 == gw ? 0 : c.x0 + 1, c.y1 = c.y0 + 1 == gh ? 0 : c.y0 + 1;
  return c;
}

float SyntheticBtf::heightAt(float x, float y) const {
  const GridCell c = cellAt(x, y);
  auto h = [&](int gx, int gy) { return geometry_.heights[geometry_.gridIndex(gx, gy)]; };
  const float a = h(c.x0, c.y0) + (h(c.x1, c.y0) - h(c.x0, c.y0)) * c.tu;
  const float b = h(c.x0, c.y1) + (h(c.x1, c.y1) - h(c.x0, c.y1)) * c.tu;
  return a + (b - a) * c.tv;
}

glm::vec2 SyntheticBtf::gradientAt(float x, float y) const {
  const GridCell c = cellAt(x, y);
  auto g = [&](int gx, int gy) { return gradients_[geometry_.gridIndex(gx, gy)]; };
  const glm::vec2 a = g(c.x0, c.y0) + (g(c.x1, c.y0) - g(c.x0, c.y0)) * c.tu;
  const glm::vec2 b = g(c.x0, c.y1) + (g(c.x1, c.y1) - g(c.x0, c.y1)) * c.tu;
  return a + (b - a) * c.tv;
}

std::size_t SyntheticBtf::nearestSample(float x, float y) const {
  const int gx = wrapIndex(int(std::floor(x * float(geometry_.samples_per_texel))), geometry_.gridWidth());
  const int gy = wrapIndex(int(std::floor(y * float(geometry_.samples_per_texel))), geometry_.gridHeight());
  return geometry_.gridIndex(gx, gy);
}

glm::vec3 SyntheticBtf::viewHit(int x, int y, const glm::vec3& wo) const {
  const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
  const glm::vec2 across(wo.x, wo.y);
  const float sin_theta = glm::length(across);
  if (sin_theta < 1e-6f) return {centre, heightAt(centre.x, centre.y)};
  // The ray is centre + t (wo.xy, wo.z), descending as t decreases; parametrize by the height
  // above the reference plane: z(t) = t wo.z. Start where it enters the slab [min, max] height.
  auto point = [&](float t) { return glm::vec3(centre + t * across, t * wo.z); };
  auto above = [&](float t) {
    const glm::vec3 p = point(t);
    return p.z - heightAt(p.x, p.y);
  };
  const float t_top = max_height_ / wo.z, t_bottom = min_height_ / wo.z;
  const float dt = step_ / sin_theta;
  float t_prev = t_top;
  if (above(t_top) <= 0.0f) return point(t_top);
  for (float t = t_top - dt;; t -= dt) {
    const float t_clamped = std::max(t, t_bottom);
    if (above(t_clamped) <= 0.0f) {
      float hi = t_prev, lo = t_clamped;  // above at hi, on or below at lo
      for (int i = 0; i < kBisectionSteps; ++i) {
        const float mid = 0.5f * (hi + lo);
        (above(mid) > 0.0f ? hi : lo) = mid;
      }
      const glm::vec3 p = point(lo);
      return {p.x, p.y, heightAt(p.x, p.y)};
    }
    if (t_clamped <= t_bottom) break;
    t_prev = t_clamped;
  }
  // Not reached for a single-valued field (the ray ends at the lowest height), kept for rounding.
  const glm::vec3 p = point(t_bottom);
  return {p.x, p.y, heightAt(p.x, p.y)};
}

bool SyntheticBtf::occluded(const glm::vec3& p, const glm::vec3& wi) const {
  const float sin_theta = std::hypot(wi.x, wi.y);
  if (sin_theta < 1e-6f || p.z >= max_height_) return false;  // nothing of a height field is above
  const float dt = step_ / sin_theta;
  const float t_end = (max_height_ - p.z) / wi.z;
  for (float t = dt; t < t_end; t += dt) {
    const glm::vec3 q = p + t * wi;
    if (q.z < heightAt(q.x, q.y) - kShadowBias) return true;
  }
  return false;
}

void SyntheticBtf::loadView(int view, std::vector<Rgb>& out) const {
  views_.require(view, name_);
  const BtfDirectionSet& set = *options_.directions;
  const glm::vec3 wo = set.view(view);
  const std::span<const glm::vec3> lights = set.lightDirections(view);
  const int w = width(), h = height();
  const std::size_t texels = texelCount();
  out.resize(texels * lights.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec3 hit = viewHit(x, y, wo);
        const glm::vec2 g = gradientAt(hit.x, hit.y);
        const glm::vec3 n = glm::normalize(glm::vec3(-g.x, -g.y, 1.0f));
        const std::size_t s = nearestSample(hit.x, hit.y);
        const float angle = geometry_.tangent_angles[s];
        const Frame frame = Frame::fromNormalTangent(n, glm::vec3(std::cos(angle), std::sin(angle), 0.0f));
        const Material& material = *geometry_.materials[geometry_.material_ids[s]];
        const Rgb tint = geometry_.tints[s];
        const glm::vec3 wo_local = frame.toLocal(wo);
        const glm::vec2 uv((hit.x) / float(w), (hit.y) / float(h));
        const std::size_t texel = std::size_t(y) * std::size_t(w) + std::size_t(x);
        for (std::size_t light = 0; light < lights.size(); ++light) {
          const glm::vec3 wi = lights[light];
          const float cos_hit = glm::dot(n, wi);
          Rgb value;
          if (cos_hit > 0.0f && wo_local.z > 0.0f && !(options_.shadows && occluded(hit, wi)))
            value = tint * material.eval(frame.toLocal(wi), wo_local, uv) * (cos_hit / wi.z);
          out[light * texels + texel] = value;
        }
      }
  });
}

}  // namespace btf::synthetic
