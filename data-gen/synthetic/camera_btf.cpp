#include "camera_btf.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/io/image.h"

namespace btf::synthetic {
namespace {

void requireOption(bool ok, const std::string& what) {
  if (!ok) throw Error("camera: " + what);
}

}  // namespace

float exposureWhite(const BtfSource& source) {
  std::vector<Rgb> values;
  source.loadView(source.views().view(0), values);
  std::vector<float> channels;
  channels.reserve(values.size() * 3);
  for (const Rgb& v : values)
    for (int c = 0; c < 3; ++c) channels.push_back(v[c]);
  if (channels.empty()) return 1.0f;
  const auto nth = channels.begin() + std::ptrdiff_t(0.99 * double(channels.size() - 1));
  std::nth_element(channels.begin(), nth, channels.end());
  return *nth > 0 ? *nth : 1.0f;
}

CameraOptions measuredCameraOptions(const BtfSource& source, std::uint64_t seed) {
  CameraOptions options;
  options.white = exposureWhite(source);
  options.jitter = 0.2f;
  options.read_noise = 0.008f;
  options.shot_noise = 0.02f;
  options.quantize = true;
  options.seed = seed;
  return options;
}

CameraBtf::CameraBtf(const BtfSource& source, const CameraOptions& options)
    : source_(source), options_(options), name_(source.name() + " (camera)") {
  requireOption(std::isfinite(options.white) && options.white > 0, "white must be finite and > 0");
  requireOption(std::isfinite(options.jitter) && options.jitter >= 0, "jitter must be finite and >= 0 texels");
  requireOption(std::isfinite(options.read_noise) && options.read_noise >= 0, "read noise must be finite and >= 0");
  requireOption(std::isfinite(options.shot_noise) && options.shot_noise >= 0, "shot noise must be finite and >= 0");
}

void CameraBtf::loadView(int view, std::vector<Rgb>& out) const {
  std::vector<Rgb> clean;
  source_.loadView(view, clean);
  const int w = width(), h = height();
  const std::size_t texels = std::size_t(w) * std::size_t(h);
  const BtfDirectionSet& set = source_.directions();
  const int lights = set.lightCount(view);
  if (clean.size() != texels * std::size_t(lights))
    throw Error(source_.name() + ": view " + std::to_string(view) + " has the wrong number of values");
  // One stream per (view, light) image: its index among all of the set's pairs (view * 81 + light on
  // the 81-direction set).
  std::uint64_t first_pair = 0;
  for (int v = 0; v < view; ++v) first_pair += std::uint64_t(set.lightCount(v));
  out.resize(clean.size());
  const CameraOptions& o = options_;
  const float read_var = (o.read_noise * o.white) * (o.read_noise * o.white);
  const float shot_gain = o.shot_noise * o.shot_noise * o.white;
  const Srgb8& srgb = Srgb8::instance();
  tbb::parallel_for(0, lights, [&](int light) {
    Rng rng(o.seed, first_pair + std::uint64_t(light));
    const Rgb* src = clean.data() + std::size_t(light) * texels;
    Rgb* dst = out.data() + std::size_t(light) * texels;
    const float dx = o.jitter * (2.0f * rng.uniform() - 1.0f), dy = o.jitter * (2.0f * rng.uniform() - 1.0f);
    NormalDeviates normal(rng);
    const float fx = dx - std::floor(dx), fy = dy - std::floor(dy);
    const int ox = int(std::floor(dx)), oy = int(std::floor(dy));
    auto at = [&](int x, int y) {
      x = ((x % w) + w) % w;
      y = ((y % h) + h) % h;
      return src[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int sx = x + ox, sy = y + oy;
        Rgb v = o.jitter > 0 ? at(sx, sy) * ((1 - fx) * (1 - fy)) + at(sx + 1, sy) * (fx * (1 - fy)) +
                                   at(sx, sy + 1) * ((1 - fx) * fy) + at(sx + 1, sy + 1) * (fx * fy)
                             : at(x, y);
        for (int c = 0; c < 3; ++c) {
          float value = v[c];
          const float variance = read_var + shot_gain * std::max(value, 0.0f);
          if (variance > 0) value += std::sqrt(variance) * normal.next();
          value = std::clamp(value, 0.0f, o.white);
          if (o.quantize) value = srgb.decode(srgb.encode(value / o.white)) * o.white;
          v[c] = value;
        }
        dst[std::size_t(y) * std::size_t(w) + std::size_t(x)] = v;
      }
  });
}

}  // namespace btf::synthetic
