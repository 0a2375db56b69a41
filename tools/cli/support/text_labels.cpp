#include "text_labels.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <string>

#include "btf/core/error.h"

namespace btf::cli {
namespace {

constexpr const char* kFontName = "DejaVuSans";

OIIO::ROI textBox(std::string_view text, int font_size) {
  const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(std::string(text), font_size, kFontName);
  if (!box.defined())
    throw Error(std::string("cannot load the font ") + kFontName + " for plot labels (Debian package fonts-dejavu-core)");
  return box;
}

// The text's coverage (0..1, antialiased) in a one-channel buffer just large enough for it.
OIIO::ImageBuf coverageMask(std::string_view text, int font_size) {
  const OIIO::ROI box = textBox(text, font_size);
  OIIO::ImageBuf mask(OIIO::ImageSpec(box.width(), box.height(), 1, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::zero(mask);
  const float white = 1.0f;
  // render_text places the baseline at y; the box's ybegin is the (negative) ascent above it.
  if (!OIIO::ImageBufAlgo::render_text(mask, -box.xbegin, -box.ybegin, std::string(text), font_size, kFontName,
                                       {&white, 1}))
    throw Error("cannot render plot label '" + std::string(text) + "': " + mask.geterror());
  return mask;
}

// Blends `color` over the image with the mask's coverage; `vertical` turns the mask 90 degrees
// counter-clockwise, so the text reads from bottom to top.
void blend(Image& image, int x0, int y0, const OIIO::ImageBuf& mask, const Rgb& color, bool vertical) {
  const int w = mask.spec().width, h = mask.spec().height;
  for (int my = 0; my < h; ++my)
    for (int mx = 0; mx < w; ++mx) {
      float a = 0;
      mask.getpixel(mx, my, &a, 1);
      if (a <= 0) continue;
      const int x = vertical ? x0 + my : x0 + mx;
      const int y = vertical ? y0 + (w - 1 - mx) : y0 + my;
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = image.at(x, y, c) * (1 - a) + color[c] * a;
    }
}

}  // namespace

int textWidth(std::string_view text, int font_size) { return textBox(text, font_size).width(); }
int textHeight(int font_size) { return textBox("Xg", font_size).height(); }

void drawText(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size) {
  blend(image, x, y, coverageMask(text, font_size), color, false);
}

void drawTextVertical(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size) {
  blend(image, x, y, coverageMask(text, font_size), color, true);
}

}  // namespace btf::cli
