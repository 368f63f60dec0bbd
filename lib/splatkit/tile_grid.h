// tile_grid: the square tiles splat-tile cuts a survey into, and the halo of each.
//
// Tile (i, j) of side S holds the points with i*S <= x < (i+1)*S and j*S <= y < (j+1)*S (file
// coordinates; z is not cut): the grid is anchored at the origin, so that tiles of the same size
// cut from different runs or inputs line up. A tile's halo holds the points of other tiles within
// H of its square in plan (x, y): every point within 3-D distance H of one of the tile's points is
// in the tile or in its halo.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace splatkit {

struct TileKey {
  int64_t i = 0, j = 0;
  friend bool operator==(const TileKey&, const TileKey&) = default;
  friend auto operator<=>(const TileKey&, const TileKey&) = default;
};

// The tile of (x, y); size > 0. Coordinates must be finite.
TileKey tile_of(double x, double y, double size);

// Appends to `out` the tiles other than tile_of(x, y) whose square lies within `halo` (>= 0) of
// (x, y), in (i, j) order.
void halo_tiles(double x, double y, double size, double halo, std::vector<TileKey>& out);

// "tile_<i>_<j>" (e.g. tile_-3_12): the file name stem of a tile.
std::string tile_name(const TileKey& key);

}  // namespace splatkit
