#include "btf/render/camera.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"

namespace btf::render {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

PinholeCamera::PinholeCamera(const CameraSettings& s) : settings_(s) {
  if (!(s.fov_deg > 0.0f && s.fov_deg < 180.0f))
    throw Error("camera: fov_deg must lie in (0, 180), got " + std::to_string(s.fov_deg));
  if (s.width < 1 || s.height < 1)
    throw Error("camera: resolution must be at least 1 x 1, got " + std::to_string(s.width) + " x " +
                std::to_string(s.height));
  if (!finite(s.position) || !finite(s.look_at) || !finite(s.up)) throw Error("camera: position, look_at and up must be finite");
  const glm::vec3 view = s.look_at - s.position;
  if (!std::isfinite(glm::length(view)) || !std::isfinite(glm::length(s.up)))
    throw Error("camera: the position, look_at or up is too large (their distances overflow a float)");
  if (!(glm::length(view) > 0.0f)) throw Error("camera: look_at equals the position");
  forward_ = glm::normalize(view);
  const glm::vec3 side = glm::cross(forward_, s.up);
  if (!(glm::length(side) > 1e-6f * glm::length(s.up))) throw Error("camera: up is parallel to the view direction");
  const glm::vec3 right = glm::normalize(side);
  const glm::vec3 up = glm::cross(right, forward_);
  // The shorter side spans 2 tan(fov / 2) at distance 1.
  const float shorter = float(std::min(s.width, s.height));
  const float pixel = 2.0f * std::tan(0.5f * s.fov_deg * kPi / 180.0f) / shorter;
  right_ = right * pixel;
  down_ = -up * pixel;
  top_left_ = forward_ - right_ * (0.5f * float(s.width)) - down_ * (0.5f * float(s.height));
}

Ray PinholeCamera::generateRay(glm::vec2 film) const {
  return Ray{settings_.position, glm::normalize(top_left_ + right_ * film.x + down_ * film.y)};
}

}  // namespace btf::render
