// A part of another BTF: a rectangle of its texels and some of its views, streamed from it view by
// view. For analyses that cannot take a whole measured BTF (the compressibility analysis is
// quadratic in the texel count) and for comparing like with like (a synthetic BTF's θv = 0 view
// against a measured one-view slice).
#pragma once

#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

struct BtfRect {
  int x = 0, y = 0, width = 0, height = 0;
};

class BtfSubset final : public BtfSource {
 public:
  // The views must be held by `source` and the rectangle lie inside it (btf::Error naming the
  // source otherwise). `source` must outlive the subset.
  BtfSubset(const BtfSource& source, const BtfRect& rect, BtfViewSet views);
  // The rectangle of width x height texels at the centre of `source` (each side clamped to its size).
  static BtfRect centredRect(const BtfSource& source, int width, int height);

  int width() const override { return rect_.width; }
  int height() const override { return rect_.height; }
  const BtfViewSet& views() const override { return views_; }
  std::optional<float> white() const override { return source_.white(); }
  std::string name() const override { return name_; }
  void loadView(int view, std::vector<Rgb>& out) const override;

 private:
  const BtfSource& source_;
  BtfRect rect_;
  BtfViewSet views_;
  std::string name_;
};

}  // namespace btf
