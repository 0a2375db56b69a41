// What a camera does to a BTF on its way into images: a gantry never registers its images to the
// texel (each (view, light) image lands a fraction of a texel off), the sensor adds noise, and the
// file stores 8-bit sRGB codes that clip at white. Measured BTFs carry all three; a synthetic BTF
// without them is noise-free, so its texels have near-twins a measured one never has
// (docs/design-notes.md#synthetic-btfs-and-the-camera). CameraBtf applies them to any BtfSource,
// view by view.
//
// Per (view, light) image, in this order:
//   1. registration: the image is resampled (bilinearly, wrapping at the borders as the periodic
//      patterns do) at an offset drawn uniformly from [-jitter, jitter]^2 texels;
//   2. sensor noise, per channel and texel: Gaussian with variance
//        (read_noise * white)^2 + shot_noise^2 * white * max(v, 0)
//      (read noise, and photon shot noise whose std is shot_noise * white at v = white);
//   3. clipping to [0, white] and, with quantize, rounding to the 8-bit sRGB code (IEC 61966-2-1)
//      and decoding back, so the values are those a reader of the camera's files gets.
// Random numbers are counter-based (core/rng.h): one stream per (view, light) image, so the result
// does not depend on the thread count or on which views are loaded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf::synthetic {

struct CameraOptions {
  float white = 1.0f;       // the value of the largest code (> 0)
  float jitter = 0.0f;      // registration error, texels (>= 0)
  float read_noise = 0.0f;  // std of the additive noise, in units of white (>= 0)
  float shot_noise = 0.0f;  // std of the shot noise at white, in units of white (>= 0)
  bool quantize = false;    // store 8-bit sRGB codes
  std::uint64_t seed = 1;
};

// An auto-exposure: the 99th percentile of the channel values of the source's first view held, so
// that the brightest 1 % clip as in a measured sample's images (1 when that percentile is 0).
float exposureWhite(const BtfSource& source);

// The camera the print pattern is calibrated with against the measured WALLPAPER slice
// (docs/design-notes.md#a-generator-calibrated-to-real-data): the registration error, read noise
// and shot noise that measuredCameraOptions sets (camera_btf.cpp, the one place they are stated),
// 8-bit sRGB codes, white by exposureWhite(source).
CameraOptions measuredCameraOptions(const BtfSource& source, std::uint64_t seed);

class CameraBtf final : public BtfSource {
 public:
  // Throws btf::Error for an option out of range. `source` must outlive the camera.
  CameraBtf(const BtfSource& source, const CameraOptions& options);

  int width() const override { return source_.width(); }
  int height() const override { return source_.height(); }
  const BtfViewSet& views() const override { return source_.views(); }
  std::optional<float> white() const override { return options_.white; }
  std::string name() const override { return name_; }
  void loadView(int view, std::vector<Rgb>& out) const override;

 private:
  const BtfSource& source_;
  CameraOptions options_;
  std::string name_;
};

}  // namespace btf::synthetic
