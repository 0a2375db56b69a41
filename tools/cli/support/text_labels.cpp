#include "text_labels.h"

#include <optional>
#include <string>
#include <utility>

#include "btf/core/error.h"

namespace btf::cli {
namespace {

constexpr const char* kFontName = "DejaVuSans";

// The text's coverage (0..1, antialiased) in a one-channel image just large enough for it.
Image coverageMask(std::string_view text, int font_size) {
  std::optional<Image> mask = renderTextMask(text, font_size, kFontName);
  if (!mask)
    throw Error(std::string("cannot load the font ") + kFontName + " for plot labels (Debian package fonts-dejavu-core)");
  return std::move(*mask);
}

// Blends `color` over the image with the mask's coverage; `vertical` turns the mask 90 degrees
// counter-clockwise, so the text reads from bottom to top.
void blend(Image& image, int x0, int y0, const Image& mask, const Rgb& color, bool vertical) {
  const int w = mask.width, h = mask.height;
  for (int my = 0; my < h; ++my)
    for (int mx = 0; mx < w; ++mx) {
      const float a = mask.at(mx, my, 0);
      if (a <= 0) continue;
      const int x = vertical ? x0 + my : x0 + mx;
      const int y = vertical ? y0 + (w - 1 - mx) : y0 + my;
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = image.at(x, y, c) * (1 - a) + color[c] * a;
    }
}

}  // namespace

int textWidth(std::string_view text, int font_size) { return coverageMask(text, font_size).width; }
int textHeight(int font_size) { return coverageMask("Xg", font_size).height; }

void drawText(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size) {
  blend(image, x, y, coverageMask(text, font_size), color, false);
}

void drawTextVertical(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size) {
  blend(image, x, y, coverageMask(text, font_size), color, true);
}

}  // namespace btf::cli
