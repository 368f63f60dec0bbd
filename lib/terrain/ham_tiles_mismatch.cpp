#include "terrain/ham_tiles_mismatch.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace splatkit::terrain {

std::string ham_tiles_mismatch(const TerrainMap& map, const HamTiles& tiles) {
  if (map.width != tiles.width || map.height != tiles.height || tiles.tile < 1) return {};
  std::vector<float> top(tiles.size(), -INFINITY);
  for (int64_t y = 0; y < map.height; ++y) {
    float* row_top = top.data() + (y / tiles.tile) * tiles.tiles_x;
    for (int64_t x = 0; x < map.width; ++x) {
      float& t = row_top[x / tiles.tile];
      t = std::max(t, map.at(x, y));
    }
  }
  for (std::size_t t = 0; t < top.size(); ++t) {
    // build-ham scales in float, the viewer's map in double: a few units in the last place.
    const double a = top[t], b = tiles.h_max[t];
    if (std::fabs(a - b) <= 1e-6 * std::max({1.0, std::fabs(a), std::fabs(b)})) continue;
    std::ostringstream what;
    what << "tile (" << t % std::size_t(tiles.tiles_x) << ", " << t / std::size_t(tiles.tiles_x)
         << ") holds a highest height of " << b << ", the heightmap's is " << a;
    return what.str();
  }
  return {};
}

}  // namespace splatkit::terrain
