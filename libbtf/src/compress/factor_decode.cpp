// FactorBtf's lookups and its decoded factors (factor_btf.h, factor_impl.h).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "btf/core/error.h"
#include "bonn_color.h"
#include "factor_impl.h"

namespace btf {

void FactorBtf::Impl::prepare() {
  k_total = k[0] + k[1] + k[2];
  offset = {0, k[0], k[0] + k[1]};
  const BtfDirectionSet& set = views.directions();
  view_pair.assign(std::size_t(set.viewCount()), -1);
  pairs = 0;
  for (const int v : views.views()) {
    view_pair[std::size_t(v)] = std::int64_t(pairs);
    pairs += std::size_t(set.lightCount(v));
  }
  const std::size_t T = texels(), K = std::size_t(k_total);
  coefficients.assign(T * K, 0.0f);
  basis.assign(pairs * K, 0.0f);
  for (std::size_t j = 0; j < K; ++j) {
    const std::int32_t* c = &coefficient_codes[j * T];
    for (std::size_t t = 0; t < T; ++t) coefficients[t * K + j] = float(double(c[t]) * coefficient_step);
    const std::int32_t* b = &basis_codes[j * pairs];
    for (std::size_t p = 0; p < pairs; ++p) basis[p * K + j] = float(double(b[p]) / basis_scale[j]);
  }
}

Rgb FactorBtf::Impl::decode(std::size_t t, std::size_t p) const {
  const std::size_t K = std::size_t(k_total);
  const float* c = &coefficients[t * K];
  const float* b = &basis[p * K];
  float a[3];
  for (int ch = 0; ch < 3; ++ch) {
    float sum = 0.0f;
    for (int j = offset[std::size_t(ch)], end = j + k[std::size_t(ch)]; j < end; ++j)
      sum += c[std::size_t(j)] * b[std::size_t(j)];
    a[ch] = sum;
  }
  return finish(a, p);
}

Rgb FactorBtf::Impl::finish(const float a[3], std::size_t p) const {
  if (color_model == FactorColorModel::LogLuminance) {
    const float scale = std::exp(pair_offset.empty() ? a[0] : a[0] + pair_offset[p]);  // Y + o
    const Rgb rgb = bonn::yuvToRgb(scale - log_offset, a[1] * scale, a[2] * scale);
    return Rgb(std::max(rgb.r, 0.0f), std::max(rgb.g, 0.0f), std::max(rgb.b, 0.0f));
  }
  const std::array<float, 9>& m = color;
  const float r = m[0] * a[0] + m[3] * a[1] + m[6] * a[2];
  const float g = m[1] * a[0] + m[4] * a[1] + m[7] * a[2];
  const float bl = m[2] * a[0] + m[5] * a[1] + m[8] * a[2];
  return Rgb(std::max(r, 0.0f), std::max(g, 0.0f), std::max(bl, 0.0f));
}

std::string factorColorModelName(FactorColorModel model) {
  return model == FactorColorModel::LogLuminance ? "log-luminance" : "linear";
}

FactorBtf::FactorBtf(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
int FactorBtf::width() const { return impl_->width; }
int FactorBtf::height() const { return impl_->height; }
std::string FactorBtf::name() const { return impl_->name; }
const BtfViewSet& FactorBtf::views() const { return impl_->views; }
const FactorOptions& FactorBtf::options() const { return impl_->options; }
const FactorStats& FactorBtf::stats() const { return impl_->stats; }
const std::array<float, 9>& FactorBtf::colorTransform() const { return impl_->color; }

Rgb FactorBtf::value(int x, int y, int view, int light) const {
  const Impl& m = *impl_;
  const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
  return m.decode(t, std::size_t(m.view_pair[std::size_t(view)]) + std::size_t(light));
}

// A block of texels at a time, its coefficients transposed (component-major) so that the inner
// loop runs over texels and vectorizes; each texel's sums still run over components in order from
// 0.0f, the arithmetic of decode(), so that loadView() and value() give the same bits.
void FactorBtf::loadView(int view, std::vector<Rgb>& out) const {
  const Impl& m = *impl_;
  m.views.require(view, m.name);
  const std::size_t T = m.texels(), lights = std::size_t(m.views.directions().lightCount(view));
  const std::size_t p0 = std::size_t(m.view_pair[std::size_t(view)]), K = std::size_t(m.k_total);
  constexpr std::size_t kBlock = 256;
  out.resize(T * lights);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, T, kBlock), [&](const tbb::blocked_range<std::size_t>& range) {
    const std::size_t t0 = range.begin(), n = range.size();
    std::vector<float> ct(K * n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < K; ++j) ct[j * n + i] = m.coefficients[(t0 + i) * K + j];
    std::vector<float> acc(3 * n);
    for (std::size_t l = 0; l < lights; ++l) {
      const float* b = &m.basis[(p0 + l) * K];
      for (int ch = 0; ch < 3; ++ch) {
        float* sum = &acc[std::size_t(ch) * n];
        std::fill(sum, sum + n, 0.0f);
        for (int j = m.offset[std::size_t(ch)], end = j + m.k[std::size_t(ch)]; j < end; ++j) {
          const float* c = &ct[std::size_t(j) * n];
          const float bj = b[std::size_t(j)];
          for (std::size_t i = 0; i < n; ++i) sum[i] += c[i] * bj;
        }
      }
      for (std::size_t i = 0; i < n; ++i) {
        const float a[3] = {acc[i], acc[n + i], acc[2 * n + i]};
        out[l * T + t0 + i] = m.finish(a, p0 + l);
      }
    }
  });
}

