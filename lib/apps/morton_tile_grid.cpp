#include "apps/morton_tile_grid.h"

#include <algorithm>

namespace splatkit::apps {

TileGridFrame morton_tile_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                               double max_size) {
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  TileGridFrame g{lo[0], lo[1], max_size};
  if (!(extent > 0)) return g;
  // MortonFrame: coordinate t = (x − lo) · (2^21 − 1) / extent, a cell of level k 2^(21−k) of t.
  double cell = extent / 2097151.0 * 2097152.0;
  for (int k = 0; k < 21 && cell > max_size; ++k) cell /= 2;
  g.size = cell;
  return g;
}

}  // namespace splatkit::apps
