// A pinhole camera and the rays it shoots. World space is right-handed; the image's x runs right
// and y runs down, as in the files we write.
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace btf::render {

struct Ray {
  glm::vec3 origin;
  glm::vec3 direction;  // unit length
  float tmin = 0.0f;
  float tmax = std::numeric_limits<float>::infinity();
};

struct CameraSettings {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 look_at{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  // Full field of view across the image's shorter side (as pbrt's "fov"), in degrees.
  float fov_deg = 40.0f;
  int width = 256;
  int height = 256;
};

class PinholeCamera {
 public:
  // Throws btf::Error for a field of view outside (0, 180), a size below 1 pixel, a look-at equal
  // to the position, an up vector parallel to the view direction, or anything not finite.
  explicit PinholeCamera(const CameraSettings& settings);

  // The ray through a point on the film in pixel units ((0, 0) is the top-left corner of the image,
  // (width, height) the bottom-right one).
  Ray generateRay(glm::vec2 film) const;
  const CameraSettings& settings() const { return settings_; }

 private:
  CameraSettings settings_;
  glm::vec3 forward_, right_, down_;  // right_ and down_ span one pixel each on the plane at distance 1
  glm::vec3 top_left_;                // direction to the film's top-left corner
};

}  // namespace btf::render