namespace {

std::uint32_t zigzag(std::int32_t v) { return (std::uint32_t(v) << 1) ^ std::uint32_t(v >> 31); }
std::int32_t unzigzag(std::uint32_t u) { return std::int32_t(u >> 1) ^ -std::int32_t(u & 1); }

void putVarint(std::uint32_t u, std::vector<std::byte>& out) {
  while (u >= 0x80) {
    out.push_back(std::byte((u & 0x7f) | 0x80));
    u >>= 7;
  }
  out.push_back(std::byte(u));
}

std::size_t varintBytes(std::uint32_t u) {
  std::size_t n = 1;
  while (u >= 0x80) {
    u >>= 7;
    ++n;
  }
  return n;
}

}  // namespace

void encodeFactorPlane(const std::int32_t* values, std::size_t count, std::vector<std::byte>& out) {
  // Differences are taken in 64 bits and kept only when each fits in 32 (codes are bounded well
  // inside int32 by the compressor, so they always do).
  std::size_t raw = 0, diff = 0;
  bool diff_fits = true;
  for (std::size_t i = 0; i < count; ++i) {
    raw += varintBytes(zigzag(values[i]));
    const std::int64_t d = std::int64_t(values[i]) - (i ? std::int64_t(values[i - 1]) : 0);
    if (d < INT32_MIN || d > INT32_MAX) diff_fits = false;
    else diff += varintBytes(zigzag(std::int32_t(d)));
  }
  const bool differences = diff_fits && diff < raw;
  out.push_back(std::byte(differences ? 1 : 0));
  for (std::size_t i = 0; i < count; ++i)
    putVarint(zigzag(differences ? std::int32_t(std::int64_t(values[i]) - (i ? std::int64_t(values[i - 1]) : 0))
                                 : values[i]),
              out);
}

void decodeFactorPlane(const std::byte*& in, const std::byte* end, std::int32_t* values, std::size_t count,
                       const std::filesystem::path& path, const std::string& what) {
  if (in == end) throw FileError(path, what + " is truncated (no plane flag)");
  const unsigned flag = unsigned(*in++);
  if (flag > 1) throw FileError(path, what + " has an unknown plane flag " + std::to_string(flag));
  std::int64_t previous = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t u = 0;
    for (int shift = 0;; shift += 7) {
      if (in == end) throw FileError(path, what + " is truncated (value " + std::to_string(i) + " of " + std::to_string(count) + ")");
      if (shift > 28) throw FileError(path, what + " holds an overlong value (value " + std::to_string(i) + ")");
      const unsigned byte = unsigned(*in++);
      if (shift == 28 && (byte & 0x70)) throw FileError(path, what + " holds a value beyond 32 bits (value " + std::to_string(i) + ")");
      u |= std::uint32_t(byte & 0x7f) << shift;
      if (!(byte & 0x80)) break;
    }
    std::int64_t v = unzigzag(u);
    if (flag == 1) v += previous;
    if (v < INT32_MIN || v > INT32_MAX) throw FileError(path, what + " holds a value beyond 32 bits (value " + std::to_string(i) + ")");
    values[i] = std::int32_t(v);
    previous = v;
  }
}

}  // namespace btf
