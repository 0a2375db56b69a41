// Comparing a rendered image with a reference: the measures of the renderer literature, under the
// project's names (docs/design-notes.md#measures), and a heat map of where the two differ.
//
// Both images are compared over their colour channels: the first 3 of an image with 3 or more
// (a 4th channel, alpha, is ignored), or the single grey channel of an image with 1 or 2 (grey,
// grey + alpha). With t the test value and r the reference value of one channel of one pixel, and
// means taken over all pixels and compared channels (N = width * height * channels values):
//
//   relmse   = mean[(t - r)^2 / (r^2 + 1e-2)]   relative MSE; the 1e-2 keeps near-black
//                                                reference pixels from dominating
//   rel_rmse = sqrt(mean[(t - r)^2]) / sqrt(mean[r^2])   (RMSE / RMS of the reference; 0 when the
//                                                images are equal, +inf when only the reference is 0)
//   psnr_db  = 10 log10(peak^2 / mean[(t - r)^2]) = 20 log10(peak / RMSE), peak = max |r| (the
//              reference's largest value); +inf when the images are equal, -inf when they differ
//              and the reference is all 0
//   max_abs  = max |t - r|
//
// Sums are taken in double.
#pragma once

#include <string>

#include "btf/core/rgb.h"
#include "btf/io/image.h"

namespace btf::render {

struct ImageComparison {
  double relmse = 0;
  double rel_rmse = 0;
  double psnr_db = 0;
  double max_abs = 0;
  int width = 0, height = 0;
  int channels = 0;  // compared per pixel: 3 (RGB) or 1 (grey)
};

// Throws btf::Error when the sizes differ or one image is grey and the other colour (naming both,
// e.g. "test image is 64x48 RGB, reference image is 64x32 RGB"), when an image is empty, or when
// a compared value is NaN or infinite (naming the image and the first such pixel, x = column,
// y = row from the top). test_name and reference_name stand for the images in messages (the CLI
// passes file names).
ImageComparison compareImages(const Image& test, const Image& reference, const std::string& test_name = "test image",
                              const std::string& reference_name = "reference image");

// Per-pixel relative error e = mean over the compared channels of |t - r| / (|r| + 0.01), mapped
// through the viridis colour map with e = 0 at its dark-purple bottom and e >= scale at its yellow
// top: a 3-channel image of sRGB-encoded values in [0, 1], ready for an 8-bit PNG as it is.
// Same checks as compareImages; throws btf::Error for a scale that is not finite and > 0.
Image errorHeatMap(const Image& test, const Image& reference, double scale,
                   const std::string& test_name = "test image", const std::string& reference_name = "reference image");

// The viridis colour map at x in [0, 1] (clamped), as sRGB-encoded values in [0, 1]: 16 control
// points interpolated linearly. The control points are entries 0, 17, 34, ..., 255 of the
// 256-entry viridis table of matplotlib (van der Walt and Smith, BIDS colormaps, CC0), which
// lists sRGB values.
Rgb viridis(double x);

}  // namespace btf::render
