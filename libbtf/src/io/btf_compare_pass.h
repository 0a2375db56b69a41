// What the measures of one BTF against another share (compareBtf in btf_data.cpp, the measures of
// btf_quality.cpp): the checks before reading, the passes over a source's views (alone, or the
// reference's views of both, each loaded once), and compareBtf's running sums, so that compareBtfQuality can feed every
// measure from a single pass instead of loading the views once per measure.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

// A source whose views have the wrong length would make the measures overrun their buffers.
void requireViewSize(const BtfSource& source, int view, std::size_t size);

// The checks compareBtf makes before reading anything: equal sizes and every view of the reference
// held by the test.
void requireComparableBtfs(const BtfSource& reference, const BtfSource& test);

// Loads each of the source's views in turn (its views() order, size checked) and hands it to add;
// progress on a terminal as `label`.
void forEachView(const BtfSource& source, const std::string& label,
                 const std::function<void(int view, const std::vector<Rgb>& values)>& add);

// Loads each of the reference's views from both sources, in the reference's order, and hands the
// two to add; progress on a terminal as `label`.
void forEachViewPair(const BtfSource& reference, const BtfSource& test, const std::string& label,
                     const std::function<void(const std::vector<Rgb>& reference, const std::vector<Rgb>& test)>& add);

class BtfErrorSums {
 public:
  // One view of the reference and the same view of the test, of equal length.
  void add(const std::vector<Rgb>& reference, const std::vector<Rgb>& test);
  // The errors over every view added; throws btf::Error naming the reference if it is all zero.
  BtfErrorStats stats(const BtfSource& reference) const;

 private:
  double squared_error_ = 0, squared_reference_ = 0, max_reference_ = 0;
  double squared_luminance_error_ = 0, squared_luminance_ = 0;
};

}  // namespace btf
