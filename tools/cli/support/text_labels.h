// Text labels on plot images, rendered by libbtf (OpenImageIO with FreeType) and Debian's DejaVu Sans
// (package fonts-dejavu-core). OpenImageIO 2.4 renders ASCII only, so labels spell Greek names.
#pragma once

#include <string_view>

#include "btf/core/rgb.h"
#include "btf/io/image.h"

namespace btf::cli {

// Size in pixels of `text` at the given font size.
int textWidth(std::string_view text, int font_size);
int textHeight(int font_size);

// Draws text with its top-left corner at (x, y) into a 3-channel image; clipped at the borders.
// Throws Error when the font cannot be loaded.
void drawText(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size);
// Draws text rotated 90 degrees counter-clockwise (reading bottom to top), top-left at (x, y).
void drawTextVertical(Image& image, int x, int y, std::string_view text, const Rgb& color, int font_size);

}  // namespace btf::cli
