#include "btf/render/environment_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "btf/core/cdf1d.h"
#include "btf/core/error.h"
#include "btf/core/value_limits.h"

namespace btf::render {
namespace {

constexpr double kPiD = std::numbers::pi;
constexpr float kTwoPiF = 2.0f * std::numbers::pi_v<float>;

std::string formatFloat(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

void requireValidScale(float scale, const std::string& source_name) {
  if (!(std::isfinite(scale) && scale > 0.0f))
    throw Error("environment map " + source_name + ": the scale must be finite and > 0, got " + formatFloat(scale));
}

bool usableDirection(const glm::vec3& d) {
  return std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f);
}

// The cell of x in [0, 1] among n equal cells (x = 1 belongs to the last).
int cellOf(float x, int n) { return std::min(static_cast<int>(x * float(n)), n - 1); }

}  // namespace

EnvironmentMap::EnvironmentMap(const Image& rgb, float scale, std::string source_name)
    : source_name_(std::move(source_name)) {
  requireValidScale(scale, source_name_);
  if (rgb.width <= 0 || rgb.height <= 0)
    throw FileError(source_name_, "environment map has no pixels (" + std::to_string(rgb.width) + "x" +
                                      std::to_string(rgb.height) + ")");
  if (rgb.channels < 3)
    throw FileError(source_name_, "environment map has " + std::to_string(rgb.channels) +
                                      " channel(s), at least 3 (linear RGB) are needed");
  if (rgb.pixels.size() != std::size_t(rgb.width) * std::size_t(rgb.height) * std::size_t(rgb.channels))
    throw FileError(source_name_, "environment map pixel data does not match its size");
  width_ = rgb.width;
  height_ = rgb.height;
  const std::size_t w = std::size_t(width_), h = std::size_t(height_);

  // ---- Radiance, checked value by value.
  radiance_.resize(w * h);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      Rgb& out = radiance_[std::size_t(y) * w + std::size_t(x)];
      for (int c = 0; c < 3; ++c) {
        const float v = rgb.at(x, y, c);
        const std::string where = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                                  std::to_string(c);
        if (std::isnan(v)) throw FileError(source_name_, where + " is NaN");
        if (std::isinf(v)) throw FileError(source_name_, where + " is infinite");
        if (v < 0.0f) throw FileError(source_name_, where + " is negative (" + formatFloat(v) + ")");
        const float scaled = v * scale;
        if (!std::isfinite(scaled) || scaled > kMaxRadiance)
          throw FileError(source_name_, where + " is " + formatFloat(v) + (scale != 1.0f ? " x scale " + formatFloat(scale) : "") +
                                            ", beyond the largest radiance a scene may hold (" + formatFloat(kMaxRadiance) + ")");
        out[c] = scaled;
      }
    }

  // ---- Row geometry: cos(theta) at the row edges, exactly 1 and -1 at the poles.
  cos_theta_edges_.resize(h + 1);
  for (std::size_t y = 0; y <= h; ++y) cos_theta_edges_[y] = std::cos(kPiD * double(y) / double(h));
  cos_theta_edges_[0] = 1.0;
  cos_theta_edges_[h] = -1.0;
  inv_pixel_solid_angle_.resize(h);
  for (std::size_t y = 0; y < h; ++y)
    inv_pixel_solid_angle_[y] =
        static_cast<float>(double(w) / (2.0 * kPiD * (cos_theta_edges_[y] - cos_theta_edges_[y + 1])));

  // ---- Mean radiance over the sphere: sum of L * pixel solid angle / (4 pi), in double.
  double sum[3] = {0, 0, 0};
  for (std::size_t y = 0; y < h; ++y) {
    double row[3] = {0, 0, 0};
    for (std::size_t x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) row[c] += radiance_[y * w + x][c];
    // pixel solid angle / (4 pi) = (cos_edge[y] - cos_edge[y+1]) / (2 w)
    const double weight = (cos_theta_edges_[y] - cos_theta_edges_[y + 1]) / (2.0 * double(w));
    for (int c = 0; c < 3; ++c) sum[c] += row[c] * weight;
  }
  mean_radiance_ = Rgb(float(sum[0]), float(sum[1]), float(sum[2]));

