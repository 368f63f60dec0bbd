#include "splatkit/tile_grid.h"

#include <algorithm>
#include <cmath>

namespace splatkit {

TileKey tile_of(double x, double y, double size) {
  return {static_cast<int64_t>(std::floor(x / size)), static_cast<int64_t>(std::floor(y / size))};
}

void halo_tiles(double x, double y, double size, double halo, std::vector<TileKey>& out) {
  const TileKey own = tile_of(x, y, size);
  const TileKey lo = tile_of(x - halo, y - halo, size), hi = tile_of(x + halo, y + halo, size);
  for (int64_t i = lo.i; i <= hi.i; ++i)
    for (int64_t j = lo.j; j <= hi.j; ++j) {
      if (i == own.i && j == own.j) continue;
      // The distance from (x, y) to the square [i*S, (i+1)*S] x [j*S, (j+1)*S].
      const double x0 = static_cast<double>(i) * size, y0 = static_cast<double>(j) * size;
      const double dx = std::max({x0 - x, 0.0, x - (x0 + size)});
      const double dy = std::max({y0 - y, 0.0, y - (y0 + size)});
      if (dx * dx + dy * dy <= halo * halo) out.push_back({i, j});
    }
}

std::string tile_name(const TileKey& key) {
  return "tile_" + std::to_string(key.i) + "_" + std::to_string(key.j);
}

}  // namespace splatkit
