#include "btf/io/btf_quality.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/image.h"
#include "btf_compare_pass.h"

namespace btf {
namespace {

// Past this many values a median or percentile is taken on a subsample: 64 MiB of floats.
constexpr std::size_t kMaxSampledValues = std::size_t(1) << 24;

bool isPrime(std::size_t n) {
  if (n < 2) return false;
  for (std::size_t d = 2; d * d <= n; ++d)
    if (n % d == 0) return false;
  return true;
}

// The stride of the deterministic subsample of `count` values: 1 when all fit, else the smallest
// prime other than 3 that leaves at most kMaxSampledValues (coprime with the 3 channels, so the
// pick does not lock onto one of them).
std::size_t subsampleStride(std::size_t count) {
  if (count <= kMaxSampledValues) return 1;
  std::size_t k = (count + kMaxSampledValues - 1) / kMaxSampledValues;
  while (!isPrime(k) || k == 3) ++k;
  return k;
}

// Keeps every stride-th of the values offered to it, counting across calls (streaming order).
class Subsample {
 public:
  explicit Subsample(std::size_t count) : stride_(subsampleStride(count)) {
    kept_.reserve(count / stride_ + 1);
  }
  void offer(float value) {
    if (index_++ == next_) {
      kept_.push_back(value);
      next_ += stride_;
    }
  }
  std::vector<float>& kept() { return kept_; }

 private:
  std::size_t stride_, index_ = 0, next_ = 0;
  std::vector<float> kept_;
};

std::string sizeText(const BtfSource& source) {
  return std::to_string(source.width()) + " x " + std::to_string(source.height()) + " texels";
}

bool positiveFinite(float value) { return std::isfinite(value) && value > 0; }

// The white of compareBtfSsim when none is given: the reference's own, else the 99.9th percentile
// (nearest rank) of its channel values, else (percentile 0) their maximum.
float defaultWhite(const BtfSource& reference) {
  if (const std::optional<float> white = reference.white()) {
    if (!positiveFinite(*white))
      throw Error(reference.name() + ": its white (" + std::to_string(*white) + ") is not a finite value > 0");
    return *white;
  }
  Subsample sample(reference.entryCount() * 3);
  float largest = 0;
  forEachView(reference, "finding the white of " + reference.name(), [&](int, const std::vector<Rgb>& values) {
    for (const Rgb& rgb : values)
      for (int c = 0; c < 3; ++c) {
        sample.offer(rgb[c]);
        largest = std::max(largest, rgb[c]);
      }
  });
  std::vector<float>& kept = sample.kept();
  const auto rank = std::size_t(std::ceil(0.999 * double(kept.size())));
  const auto nth = kept.begin() + std::ptrdiff_t(std::max<std::size_t>(rank, 1) - 1);
  std::nth_element(kept.begin(), nth, kept.end());
  const float white = *nth > 0 ? *nth : largest;
  if (!positiveFinite(white))
    throw Error(reference.name() + ": cannot choose a white for SSIM: the BTF has no finite value > 0 (give one)");
  return white;
}

// The colour as a camera shows it: divided by white, clipped, sRGB-encoded.
Rgb displayed(const Rgb& rgb, float inv_white) {
  Rgb encoded;
  for (int c = 0; c < 3; ++c) encoded[c] = srgbEncode(std::clamp(rgb[c] * inv_white, 0.0f, 1.0f));
  return encoded;
}
float luma(const Rgb& encoded) { return 0.2126f * encoded[0] + 0.7152f * encoded[1] + 0.0722f * encoded[2]; }

// Buffers of one image comparison, reused by a thread across images: two luma images and the
// summed-area tables of x, y, x^2, y^2 and x y, (width + 1) x (height + 1) with a zero first row
// and column.
struct SsimScratch {
  std::vector<float> x, y;
  std::vector<double> sx, sy, sxx, syy, sxy;
};

constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;

// Mean SSIM over the window positions of one image (lumas already in scratch.x, scratch.y).
double imageSsim(SsimScratch& s, int width, int height, int window) {
  const std::size_t stride = std::size_t(width) + 1, table = stride * (std::size_t(height) + 1);
  for (std::vector<double>* t : {&s.sx, &s.sy, &s.sxx, &s.syy, &s.sxy}) t->assign(table, 0.0);
  for (int row = 0; row < height; ++row) {
    double rx = 0, ry = 0, rxx = 0, ryy = 0, rxy = 0;
    const std::size_t above = std::size_t(row) * stride, here = above + stride;
    for (int col = 0; col < width; ++col) {
      const std::size_t p = std::size_t(row) * std::size_t(width) + std::size_t(col);
      const double a = s.x[p], b = s.y[p];
      rx += a;
      ry += b;
      rxx += a * a;
      ryy += b * b;
      rxy += a * b;
      const std::size_t c = std::size_t(col) + 1;
      s.sx[here + c] = s.sx[above + c] + rx;
      s.sy[here + c] = s.sy[above + c] + ry;
      s.sxx[here + c] = s.sxx[above + c] + rxx;
      s.syy[here + c] = s.syy[above + c] + ryy;
      s.sxy[here + c] = s.sxy[above + c] + rxy;
    }
  }
  const int wx = std::min(window, width), wy = std::min(window, height);
  const double inv_n = 1.0 / (double(wx) * double(wy));
  double sum = 0;
  for (int y0 = 0; y0 + wy <= height; ++y0) {
    const std::size_t top = std::size_t(y0) * stride, bottom = std::size_t(y0 + wy) * stride;
    for (int x0 = 0; x0 + wx <= width; ++x0) {
      const std::size_t a = top + std::size_t(x0), b = top + std::size_t(x0 + wx);
      const std::size_t c = bottom + std::size_t(x0), d = bottom + std::size_t(x0 + wx);
      const auto box = [&](const std::vector<double>& t) { return (t[d] - t[b] - t[c] + t[a]) * inv_n; };
      const double mx = box(s.sx), my = box(s.sy);
      const double vx = box(s.sxx) - mx * mx, vy = box(s.syy) - my * my, cxy = box(s.sxy) - mx * my;
      sum += ((2.0 * mx * my + kC1) * (2.0 * cxy + kC2)) / ((mx * mx + my * my + kC1) * (vx + vy + kC2));
    }
  }
  return sum / (double(width - wx + 1) * double(height - wy + 1));
}

// The running sums of compareBtfSsim, view by view (images of a view in parallel, summed in image
// order, so the result does not depend on the thread count).
class SsimSums {
 public:
  SsimSums(const BtfSource& reference, float white, int window)
      : width_(reference.width()), height_(reference.height()), pixels_(reference.texelCount()), window_(window),
        inv_white_(1.0f / white) {
    stats_.white = white;
  }

