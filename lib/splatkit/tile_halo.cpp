#include "splatkit/tile_halo.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "splatkit/spatial_index.h"

namespace splatkit {

double tile_halo(std::span<const Vec3f> positions) {
  const std::size_t n = positions.size();
  if (n < kTileHaloRow) return 0;
  const SpatialIndex index(positions);
  const std::size_t samples = std::min(n, kTileHaloSample);
  std::vector<float> reach(samples);
  tbb::parallel_for(std::size_t{0}, samples, [&](std::size_t s) {
    std::vector<uint32_t> row(kTileHaloRow);
    std::vector<float> sq(kTileHaloRow);
    const std::size_t i = s * n / samples;  // evenly over the input's order
    const std::size_t got = index.knn(positions[i], kTileHaloRow, row.data(), sq.data());
    reach[s] = got == kTileHaloRow ? std::sqrt(sq[kTileHaloRow - 1]) : 0.0f;
  });
  const auto q =
      reach.begin() +
      static_cast<std::ptrdiff_t>(std::floor(kTileHaloQuantile * static_cast<double>(samples - 1)));
  std::nth_element(reach.begin(), q, reach.end());
  return 2.0 * static_cast<double>(*q);
}

}  // namespace splatkit
