#include "normals/bound_radii.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace splatkit {

namespace {

// Relative margin on a squared distance: far above the rounding of two computations of it.
constexpr float kReachMargin = 1e-4f;

// The 4th smallest of 8 values: they are sorted by Batcher's odd-even merge sort network (19
// minima and maxima, no branches: which way a comparison of radii goes is a coin flip).
float fourth_of_eight(float v[8]) {
  auto sort2 = [&](int a, int b) {
    const float lo = std::min(v[a], v[b]), hi = std::max(v[a], v[b]);
    v[a] = lo;
    v[b] = hi;
  };
  sort2(0, 1), sort2(2, 3), sort2(4, 5), sort2(6, 7);
  sort2(0, 2), sort2(1, 3), sort2(4, 6), sort2(5, 7);
  sort2(1, 2), sort2(5, 6);
  sort2(0, 4), sort2(1, 5), sort2(2, 6), sort2(3, 7);
  sort2(2, 4), sort2(3, 5);
  sort2(1, 2), sort2(3, 4), sort2(5, 6);
  return v[3];
}

// The lower median (for an even k the smaller middle value) of the radii of the k points
// neighbours[0 .. k); r: room for k values.
float lower_median(const uint32_t* neighbours, std::size_t k, const std::vector<float>& radii,
                   std::vector<float>& r) {
  if (k == 8) {
    float v[8];
    for (int j = 0; j < 8; ++j) v[j] = radii[neighbours[j]];
    return fourth_of_eight(v);
  }
  for (std::size_t j = 0; j < k; ++j) r[j] = radii[neighbours[j]];
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>((k - 1) / 2), r.end());
  return r[(k - 1) / 2];
}

}  // namespace

std::vector<float> neighbour_median_radii(const SpatialIndex& index,
                                          const std::vector<float>& radii, std::size_t k,
                                          std::span<float> sq_reach) {
  std::vector<float> median(radii.size(), 0.0f);
  if (radii.size() < 2) return median;
  k = std::min(k, radii.size() - 1);
  index.for_each_knn_block(
      k + 1, [&](std::span<const uint32_t> queries, std::span<const uint32_t> rows,
                 std::span<const float> sq_dists) {
        std::vector<float> r(k);
        for (std::size_t q = 0; q < queries.size(); ++q) {
          median[queries[q]] = lower_median(rows.data() + q * (k + 1) + 1, k, radii, r);
          if (!sq_reach.empty()) sq_reach[queries[q]] = sq_dists[q * (k + 1) + k];
        }
      });
  return median;
}

std::vector<float> row_median_radii(std::span<const uint32_t> rows, std::size_t width,
                                    const std::vector<float>& radii, std::size_t k) {
  std::vector<float> median(radii.size(), 0.0f);
  k = std::min(k, width);
  if (k == 0) return median;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, radii.size(), 1 << 14), [&](const auto& b) {
    std::vector<float> r(k);
    for (std::size_t i = b.begin(); i < b.end(); ++i)
      median[i] = lower_median(rows.data() + i * width, k, radii, r);
  });
  return median;
}

BoundRadiiResult bound_wide_radii(const SpatialIndex& index, std::span<const Vec3f> positions,
                                  std::vector<float>& radii, std::vector<float>& minor_radii,
                                  float ratio, std::size_t k, std::size_t max_passes) {
  const std::size_t n = radii.size();
  if (n < 2) return {};
  k = std::min(k, n - 1);
  std::vector<float> sorted = radii;
  std::nth_element(sorted.begin(), sorted.begin() + n / 50, sorted.end());
  const float floor = ratio * sorted[n / 50];
  std::vector<uint32_t> candidates;
  for (std::size_t i = 0; i < n; ++i)
    if (radii[i] > floor) candidates.push_back(static_cast<uint32_t>(i));
  sorted = {};
  // The candidates' medians (0, no bound, for the others), each candidate's k-th neighbour's
  // squared distance, and the candidates' radii the medians were last found with.
  std::vector<float> median(n, 0.0f), reach(candidates.size()), found_with(candidates.size());
  std::vector<uint8_t> redo(candidates.size(), 1);
  auto median_of = [&](std::size_t c, const std::vector<float>& r, std::vector<uint32_t>& row,
                       std::vector<float>& d2, std::vector<float>& scratch) {
    const uint32_t i = candidates[c];
    const std::size_t found = index.knn(positions[i], k + 1, row.data(), d2.data());
    // The point itself is among the k + 1 nearest (first, or tied at distance 0).
    std::size_t m = 0;
    for (std::size_t j = 0; j < found && m < k; ++j)
      if (row[j] != i) row[m++] = row[j];
    median[i] = m > 0 ? lower_median(row.data(), m, r, scratch) : 0.0f;
    reach[c] = found == k + 1 ? d2[k] : std::numeric_limits<float>::infinity();
  };
  bool first = true;
  auto medians = [&](const std::vector<float>& r) {
    // Only candidates change between passes (a median of 0 caps nothing), and a median changes
    // only when one of its k points did: a candidate with no changed candidate within its k-th
    // neighbour's distance keeps its median. (The distances are compared with a margin: a
    // candidate found again needlessly gets the same median.)
    if (!first) {
      std::vector<Vec3f> changed;
      for (std::size_t c = 0; c < candidates.size(); ++c)
        if (r[candidates[c]] != found_with[c]) changed.push_back(positions[candidates[c]]);
      if (changed.empty()) return median;
      const SpatialIndex near(changed);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 1024), [&](auto& b) {
        for (std::size_t c = b.begin(); c < b.end(); ++c) {
          uint32_t id;
          float d2;
          redo[c] = near.knn(positions[candidates[c]], 1, &id, &d2) == 1 &&
                    d2 <= reach[c] * (1 + kReachMargin);
        }
      });
    }
    first = false;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256), [&](auto& b) {
      std::vector<uint32_t> row(k + 1);
      std::vector<float> d2(k + 1), scratch(k);
      for (std::size_t c = b.begin(); c < b.end(); ++c)
        if (redo[c]) median_of(c, r, row, d2, scratch);
    });
    for (std::size_t c = 0; c < candidates.size(); ++c) found_with[c] = r[candidates[c]];
    return median;
  };
  return bound_radii(medians, radii, minor_radii, ratio, max_passes);
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
