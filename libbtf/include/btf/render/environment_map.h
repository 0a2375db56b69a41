// A lat-long (equirectangular) environment map light, importance-sampled by luminance.
//
// Convention (world space, not the shading frame of material.h):
// - World up is +y. A unit direction d has the polar angle theta = acos(d.y) in [0, pi], measured
//   from +y, and the azimuth phi = atan2(d.z, d.x) wrapped to [0, 2 pi), measured from +x towards +z.
// - Image coordinates: u = phi / (2 pi) across the columns (left edge phi = 0, i.e. +x; a quarter
//   of the way across phi = pi/2, i.e. +z), v = theta / pi down the rows (top row = +y, bottom row
//   = -y). Pixel (x, y) covers u in [x, x+1) / width and v in [y, y+1) / height; its centre is at
//   ((x + 0.5) / width, (y + 0.5) / height). The seam phi = 0 lies between the last column and the
//   first; a direction on it (u rounded to 1) belongs to the last column.
// - Lookup is nearest (piecewise constant): eval() returns the value of the pixel holding d,
//   without filtering, so that the radiance a path sees, the pdf and the power all describe the
//   same function.
//
// Sampling: a pixel is chosen with probability proportional to w(x, y) * solid_angle(row y), where
// w is the pixel's luminance (Rec. 709), and the direction is then uniform in solid angle inside
// the pixel (uniform in phi and in cos theta across the pixel). The pdf is therefore piecewise
// constant per pixel: pdf(d) = P(pixel) / solid_angle(pixel). In image (u, v) space that is the
// usual density proportional to luminance * sin(theta), integrated exactly over each row rather
// than taken at the row centre, so nothing diverges at the poles, and a constant map is sampled
// exactly uniformly (pdf 1 / (4 pi)).
//
// The sampling weight has a floor: w = max(luminance, kSamplingFloor * mean luminance) for every
// pixel with radiance > 0 (mean over the sphere, solid-angle weighted), and 0 for black pixels.
// The floor keeps pixels far dimmer than the map's bright parts (a sky beside the sun) reachable
// by light sampling, and moves at most kSamplingFloor (0.1%) of the samples. Black pixels are
// never drawn and have pdf 0. The CDFs are stored in float: a pixel whose probability within its
// row (or a row whose probability) lies below float resolution (~1e-7 of the mass) can still round
// to an empty cell; pdf() then reports 0 for it as well, so sample() and pdf() agree everywhere and
// a combination with BSDF sampling by MIS stays unbiased. An all-black map samples uniformly.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "btf/core/rgb.h"
#include "btf/io/image.h"

namespace btf::render {

struct EnvironmentSample {
  glm::vec3 direction;  // unit, world space: the direction light arrives from
  Rgb radiance;         // eval(direction)
  float pdf;            // solid-angle density, equal to pdf(direction)
};

class EnvironmentMap {
 public:
  // Fraction of the mean luminance below which no pixel with radiance > 0 is weighted (see above).
  static constexpr float kSamplingFloor = 1e-3f;

  // rgb: width x height pixels with >= 3 channels of linear radiance (channels past the third,
  // e.g. alpha, are ignored); scale multiplies every value. source_name names the data in errors.
  // Throws btf::Error for a scale that is not finite and > 0, and btf::FileError naming
  // source_name for no pixels, fewer than 3 channels, or a NaN, infinite or negative value
  // ("pixel (12, 40) channel 1 is NaN", x = column, y = row from the top).
  EnvironmentMap(const Image& rgb, float scale, std::string source_name);
  // Reads an image file (EXR, or any format btf::readImage knows) with the checks above.
  static EnvironmentMap load(const std::filesystem::path& exr, float scale);

  // Radiance arriving from `direction` (world space; need not be normalized). Black for a zero or
  // non-finite vector.
  Rgb eval(const glm::vec3& direction) const;
  // Draws a direction with density pdf() from u in [0,1)^2. Empty only in the rare case that
  // float rounding puts the direction onto a pixel of probability 0.
  std::optional<EnvironmentSample> sample(glm::vec2 u) const;
  // Solid-angle density of sample() at `direction` (0 for a zero or non-finite vector).
  float pdf(const glm::vec3& direction) const;

  // Mean radiance over the sphere, solid-angle weighted: (1 / 4 pi) * integral of L dw, summed
  // exactly pixel by pixel. A constant map has meanRadiance() = its value (the furnace test: a
  // white Lambertian surface under it reflects exactly that); the power the map sends through a
  // disk of radius r facing it from every direction is pi r^2 * 4 pi * meanRadiance() (photon
  // emission from a scene's bounding disk).
  Rgb meanRadiance() const { return mean_radiance_; }

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& sourceName() const { return source_name_; }
  // The scaled radiance of pixel (x, y), x = column, y = row from the top.
  const Rgb& pixel(int x, int y) const { return radiance_[std::size_t(y) * std::size_t(width_) + std::size_t(x)]; }

  // The mapping of the convention above. directionToUv accepts any non-zero finite vector and
  // returns u in [0, 1], v in [0, 1]; uvToDirection returns a unit vector.
  static glm::vec2 directionToUv(const glm::vec3& direction);
  static glm::vec3 uvToDirection(glm::vec2 uv);
  // The pixel (x = column, y = row) holding a direction (a non-zero finite vector).
  glm::ivec2 pixelOf(const glm::vec3& direction) const;

 private:
  std::span<const float> columnCdf(int row) const;

  int width_ = 0, height_ = 0;
  std::string source_name_;
  std::vector<Rgb> radiance_;            // scaled, row-major from the top
  std::vector<float> row_cdf_;           // height + 1 entries: the marginal over rows
  std::vector<float> column_cdfs_;       // height x (width + 1): the conditional over columns per row
  std::vector<double> cos_theta_edges_;  // height + 1 entries: cos(pi * y / height), 1 ... -1
  std::vector<float> inv_pixel_solid_angle_;  // per row: width / (2 pi (cos_edge[y] - cos_edge[y+1]))
  Rgb mean_radiance_;
};

}  // namespace btf::render
