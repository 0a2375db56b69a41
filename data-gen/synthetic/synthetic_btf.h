// Synthetic BTFs that behave like measured ones: a virtual gonioreflectometer observing a
// procedural microgeometry (microgeometry.h, btf_patterns.h) from the 81 x 81 directions, or from
// any direction set (the Bonn dome's 151, a scattered one).
//
// Per view and light, for each texel: the orthographic view ray through the texel centre of the
// reference plane (height 0) meets the height field, so the texel shows whatever it hits
// (parallax, masking); a shadow ray from the hit point towards the light decides visibility
// (self-shadowing). The value is the apparent BRDF an image-based measurement records:
//   f(material at the hit; wi, wo in the hit point's tangent frame) * tint
//     * max(0, n.wi) / cos(theta_light) * visibility,
// so a flat surface gives f exactly. Interreflections between facets are left out (they would
// need a path tracer per entry; they brighten concave regions a little in real data).
//
// SyntheticBtf renders a view on demand in loadView (TBB-parallel over texel rows, each texel a
// pure function of the geometry, so the output is identical for any thread count): a 256 x 256
// BTF streams into a compressor without its 5 GiB ever being stored.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "btf/io/btf_data.h"
#include "microgeometry.h"

namespace btf::synthetic {

struct SyntheticBtfOptions {
  bool shadows = true;  // false: every light reaches every hit point (for tests of the shadowing)
  BtfDirectionSetPtr directions = BtfDirectionSet::ubo2003();  // where the gonioreflectometer looks from
};

// A scattered direction set that no ring structure serves, for tests and generated data: `views`
// views and, per view, `lights` lights on spherical Fibonacci spirals over the cap theta <= 80
// degrees, each view's spiral turned by its own angle (view-dependent light lists).
BtfDirectionSetPtr scatteredDirectionSet(int views, int lights);

class SyntheticBtf final : public BtfSource {
 public:
  SyntheticBtf(Microgeometry geometry, std::string name, SyntheticBtfOptions options = {});

  int width() const override { return geometry_.width; }
  int height() const override { return geometry_.height; }
  std::string name() const override { return name_; }
  const BtfViewSet& views() const override { return views_; }
  void loadView(int view, std::vector<Rgb>& out) const override;

  const Microgeometry& geometry() const { return geometry_; }
  float minHeight() const { return min_height_; }
  float maxHeight() const { return max_height_; }

  // The surface point the view ray through texel centre (x + 0.5, y + 0.5) hits, for tests.
  glm::vec3 viewHit(int x, int y, const glm::vec3& wo) const;

 private:
  struct GridCell {
    int x0, y0, x1, y1;
    float tu, tv;
  };
  GridCell cellAt(float x, float y) const;
  float heightAt(float x, float y) const;            // bilinear, periodic (texel units)
  glm::vec2 gradientAt(float x, float y) const;      // bilinear of the sample gradients
  std::size_t nearestSample(float x, float y) const;
  bool occluded(const glm::vec3& p, const glm::vec3& wi) const;

  Microgeometry geometry_;
  std::string name_;
  SyntheticBtfOptions options_;
  BtfViewSet views_;
  std::vector<glm::vec2> gradients_;  // dh/dx, dh/dy per grid sample (central differences)
  float min_height_ = 0, max_height_ = 0;
  float step_ = 0;  // horizontal ray-marching step (texels): half a grid cell
};

}  // namespace btf::synthetic
