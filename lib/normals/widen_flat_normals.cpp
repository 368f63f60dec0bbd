#include "normals/widen_flat_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

#include "normals/layer_cuts.h"
#include "splatkit/pca_normal.h"

namespace splatkit {

namespace {

constexpr int kFaceIterations = 4;

Vec3f to_vec3f(const std::array<double, 3>& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// The row's points about `origin` summed per part: the covariance of a part about its own centroid
// is S - s s^T / count.
struct Sums {
  double s[3] = {0, 0, 0}, c[6] = {0, 0, 0, 0, 0, 0};
  double count = 0;
  void add(const Vec3f& d) {
    const double x = d.x, y = d.y, z = d.z;
    s[0] += x, s[1] += y, s[2] += z;
    c[0] += x * x, c[1] += x * y, c[2] += x * z, c[3] += y * y, c[4] += y * z, c[5] += z * z;
    count += 1;
  }
  void scatter(std::array<double, 6>& to) const {
    if (count == 0) return;
    const double inv = 1.0 / count;
    to[0] += c[0] - s[0] * s[0] * inv, to[1] += c[1] - s[0] * s[1] * inv;
    to[2] += c[2] - s[0] * s[2] * inv, to[3] += c[3] - s[1] * s[1] * inv;
    to[4] += c[4] - s[1] * s[2] * inv, to[5] += c[5] - s[2] * s[2] * inv;
  }
  float offset(const Vec3f& n) const {
    return count > 0 ? static_cast<float>((n.x * s[0] + n.y * s[1] + n.z * s[2]) / count) : 0.0f;
  }
};

// Two parallel faces fitted to a row that holds both faces of a thin wall: the row's offsets along
// the normal are split where the two parts lie furthest apart in pooled deviations (as
// layer_cuts.h), and the normal is refitted to both parts about their own centroids (the pooled
// within-face covariance), a few times from the row's PCA normal. Returns the model; `normal`
// becomes the two faces' normal when the row splits (else it and the one-plane model stay).
FaceModel two_faces(std::span<const Vec3f> positions, std::span<const uint32_t> row,
                    const Vec3f& origin, Vec3f& normal, double pca_variance,
                    std::vector<std::pair<float, uint32_t>>& off) {
  FaceModel model;
  Sums all;
  for (uint32_t j : row)
    if (j != SpatialIndex::kNone) all.add(positions[j] - origin);
  model.a = model.b = all.offset(normal);
  model.variance = static_cast<float>(pca_variance / std::max(all.count, 1.0));
  const std::size_t m = static_cast<std::size_t>(all.count);
  if (m < 8) return model;
  Vec3f n = normal;
  for (int iteration = 0; iteration < kFaceIterations; ++iteration) {
    off.clear();
    for (uint32_t j : row)
      if (j != SpatialIndex::kNone) off.push_back({dot(n, positions[j] - origin), j});
    std::sort(off.begin(), off.end());
    double total = 0, total2 = 0;
    for (const auto& o : off) total += o.first, total2 += double{o.first} * o.first;
    double below = 0, below2 = 0, best = 0;
    std::size_t split = 0;
    for (std::size_t s = 1; s + 3 <= m; ++s) {
      below += off[s - 1].first, below2 += double{off[s - 1].first} * off[s - 1].first;
      if (s < 3) continue;
      const double na = static_cast<double>(s), nb = static_cast<double>(m - s);
      const double ma = below / na, mb = (total - below) / nb;
      const double ss = (below2 - na * ma * ma) + (total2 - below2 - nb * mb * mb);
      const double sd = std::sqrt(std::max(ss, 0.0) / static_cast<double>(m));
      const double gap = mb - ma;
      if (gap > best * sd) {
        best = sd > 0 ? gap / sd : std::numeric_limits<double>::infinity();
        split = s;
      }
    }
    if (split == 0 || !(best >= kLayerSeparation)) return model;
    Sums lo, hi;
    for (std::size_t q = 0; q < m; ++q)
      (q < split ? lo : hi).add(positions[off[q].second] - origin);
    std::array<double, 6> c{0, 0, 0, 0, 0, 0};
    lo.scatter(c);
    hi.scatter(c);
    const CovarianceEigen e = pca_normal(c);
    if (!(e.eigenvalues[2] > 0)) return model;
    n = to_vec3f(e.normal);
    if (iteration + 1 == kFaceIterations) {
      // Faces over each other, as layer_cuts.h asks: two levels side by side (a step, a recess)
      // are no wall.
      const float lo_along = lo.offset(n), hi_along = hi.offset(n);
      const Vec3f ca =
          Vec3f{static_cast<float>(lo.s[0] / lo.count), static_cast<float>(lo.s[1] / lo.count),
                static_cast<float>(lo.s[2] / lo.count)} -
          n * lo_along;
      const Vec3f cb =
          Vec3f{static_cast<float>(hi.s[0] / hi.count), static_cast<float>(hi.s[1] / hi.count),
                static_cast<float>(hi.s[2] / hi.count)} -
          n * hi_along;
      float radius2 = 0;
      for (uint32_t j : row)
        if (j != SpatialIndex::kNone)
          radius2 = std::max(radius2, squared_norm(positions[j] - origin));
      if (squared_norm(ca - cb) > kLayerOverlap * kLayerOverlap * radius2) return model;
      // About their own centroids the two parts must show a plane, as a k-row on one face does:
      // the two faces of a crease or a wedge, split so, still do not.
      if (!(e.eigenvalues[0] <= kWidenRatio * e.eigenvalues[1])) return model;
      normal = canonical_sign(n);
      model.a = lo.offset(normal);
      model.b = hi.offset(normal);
      model.variance = static_cast<float>(std::max(e.eigenvalues[0], 0.0) / all.count);
    }
  }
  return model;
}

}  // namespace

float flatness_ratio(const PcaNormal& pca) {
  return pca.eigenvalues[1] > 0 ? static_cast<float>(pca.eigenvalues[0] / pca.eigenvalues[1]) : 0;
}

std::size_t widen_flat_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::span<const uint32_t> points, std::size_t k,
                               std::span<Vec3f> normals, std::span<float> sq_reach,
                               std::span<FaceModel> models) {
  const std::size_t wide = std::min(2 * k, positions.size());
  std::atomic<std::size_t> replaced{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& range) {
    std::vector<uint32_t> row(wide, SpatialIndex::kNone);
    std::vector<float> sq(wide, std::numeric_limits<float>::infinity());
    std::vector<std::pair<float, uint32_t>> off;
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
      if (!models.empty())
        models[i] = two_faces(positions, row, positions[i], normals[i], pca.eigenvalues[0], off);
      ++here;
    }
    replaced += here;
  });
  return replaced;
}

}  // namespace splatkit
