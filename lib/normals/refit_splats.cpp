#include "normals/refit_splats.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "normals/pca_normals_and_radii.h"

namespace splatkit {

void refit_splats(const SpatialIndex& index, SplatCloud& cloud, const NormalOptions& o,
                  std::span<const uint32_t> points, std::size_t k, std::span<float> sq_reach) {
  k = std::min(k, cloud.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& range) {
    std::vector<uint32_t> row(k, SpatialIndex::kNone);
    std::vector<float> sq(k, std::numeric_limits<float>::infinity());
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const uint32_t i = points[p];
      const std::size_t got = index.knn(cloud.positions[i], k, row.data(), sq.data());
      std::fill(row.begin() + got, row.end(), SpatialIndex::kNone);
      std::fill(sq.begin() + got, sq.end(), std::numeric_limits<float>::infinity());
      fit_splat(cloud, o, i, row, sq, cloud.normals);
      if (!sq_reach.empty()) sq_reach[i] = sq[k - 1];
    }
  });
}

}  // namespace splatkit