  void add(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
    const int lights = int(a.size() / pixels_);  // this view's
    image_ssim_.assign(std::size_t(lights), 0.0);
    image_error2_.assign(std::size_t(lights), 0.0);
    image_reference2_.assign(std::size_t(lights), 0.0);
    tbb::parallel_for(0, lights, [&](int light) {
      SsimScratch& s = scratch_.local();
      s.x.resize(pixels_);
      s.y.resize(pixels_);
      const std::size_t first = std::size_t(light) * pixels_;
      double e2 = 0, r2 = 0;
      for (std::size_t p = 0; p < pixels_; ++p) {
        const Rgb x = displayed(a[first + p], inv_white_), y = displayed(b[first + p], inv_white_);
        s.x[p] = luma(x);
        s.y[p] = luma(y);
        for (int c = 0; c < 3; ++c) {
          const double d = double(y[c]) - double(x[c]);
          e2 += d * d;
          r2 += double(x[c]) * double(x[c]);
        }
      }
      image_error2_[std::size_t(light)] = e2;
      image_reference2_[std::size_t(light)] = r2;
      image_ssim_[std::size_t(light)] = imageSsim(s, width_, height_, window_);
    });
    // In image order, whatever the threads did.
    for (std::size_t i = 0; i < image_ssim_.size(); ++i) {
      sum_ += image_ssim_[i];
      stats_.min_image_ssim = std::min(stats_.min_image_ssim, image_ssim_[i]);
      error2_ += image_error2_[i];
      reference2_ += image_reference2_[i];
    }
    stats_.images += image_ssim_.size();
  }

  BtfSsimStats stats() const {
    BtfSsimStats s = stats_;
    s.mean_ssim = sum_ / double(s.images);
    s.rel_rmse_display = reference2_ > 0 ? std::sqrt(error2_ / reference2_) : (error2_ > 0 ? HUGE_VAL : 0.0);
    return s;
  }

