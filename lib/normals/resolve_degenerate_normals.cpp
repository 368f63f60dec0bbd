#include "normals/resolve_degenerate_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "normals/neighborhood_pca.h"
#include "normals/splat_radius.h"

namespace splatkit {

Vec3f fallback_normal(const Vec3f& axis, double largest) {
  if (!(largest > 0)) return {0, 0, 1};
  const Vec3f a = normalized(axis);
  const Vec3f up = std::fabs(a.z) > 0.9999f ? Vec3f{1, 0, 0} : Vec3f{0, 0, 1};
  const Vec3f n = normalized(up - a * dot(up, a));
  return squared_norm(n) > 0 ? n : Vec3f{0, 0, 1};
}

// The whole cloud's PCA: when it is degenerate every neighbourhood is, so the per-point search
// (up to kMaxWideK neighbours each) would only burn time.
PcaNormal whole_cloud_pca(std::span<const Vec3f> positions) {
  std::vector<uint32_t> all(positions.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
  return neighborhood_pca(positions, all);
}

DegenerateStats resolve_degenerate_normals(const SpatialIndex& index,
                                           std::span<const Vec3f> positions,
                                           std::span<const uint32_t> points, std::size_t k,
                                           std::size_t radius_k, std::span<Vec3f> normals,
                                           std::span<float> radii, const WholeCloud* whole,
                                           std::span<float> sq_reach,
                                           std::span<uint32_t> bridges) {
  DegenerateStats stats;
  std::fill(bridges.begin(), bridges.end(), kNoBridge);
  if (points.empty()) return stats;
  const std::size_t n = whole ? whole->size : positions.size();
  const PcaNormal global = whole ? whole->pca : whole_cloud_pca(positions);
  const std::size_t limit = std::min(n, std::max(kMaxWideK, 4 * k));
  if (global.degenerate) {
    const Vec3f normal = fallback_normal(global.axis, global.eigenvalues[2]);
    for (uint32_t i : points) normals[i] = normal;
    stats.unresolved = points.size();
    return stats;
  }
  stats.unresolved = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), 16), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t unresolved) {
        std::vector<uint32_t> ids;
        std::vector<float> d2;
        for (std::size_t p = range.begin(); p < range.end(); ++p) {
          const uint32_t i = points[p];
          PcaNormal pca;
          std::size_t wide = k, got = 0;
          Vec3f thread_axis{0, 0, 0};  // the direction of the point's own k nearest
          // A thread grows to 16k points (scan lines up to ~30 spacings apart), a degenerate set
          // to the limit: a wire is a thread at every scale, and 1024-point queries for each of
          // its points would only cost time.
          do {
            wide = std::min(wide * 4, limit);
            ids.resize(wide);
            d2.resize(wide);
            got = index.knn(positions[i], wide, ids.data(), d2.data());
            if (wide == std::min(k * 4, limit))
              thread_axis =
                  neighborhood_pca(positions, std::span<const uint32_t>(ids.data(), std::min(k, got)))
                      .axis;
            pca = neighborhood_pca(positions, std::span<const uint32_t>(ids.data(), got));
          } while (wide < limit &&
                   (pca.degenerate ||
                    (wide < 16 * k &&
                     is_thread(pca, positions, i, std::span<const uint32_t>(ids.data(), got)))));
          if (!bridges.empty()) {
            // The nearest point off the thread (more than 45° from its direction): an edge to the
            // next scan line for the orientation's graph, whose k nearest would all be on this one.
            bridges[p] = kNoBridge;
            for (std::size_t s = 0; s < got; ++s) {
              const Vec3f d = positions[ids[s]] - positions[i];
              const float along = dot(d, thread_axis);
              if (d2[s] > 0 && 2 * along * along < squared_norm(d)) {
                bridges[p] = ids[s];
                break;
              }
            }
          }
          if (radii[i] == 0.0f) radii[i] = splat_radius(d2, radius_k);
          if (!sq_reach.empty())
            sq_reach[i] = got == wide ? d2[wide - 1] : std::numeric_limits<float>::infinity();
          if (pca.degenerate) {
            normals[i] = fallback_normal(pca.axis, pca.eigenvalues[2]);
            ++unresolved;
          } else {
            normals[i] = pca.normal;
          }
        }
        return unresolved;
      },
      std::plus<>());
  stats.resolved = points.size() - stats.unresolved;
  return stats;
}

}  // namespace splatkit
