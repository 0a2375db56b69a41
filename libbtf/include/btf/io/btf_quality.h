// Two measures of a BTF's error beyond rel_rmse (docs/design-notes.md#measures): how different a
// compressed BTF *looks* from its reference (mean SSIM over its images), and how much error the
// data carries anyway (its own measurement noise), below which a smaller compression error
// buys nothing.
//
// Both stream the sources view by view (loadView), in the order of the reference's views(), and
// look at no view the reference does not hold, so they work on partial BTFs as on complete ones.
// compareBtfQuality (at the end) gives both with compareBtf's errors in a single such pass.
#pragma once

#include <cstddef>
#include <optional>

#include "btf/io/btf_data.h"

namespace btf {

// ---------------------------------------------------------------------------------------------
// SSIM (Wang, Bovik, Sheikh and Simoncelli 2004, "Image quality assessment: from error visibility
// to structural similarity").
//
// A BTF is a stack of images, one per (view, light) pair: 81 per held view. Each image is compared
// as a camera would show it, because SSIM's constants and its sensitivity to structure assume
// display-referred values in [0, 1], not linear reflectance:
//   1. every channel divided by white and clipped to [0, 1] (what the camera saturates at:
//      detail above white was never measured, so it must not count);
//   2. sRGB-encoded with the IEC 61966-2-1 piecewise curve
//      (12.92 c for c <= 0.0031308, else 1.055 c^(1/2.4) - 0.055);
//   3. reduced to luma Y' = 0.2126 R' + 0.7152 G' + 0.0722 B' (Rec. 709 weights on encoded
//      values, as video luma is formed).
// On Y' of the reference (x) and the test (y), per window:
//   SSIM = (2 mu_x mu_y + C1) (2 sigma_xy + C2) / ((mu_x^2 + mu_y^2 + C1) (sigma_x^2 + sigma_y^2 + C2)),
//   C1 = (0.01)^2, C2 = (0.03)^2 (the paper's K1, K2 with dynamic range 1),
// with uniform weights: means, variances and the covariance are window averages (divided by the
// pixel count N, not N - 1, i.e. the paper's weighted form with equal weights). The windows are
// squares of `window` pixels sliding with stride 1 and lying fully inside the image; an image's
// SSIM is the mean over all window positions. A side of the image shorter than the window clips
// the window to that side, so an image smaller than the window in both directions (e.g. the 1 x 1
// images of a one-texel BTF made from a BRDF) is one window covering the whole image; for a
// 1 x 1 image that leaves the luminance term (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1) alone.
//
// Window sums come from summed-area tables in double, so an image costs O(pixels) whatever the
// window. Images of one view are compared in parallel (TBB, over lights); per-image results are
// summed in image order afterwards, so the result does not depend on the thread count.
struct BtfSsimOptions {
  // The linear value shown as white. Default: reference.white() (the value its encoding saturates
  // at), else the 99.9th percentile (nearest rank) of the reference's channel values over its
  // held views, so that a few specular peaks do not push every other texel into the dark end of
  // the curve (the largest value instead, if that percentile is 0: mostly black data). The
  // percentile costs an extra pass over the reference; past 2^24 values it is taken on a
  // deterministic subsample (every k-th value in streaming order, k fixed by the value count as
  // for the noise floor below).
  std::optional<float> white;
  // Side of the square windows in pixels (>= 1). Uniform 8 x 8 windows are the authors' earlier
  // choice (Wang and Bovik 2002); the 2004 paper's 11 x 11 Gaussian weights are not offered.
  int window = 8;
};

struct BtfSsimStats {
  double mean_ssim = 1;       // mean over all compared images of the per-image SSIM
  double min_image_ssim = 1;  // the worst image's SSIM: a few bad lights hide in the mean
  float white = 0;            // the white used (option, reference.white() or the percentile)
  // rel_rmse of the displayed colours (steps 1 and 2 above, all three channels): the error in the
  // 8-bit code values a camera or a viewer would show, where rel_rmse of the linear values weighs
  // the bright lights most. BTFBASE's published errors are of this kind.
  double rel_rmse_display = 0;
  std::size_t images = 0;     // compared images: held views of the reference x 81 lights
};

// Mean SSIM of test against reference over every (view, light) image of the reference's views.
// Throws btf::Error naming both BTFs when their sizes differ or the test lacks one of the
// reference's views, naming the reference when no white can be found (a reference that is all
// zero and no white given), and for a window < 1 or a given white that is not finite and > 0.
BtfSsimStats compareBtfSsim(const BtfSource& reference, const BtfSource& test, const BtfSsimOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Noise floor: the data's own noise level, as a rel_rmse (noise RMS / data RMS), comparable with
// compareBtf's rel_rmse. A compression error well below it is indistinguishable from measurement
// noise, so it is where pushing a codec further stops paying off.
//
// Method: measured BTFs are smooth over light azimuth at fixed elevation (neighbouring lights of a
// ring are 15 to 60 degrees apart), measurement noise is not. For every texel, held view, light
// ring with >= 6 azimuths (rings 1 .. 5) and channel, each light's value f_a gives the residual
//   r = f_a - (f_{a-1} + f_{a+1}) / 2          (azimuths cyclic within the ring),
// for which independent noise of standard deviation sigma gives var(r) = (1 + 1/4 + 1/4) sigma^2
// = 1.5 sigma^2. The signal's own curvature enters r too, large at specular peaks and shadow
// edges, so sigma comes from the median absolute residual (robust to a minority of such
// residuals) rather than from their RMS:
//   sigma = 1.4826 * median |r| / sqrt(1.5)    (1.4826 median |r| estimates a normal's std),
//   rel_rmse = sigma / RMS of all the source's values (every channel, held view and light).
// The median is over all residuals of the BTF; past 2^24 residuals it is taken over a
// deterministic subsample: every k-th residual in streaming order, k the smallest prime giving at
// most 2^24 and not 3 (coprime with the 3 channels, so the pick cycles through channels and
// lights instead of locking onto one).
//
// An estimate, and an overestimate where the data is not smooth over light azimuth (sharp
// highlights or shadow edges in more than a few lights of a ring, the coarse 60-degree steps of
// ring 1): the curvature then reads as noise. A codec stopped at such a floor may stop early.
// Throws btf::Error naming the source when it is all zero (no relative noise level exists).
struct BtfNoiseFloor {
  double rms_noise = 0;       // sigma, in the source's units
  double rel_rmse = 0;        // sigma / RMS of the source's values
  std::size_t residuals = 0;  // residuals the median was taken over (after any subsampling)
};
BtfNoiseFloor estimateBtfNoiseFloor(const BtfSource& source);

// ---------------------------------------------------------------------------------------------
// All three measures of a test BTF against its reference in one pass: compareBtf, compareBtfSsim
// (with options) and estimateBtfNoiseFloor of the reference, bit for bit as the three calls give
// them, but each view of the reference and of the test loaded once. The three calls in turn load
// the reference three times and the test twice, and a view of an image folder is 81 image files
// read from disk, a view of a .btfz 81 images decoded. Throws as the three calls do.
struct BtfQuality {
  BtfErrorStats error;
  BtfSsimStats ssim;
  BtfNoiseFloor noise;  // of the reference
};
BtfQuality compareBtfQuality(const BtfSource& reference, const BtfSource& test, const BtfSsimOptions& options = {});

}  // namespace btf
