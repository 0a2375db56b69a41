// A built-in 5x7 pixel font for labels on plots, so `btf plot` needs no font files.
// Covers A-Z (lower case is drawn as upper case), 0-9 and . , - _ = ( ) * / : + ; other
// characters are drawn as '?'.
#pragma once

#include <string_view>

#include "btf/core/rgb.h"
#include "btf/io/image.h"

namespace btf::cli {

// Width in pixels of `text` drawn at `scale` (each glyph cell is 6 x 8 units including spacing).
int textWidth(std::string_view text, int scale);
inline int textHeight(int scale) { return 7 * scale; }

// Draws text with its top-left corner at (x, y) into a 3-channel image; clipped at the borders.
void drawText(Image& image, int x, int y, std::string_view text, const Rgb& color, int scale = 2);
// Draws text rotated 90 degrees counter-clockwise (reading bottom to top), top-left at (x, y).
void drawTextVertical(Image& image, int x, int y, std::string_view text, const Rgb& color, int scale = 2);

}  // namespace btf::cli
