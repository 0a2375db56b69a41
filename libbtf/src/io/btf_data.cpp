#include "btf/io/btf_data.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf_compare_pass.h"

namespace btf {
namespace {

const BtfViewSet& allViews() {
  static const BtfViewSet all;
  return all;
}

}  // namespace

const BtfViewSet& BtfSource::views() const { return allViews(); }
const BtfViewSet& BtfLookup::lookupViews() const { return allViews(); }

std::size_t BtfSource::entryCount() const {
  std::size_t pairs = 0;
  for (const int v : views().views()) pairs += std::size_t(directions().lightCount(v));
  return texelCount() * pairs;
}

BtfData::BtfData(int width, int height, std::string name, BtfViewSet views)
    : width_(width), height_(height), name_(std::move(name)), views_(std::move(views)) {
  if (width < 1 || height < 1)
    throw Error("BTF size " + std::to_string(width) + " x " + std::to_string(height) + " is invalid: both must be >= 1");
  std::size_t total = 0;
  for (const int v : views_.views()) {
    view_offsets_.push_back(total);
    total += viewValueCount(v);
  }
  values_.assign(total, Rgb());
}

void BtfLookup::checkSampleIndices(std::span<const BtfSampleIndex> samples, std::size_t out_size) const {
  if (samples.size() != out_size) throw Error("BTF values: spans of different sizes");
  const int w = lookupWidth(), h = lookupHeight();
  const BtfViewSet& held = lookupViews();
  const BtfDirectionSet& set = held.directions();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const BtfSampleIndex& s = samples[i];
    if (s.x < 0 || s.x >= w || s.y < 0 || s.y >= h || s.view < 0 || s.view >= set.viewCount() || s.light < 0 ||
        s.light >= set.lightCount(s.view))
      throw Error("BTF values: sample " + std::to_string(i) + " (x " + std::to_string(s.x) + ", y " + std::to_string(s.y) +
                  ", view " + std::to_string(s.view) + ", light " + std::to_string(s.light) + ") is outside the " +
                  std::to_string(w) + " x " + std::to_string(h) + " texels and " + set.describe());
    if (!held.contains(s.view)) held.require(s.view, "BTF values: sample " + std::to_string(i));
  }
}

void BtfLookup::values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const {
  checkSampleIndices(samples, out.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    out[i] = value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
}

void BtfData::loadView(int v, std::vector<Rgb>& out) const {
  views_.require(v, name_);
  out.assign(view(v), view(v) + viewValueCount(v));
}

BtfData BtfData::copyOf(const BtfSource& source) {
  BtfData data(source.width(), source.height(), source.name(), source.views());
  data.setWhite(source.white());
  forEachView(source, "reading " + source.name(),
              [&](int v, const std::vector<Rgb>& values) { std::copy(values.begin(), values.end(), data.view(v)); });
  return data;
}

void requireViewSize(const BtfSource& source, int view, std::size_t size) {
  const std::size_t expected = source.viewValueCount(view);
  if (size != expected)
    throw Error(source.name() + ": view " + std::to_string(view) + " has " + std::to_string(size) +
                " values, expected " + std::to_string(expected));
}

void requireComparableBtfs(const BtfSource& reference, const BtfSource& test) {
  if (reference.width() != test.width() || reference.height() != test.height())
    throw Error("cannot compare " + test.name() + " (" + std::to_string(test.width()) + " x " +
                std::to_string(test.height()) + " texels) with " + reference.name() + " (" +
                std::to_string(reference.width()) + " x " + std::to_string(reference.height()) + ")");
  if (!(reference.directions() == test.directions()))
    throw Error("cannot compare " + test.name() + " (" + test.directions().describe() + ") with " + reference.name() +
                " (" + reference.directions().describe() + "): they are measured on different direction sets");
  for (const int v : reference.views().views()) test.views().require(v, "cannot compare " + test.name() + " with " + reference.name());
}

void BtfErrorSums::add(const std::vector<Rgb>& reference, const std::vector<Rgb>& test) {
  for (std::size_t i = 0; i < reference.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double r = reference[i][c], d = double(test[i][c]) - r;
      squared_error_ += d * d;
      squared_reference_ += r * r;
      max_reference_ = std::max(max_reference_, r);
    }
    const double y = reference[i].luminance(), dy = double(test[i].luminance()) - y;
    squared_luminance_error_ += dy * dy;
    squared_luminance_ += y * y;
  }
}

BtfErrorStats BtfErrorSums::stats(const BtfSource& reference) const {
  BtfErrorStats s;
  s.entries = reference.entryCount();
  const double n = double(s.entries) * 3.0;
  if (!(squared_reference_ > 0)) throw Error(reference.name() + ": the reference BTF is all zero; relative errors are undefined");
  s.rmse = std::sqrt(squared_error_ / n);
  s.reference_rms = std::sqrt(squared_reference_ / n);
  s.reference_max = max_reference_;
  s.rel_rmse = s.rmse / s.reference_rms;
  s.luminance_rel_rmse = squared_luminance_ > 0 ? std::sqrt(squared_luminance_error_ / squared_luminance_) : 0.0;
  s.psnr_db = s.rmse > 0 ? 20.0 * std::log10(max_reference_ / s.rmse) : std::numeric_limits<double>::infinity();
  return s;
}

void forEachView(const BtfSource& source, const std::string& label,
                 const std::function<void(int, const std::vector<Rgb>&)>& add) {
  std::vector<Rgb> values;
  Progress progress(label, std::uint64_t(source.views().count()));
  for (const int v : source.views().views()) {
    source.loadView(v, values);
    requireViewSize(source, v, values.size());
    add(v, values);
    progress.advance();
  }
}

void forEachViewPair(const BtfSource& reference, const BtfSource& test, const std::string& label,
                     const std::function<void(const std::vector<Rgb>&, const std::vector<Rgb>&)>& add) {
  std::vector<Rgb> a, b;
  Progress progress(label, std::uint64_t(reference.views().count()));
  for (const int v : reference.views().views()) {
    reference.loadView(v, a);
    requireViewSize(reference, v, a.size());
    test.loadView(v, b);
    requireViewSize(test, v, b.size());
    add(a, b);
    progress.advance();
  }
}

BtfErrorStats compareBtf(const BtfSource& reference, const BtfSource& test) {
  requireComparableBtfs(reference, test);
  BtfErrorSums sums;
  forEachViewPair(reference, test, "comparing " + test.name(),
                  [&](const std::vector<Rgb>& a, const std::vector<Rgb>& b) { sums.add(a, b); });
  return sums.stats(reference);
}

}  // namespace btf
