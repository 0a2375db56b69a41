// The canvas of the btf command's figures (plot, sample): one palette, light ink on dark paper,
// and filled rectangles clipped at the borders, so that the figures look alike.
#pragma once

#include <algorithm>

#include "btf/core/rgb.h"
#include "btf/io/image.h"

namespace btf::cli {

inline constexpr Rgb kInk(0.92f), kPaper(0.12f);

inline void fillRect(Image& image, int x0, int y0, int w, int h, const Rgb& color) {
  for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = color[c];
}

}  // namespace btf::cli
