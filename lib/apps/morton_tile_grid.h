// morton_tile_grid: a splat-tile grid whose tiles are columns of the Morton cells of a survey's
// bounding cube (splatkit/morton_order.h), the cells build-spt's octree over the whole survey is
// made of (spt/build_spt_tree.h), so that each tile's octree holds whole cells of that tree and
// the tiles' .spt files merge into the whole build's list (docs/design/tiles.md, "Merged
// level-of-detail files").
#pragma once

#include <array>

namespace splatkit::apps {

// Tile (i, j) holds x0 + i*size <= x < x0 + (i+1)*size, y0 + j*size <= y < y0 + (j+1)*size.
struct TileGridFrame {
  double x0 = 0, y0 = 0, size = 1;
};

// The grid anchored at the box's lower corner (lo, hi: the survey's box in file coordinates, lo
// <= hi) whose side is the side of the largest Morton cell (the cube's side, the box's largest
// extent, over 2^k: MortonFrame's 2^21 − 1 steps of extent / (2^21 − 1) each, so cells of 2^(21−k)
// steps) that is at most `max_size` (> 0), and no finer than the cube's 2^21 steps. A box of no
// extent gives max_size. Cuts fall on the cells' borders up to the rounding of the coordinates.
TileGridFrame morton_tile_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                               double max_size);

}  // namespace splatkit::apps