 private:
  int width_, height_;
  std::size_t pixels_;
  int window_;
  float inv_white_;
  tbb::enumerable_thread_specific<SsimScratch> scratch_;
  // Per image of the current view: SSIM, squared differences and squares of the displayed reference.
  std::vector<double> image_ssim_, image_error2_, image_reference2_;
  double sum_ = 0, error2_ = 0, reference2_ = 0;
  BtfSsimStats stats_;
};

// The checks of compareBtfSsim before reading anything, and the white it uses.
float ssimWhite(const BtfSource& reference, const BtfSource& test, const BtfSsimOptions& options) {
  const std::string what = "cannot compare " + test.name() + " with " + reference.name();
  if (reference.width() != test.width() || reference.height() != test.height())
    throw Error(what + ": " + test.name() + " has " + sizeText(test) + ", " + reference.name() + " has " +
                sizeText(reference));
  for (const int v : reference.views().views()) test.views().require(v, what);
  if (options.window < 1) throw Error(what + ": the SSIM window (" + std::to_string(options.window) + ") must be >= 1");
  if (options.white && !positiveFinite(*options.white))
    throw Error(what + ": the white (" + std::to_string(*options.white) + ") must be a finite value > 0");
  return options.white ? *options.white : defaultWhite(reference);
}

constexpr int kFirstNoiseRing = 1;  // ring 0 is a single light: it has no azimuthal neighbours

// The running state of estimateBtfNoiseFloor, view by view: the squares of the source's values
// and the (subsampled) residuals against the azimuthal neighbours.
class NoiseSums {
 public:
  explicit NoiseSums(const BtfSource& source)
      : texels_(source.texelCount()),
        residuals_(texels_ * std::size_t(source.views().count()) * std::size_t(lightsWithNeighbours()) * 3) {}

  void add(const std::vector<Rgb>& values) {
    for (const Rgb& rgb : values)
      for (int c = 0; c < 3; ++c) squares_ += double(rgb[c]) * double(rgb[c]);
    for (int ring = kFirstNoiseRing; ring < kBtfRingCount; ++ring) {
      const int n = btfRingSize(ring);
      for (int azimuth = 0; azimuth < n; ++azimuth) {
        const Rgb* here = values.data() + std::size_t(btfDirectionIndex(ring, azimuth)) * texels_;
        const Rgb* before = values.data() + std::size_t(btfDirectionIndex(ring, (azimuth + n - 1) % n)) * texels_;
        const Rgb* after = values.data() + std::size_t(btfDirectionIndex(ring, (azimuth + 1) % n)) * texels_;
        for (std::size_t t = 0; t < texels_; ++t)
          for (int c = 0; c < 3; ++c) residuals_.offer(std::abs(here[t][c] - 0.5f * (before[t][c] + after[t][c])));
      }
    }
  }

  // Takes the median in place: call once, after the last view.
  BtfNoiseFloor floor(const BtfSource& source) {
    const double rms = std::sqrt(squares_ / (double(source.entryCount()) * 3.0));
    if (!(rms > 0)) throw Error(source.name() + ": the BTF is all zero; its relative noise level is undefined");
    std::vector<float>& kept = residuals_.kept();
    const auto middle = kept.begin() + std::ptrdiff_t(kept.size() / 2);
    std::nth_element(kept.begin(), middle, kept.end());
    BtfNoiseFloor f;
    f.residuals = kept.size();
    f.rms_noise = 1.4826 * double(*middle) / std::sqrt(1.5);
    f.rel_rmse = f.rms_noise / rms;
    return f;
  }

 private:
  static int lightsWithNeighbours() {
    int lights = 0;
    for (int ring = kFirstNoiseRing; ring < kBtfRingCount; ++ring) lights += btfRingSize(ring);
    return lights;
  }

  std::size_t texels_;
  double squares_ = 0;
  Subsample residuals_;
};

}  // namespace

BtfSsimStats compareBtfSsim(const BtfSource& reference, const BtfSource& test, const BtfSsimOptions& options) {
  SsimSums sums(reference, ssimWhite(reference, test, options), options.window);
  forEachViewPair(reference, test, "SSIM of " + test.name(),
                  [&](const std::vector<Rgb>& a, const std::vector<Rgb>& b) { sums.add(a, b); });
  return sums.stats();
}

BtfNoiseFloor estimateBtfNoiseFloor(const BtfSource& source) {
  NoiseSums sums(source);
  forEachView(source, "estimating the noise of " + source.name(),
              [&](int, const std::vector<Rgb>& values) { sums.add(values); });
  return sums.floor(source);
}

BtfQuality compareBtfQuality(const BtfSource& reference, const BtfSource& test, const BtfSsimOptions& options) {
  requireComparableBtfs(reference, test);
  BtfErrorSums errors;
  SsimSums ssim(reference, ssimWhite(reference, test, options), options.window);
  NoiseSums noise(reference);
  forEachViewPair(reference, test, "measuring " + test.name() + " against " + reference.name(),
                  [&](const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
                    errors.add(a, b);
                    ssim.add(a, b);
                    noise.add(a);
                  });
  return {errors.stats(reference), ssim.stats(), noise.floor(reference)};
}

}  // namespace btf
