#include "normals/widen_flat_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>

namespace splatkit {

float flatness_ratio(const PcaNormal& pca) {
  return pca.eigenvalues[1] > 0 ? static_cast<float>(pca.eigenvalues[0] / pca.eigenvalues[1]) : 0;
}

std::size_t widen_flat_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::span<const uint32_t> points, std::size_t k,
                               std::span<Vec3f> normals, std::span<float> sq_reach) {
  const std::size_t wide = std::min(2 * k, positions.size());
  std::atomic<std::size_t> replaced{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& range) {
    std::vector<uint32_t> row(wide, SpatialIndex::kNone);
    std::vector<float> sq(wide, std::numeric_limits<float>::infinity());
    std::size_t here = 0;
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const uint32_t i = points[p];
      const std::size_t got = index.knn(positions[i], wide, row.data(), sq.data());
      std::fill(row.begin() + got, row.end(), SpatialIndex::kNone);
      if (!sq_reach.empty())
        sq_reach[i] = std::max(sq_reach[i], got == wide && wide > 0
                                                ? sq[wide - 1]
                                                : std::numeric_limits<float>::infinity());
      const PcaNormal pca = neighborhood_pca(positions, row);
      if (pca.degenerate) continue;
      normals[i] = pca.normal;
      ++here;
    }
    replaced += here;
  });
  return replaced;
}

}  // namespace splatkit
