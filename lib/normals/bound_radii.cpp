#include "normals/bound_radii.h"

#include <algorithm>

namespace splatkit {

std::vector<float> neighbour_median_radii(const SpatialIndex& index,
                                          const std::vector<float>& radii, std::size_t k,
                                          std::span<float> sq_reach) {
  std::vector<float> median(radii.size(), 0.0f);
  if (radii.size() < 2) return median;
  k = std::min(k, radii.size() - 1);
  index.for_each_knn_block(k + 1, [&](std::span<const uint32_t> queries,
                                      std::span<const uint32_t> rows,
                                      std::span<const float> sq_dists) {
    std::vector<float> r(k);
    for (std::size_t q = 0; q < queries.size(); ++q) {
      for (std::size_t j = 0; j < k; ++j) r[j] = radii[rows[q * (k + 1) + 1 + j]];
      // Lower median: for an even k the smaller middle value.
      std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>((k - 1) / 2), r.end());
      median[queries[q]] = r[(k - 1) / 2];
      if (!sq_reach.empty()) sq_reach[queries[q]] = sq_dists[q * (k + 1) + k];
    }
  });
  return median;
}

BoundRadiiResult bound_radii(const SpatialIndex& index, std::vector<float>& radii,
                             std::vector<float>& minor_radii, float ratio, std::size_t k,
                             std::size_t max_passes) {
  return bound_radii(
      [&](const std::vector<float>& r) { return neighbour_median_radii(index, r, k); }, radii,
      minor_radii, ratio, max_passes);
}

BoundRadiiResult bound_radii(
    const std::function<std::vector<float>(const std::vector<float>&)>& medians,
    std::vector<float>& radii, std::vector<float>& minor_radii, float ratio,
    std::size_t max_passes) {
  BoundRadiiResult result;
  std::vector<uint8_t> capped(radii.size(), 0);
  bool settled = false;  // a pass capped nothing: every radius is within its bound
  while (!settled && result.passes < max_passes) {
    const std::vector<float> median = medians(radii);
    ++result.passes;
    std::size_t now = 0;
    for (std::size_t i = 0; i < radii.size(); ++i) {
      const float cap = ratio * median[i];
      if (!(radii[i] > cap) || !(cap > 0)) continue;
      if (!minor_radii.empty()) minor_radii[i] *= cap / radii[i];
      radii[i] = cap;
      capped[i] = 1;
      ++now;
    }
    settled = now == 0;
  }
  result.capped = static_cast<std::size_t>(std::count(capped.begin(), capped.end(), 1));
  // A pass that capped nothing found every radius within ratio × the medians it computed, and
  // the radii have not changed since: none is over (no kNN pass needed to count them).
  if (settled) return result;
  const std::vector<float> median = medians(radii);
  for (std::size_t i = 0; i < radii.size(); ++i)
    result.over += median[i] > 0 && radii[i] > ratio * median[i];
  return result;
}

}  // namespace splatkit
