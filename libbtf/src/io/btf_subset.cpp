#include "btf/io/btf_subset.h"

#include <algorithm>

#include "btf/core/error.h"

namespace btf {

BtfSubset::BtfSubset(const BtfSource& source, const BtfRect& rect, BtfViewSet views)
    : source_(source), rect_(rect), views_(std::move(views)) {
  if (rect.width < 1 || rect.height < 1 || rect.x < 0 || rect.y < 0 || rect.x + rect.width > source.width() ||
      rect.y + rect.height > source.height())
    throw Error(source.name() + ": the texel rectangle (" + std::to_string(rect.x) + ", " + std::to_string(rect.y) +
                ") + " + std::to_string(rect.width) + " x " + std::to_string(rect.height) + " is not inside its " +
                std::to_string(source.width()) + " x " + std::to_string(source.height()) + " texels");
  if (!(views_.directions() == source.directions()))
    throw Error("a subset of " + source.name() + ": its views are on " + views_.directions().describe() +
                ", the BTF's on " + source.directions().describe());
  for (const int v : views_.views()) source.views().require(v, "a subset of " + source.name());
  name_ = source.name();
  if (rect.width != source.width() || rect.height != source.height())
    name_ += " [" + std::to_string(rect.width) + "x" + std::to_string(rect.height) + " at " + std::to_string(rect.x) +
             "," + std::to_string(rect.y) + "]";
  if (!(views_ == source.views())) name_ += " (" + views_.describe() + ")";
}

BtfRect BtfSubset::centredRect(const BtfSource& source, int width, int height) {
  const int w = std::clamp(width, 1, source.width()), h = std::clamp(height, 1, source.height());
  return {(source.width() - w) / 2, (source.height() - h) / 2, w, h};
}

void BtfSubset::loadView(int view, std::vector<Rgb>& out) const {
  views_.require(view, name_);
  std::vector<Rgb> full;
  source_.loadView(view, full);
  const std::size_t sw = std::size_t(source_.width()), sh = std::size_t(source_.height());
  const int lights = source_.directions().lightCount(view);
  if (full.size() != std::size_t(lights) * sw * sh)
    throw Error(source_.name() + ": view " + std::to_string(view) + " has the wrong number of values");
  out.resize(std::size_t(lights) * texelCount());
  Rgb* dst = out.data();
  for (int light = 0; light < lights; ++light)
    for (int y = 0; y < rect_.height; ++y) {
      const Rgb* row = full.data() + (std::size_t(light) * sh + std::size_t(rect_.y + y)) * sw + std::size_t(rect_.x);
      dst = std::copy(row, row + rect_.width, dst);
    }
}

}  // namespace btf