  // ---- Sampling weights and CDFs.
  const double mean_luminance = 0.2126 * sum[0] + 0.7152 * sum[1] + 0.0722 * sum[2];
  const bool all_black = !(mean_luminance > 0.0);
  const float floor = std::max(static_cast<float>(kSamplingFloor * mean_luminance), std::numeric_limits<float>::min());
  column_cdfs_.resize(h * (w + 1));
  std::vector<float> weights(w);
  std::vector<double> row_weights(h);
  double largest_row = 0.0;
  for (std::size_t y = 0; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) {
      const Rgb& L = radiance_[y * w + x];
      weights[x] = all_black ? 1.0f : (L.isBlack() ? 0.0f : std::max(L.luminance(), floor));
    }
    const double row_mean = buildCdf1D(weights, std::span<float>(column_cdfs_).subspan(y * (w + 1), w + 1));
    row_weights[y] = row_mean * (cos_theta_edges_[y] - cos_theta_edges_[y + 1]);
    largest_row = std::max(largest_row, row_weights[y]);
  }
  // Normalized by the largest row before the conversion to float, so that neither tiny nor huge
  // weights under- or overflow.
  std::vector<float> row_weights_f(h);
  for (std::size_t y = 0; y < h; ++y) row_weights_f[y] = static_cast<float>(row_weights[y] / largest_row);
  row_cdf_.resize(h + 1);
  buildCdf1D(row_weights_f, row_cdf_);
}

EnvironmentMap EnvironmentMap::load(const std::filesystem::path& exr, float scale) {
  requireValidScale(scale, exr.string());  // before reading a possibly large file
  // By content: a PNG or JPEG holds display values, not radiance, whatever its name says.
  std::error_code ec;
  const std::string format = imageFileFormat(exr);
  if (std::filesystem::is_regular_file(exr, ec) && format != "openexr")  // (a missing file: readImage says so)
    throw FileError(exr, "is " + (format.empty() ? std::string("not an image libbtf reads") : "a " + format + " image") +
                             ", not OpenEXR: an environment map holds linear radiance (convert it, e.g. oiiotool IN "
                             "--colorconvert sRGB linear -o map.exr)");
  return EnvironmentMap(readImage(exr), scale, exr.string());
}

std::span<const float> EnvironmentMap::columnCdf(int row) const {
  const std::size_t n = std::size_t(width_) + 1;
  return std::span<const float>(column_cdfs_).subspan(std::size_t(row) * n, n);
}

glm::vec2 EnvironmentMap::directionToUv(const glm::vec3& d) {
  // atan2 rather than acos: acos loses half the digits near the poles.
  const float theta = std::atan2(std::hypot(d.x, d.z), d.y);
  float phi = std::atan2(d.z, d.x);
  if (phi < 0.0f) phi += kTwoPiF;
  return {std::clamp(phi / kTwoPiF, 0.0f, 1.0f), std::clamp(theta / std::numbers::pi_v<float>, 0.0f, 1.0f)};
}

glm::vec3 EnvironmentMap::uvToDirection(glm::vec2 uv) {
  const float phi = uv.x * kTwoPiF, theta = uv.y * std::numbers::pi_v<float>;
  const float sin_theta = std::sin(theta);
  return {sin_theta * std::cos(phi), std::cos(theta), sin_theta * std::sin(phi)};
}

glm::ivec2 EnvironmentMap::pixelOf(const glm::vec3& direction) const {
  const glm::vec2 uv = directionToUv(direction);
  return {cellOf(uv.x, width_), cellOf(uv.y, height_)};
}

Rgb EnvironmentMap::eval(const glm::vec3& direction) const {
  if (!usableDirection(direction)) return Rgb(0.0f);
  const glm::ivec2 p = pixelOf(direction);
  return pixel(p.x, p.y);
}

float EnvironmentMap::pdf(const glm::vec3& direction) const {
  if (!usableDirection(direction)) return 0.0f;
  const glm::ivec2 p = pixelOf(direction);
  const std::span<const float> columns = columnCdf(p.y);
  const float row_probability = row_cdf_[std::size_t(p.y) + 1] - row_cdf_[std::size_t(p.y)];
  const float column_probability = columns[std::size_t(p.x) + 1] - columns[std::size_t(p.x)];
  return row_probability * column_probability * inv_pixel_solid_angle_[std::size_t(p.y)];
}

std::optional<EnvironmentSample> EnvironmentMap::sample(glm::vec2 u) const {
  // Row by the marginal; u.y's place inside the row (remapped) becomes cos(theta), uniform between
  // the row's edges, so the direction is uniform in solid angle inside the pixel.
  const Cdf1DSample row = sampleCdf1D(row_cdf_, u.y);
  const int y = static_cast<int>(row.cell);
  const Cdf1DSample column = sampleCdf1D(columnCdf(y), u.x);
  const double c0 = cos_theta_edges_[std::size_t(y)], c1 = cos_theta_edges_[std::size_t(y) + 1];
  const double cos_theta = std::clamp(c0 + double(row.remapped) * (c1 - c0), -1.0, 1.0);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPiD * double(column.x);
  const glm::vec3 direction{static_cast<float>(sin_theta * std::cos(phi)), static_cast<float>(cos_theta),
                            static_cast<float>(sin_theta * std::sin(phi))};
  // pdf and radiance of the direction as returned, so that they equal pdf() and eval() exactly
  // even where rounding moved it across a pixel edge.
  const float density = pdf(direction);
  if (!(density > 0.0f)) return std::nullopt;
  return EnvironmentSample{direction, eval(direction), density};
}

}  // namespace btf::render
