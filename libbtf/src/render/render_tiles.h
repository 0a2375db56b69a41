// Image tiles rendered in parallel (TBB), with progress per finished tile. Private to render/.
#pragma once

#include <tbb/parallel_for.h>

#include <cstdint>
#include <string>

#include "btf/core/progress.h"

namespace btf::render {

struct TileRange {
  int x0, y0, x1, y1;
};

// Calls body(tile) for every tile of a width x height image, in parallel, in any order; the body
// must write only its own pixels.
template <class Body>
void forEachTile(int width, int height, int tile_size, const std::string& task, const Body& body) {
  const int tiles_x = (width + tile_size - 1) / tile_size, tiles_y = (height + tile_size - 1) / tile_size;
  const int tiles = tiles_x * tiles_y;
  Progress progress(task, std::uint64_t(tiles));
  // One tile per task: tiles differ widely in cost (sky against glossy geometry), so TBB's work
  // stealing balances them better than large blocks would.
  tbb::parallel_for(0, tiles, 1, [&](int t) {
    const int tx = t % tiles_x, ty = t / tiles_x;
    body(TileRange{tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
                   std::min(height, (ty + 1) * tile_size)});
    progress.advance();
  });
}

}  // namespace btf::render
