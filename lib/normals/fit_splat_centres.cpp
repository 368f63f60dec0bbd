#include "normals/fit_splat_centres.h"

#include <cmath>
#include <vector>

namespace splatkit {

double fit_splat_centres(const SpatialIndex& index, std::span<Vec3f> positions,
                         std::span<const Vec3f> normals, std::size_t k) {
  const std::size_t n = positions.size();
  std::vector<float> offsets(n, 0.0f);
  index.for_each_knn_block(k, [&](std::span<const uint32_t> queries,
                                  std::span<const uint32_t> indices, std::span<const float>) {
    for (std::size_t r = 0; r < queries.size(); ++r) {
      const uint32_t i = queries[r];
      const Vec3f& c = positions[i];
      const Vec3f& ni = normals[i];
      double sum = 0;
      std::size_t count = 0;
      for (uint32_t j : indices.subspan(r * k, k)) {
        if (j == SpatialIndex::kNone || std::fabs(dot(normals[j], ni)) < kSameSheetCos) continue;
        sum += dot(positions[j] - c, ni);
        ++count;
      }
      offsets[i] = count == 0 ? 0.0f : static_cast<float>(sum / static_cast<double>(count));
    }
  });
  double shift = 0;
  for (std::size_t i = 0; i < n; ++i) {
    positions[i] += normals[i] * offsets[i];
    shift += std::fabs(offsets[i]);
  }
  return n == 0 ? 0.0 : shift / static_cast<double>(n);
}

}  // namespace splatkit
